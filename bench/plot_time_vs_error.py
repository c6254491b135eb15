#!/usr/bin/env python3
"""Plots and tabulates bench_time_vs_error's CSV.

usage: python3 bench/plot_time_vs_error.py time_vs_error.csv OUT_DIR > table.md
Writes OUT_DIR/time_vs_error-<scene>.png (log-log rel. MSE against seconds) and prints a Markdown table per scene:
convergence slope of log rel_mse against log spp (about -1 for an unbiased estimator), time to reach rel_mse 1e-2
and 1e-3 (log-log interpolation; '-' if not reached), and efficiency 1 / (rel_mse x seconds) at the last point.
"""
import csv
import math
import os
import sys
from collections import defaultdict


def slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(max(y, 1e-300)) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    den = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / den if den > 0 else float("nan")


def time_to(target, secs, errs):
    for i in range(1, len(errs)):
        if errs[i] <= target < errs[i - 1] or (i == 1 and errs[0] <= target):
            if errs[0] <= target:
                return secs[0]
            t = (math.log(target) - math.log(errs[i - 1])) / (math.log(errs[i]) - math.log(errs[i - 1]))
            return math.exp(math.log(secs[i - 1]) + t * (math.log(secs[i]) - math.log(secs[i - 1])))
    return None


def main():
    path, out_dir = sys.argv[1], sys.argv[2]
    rows = defaultdict(list)
    for r in csv.DictReader(open(path)):
        rows[(r["scene"], r["strategy"], r["sampler"])].append(
            (int(r["spp"]), float(r["seconds"]), float(r["rmse"]), float(r["rel_mse"])))
    scenes = sorted({k[0] for k in rows})
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        plt = None
    os.makedirs(out_dir, exist_ok=True)
    for scene in scenes:
        keys = sorted(k for k in rows if k[0] == scene)
        print(f"\n#### {scene}\n")
        print("| strategy | sampler | slope | t(relMSE 1e-2) s | t(relMSE 1e-3) s | efficiency 1/(relMSE s) |")
        print("| --- | --- | ---: | ---: | ---: | ---: |")
        if plt:
            plt.figure(figsize=(6, 4.2))
        for k in keys:
            pts = sorted(rows[k])
            spp = [p[0] for p in pts]
            secs = [max(p[1], 1e-6) for p in pts]
            rel = [p[3] for p in pts]
            usable = [(s, e) for s, e in zip(spp, rel) if e > 0]
            sl = slope([u[0] for u in usable], [u[1] for u in usable]) if len(usable) > 2 else float("nan")
            t2, t3 = time_to(1e-2, secs, rel), time_to(1e-3, secs, rel)
            eff = 1.0 / (rel[-1] * secs[-1]) if rel[-1] > 0 else float("inf")
            fmt = lambda v: "-" if v is None else f"{v:.3g}"
            print(f"| {k[1]} | {k[2]} | {sl:.2f} | {fmt(t2)} | {fmt(t3)} | {eff:.4g} |")
            if plt:
                plt.loglog(secs, rel, marker="o", ms=3, label=f"{k[1]} / {k[2]}",
                           linestyle="-" if k[2] == "sobol" else "--")
        if plt:
            plt.xlabel("seconds")
            plt.ylabel("relative MSE")
            plt.title(scene)
            plt.grid(True, which="both", alpha=0.3)
            plt.legend(fontsize=7)
            plt.tight_layout()
            plt.savefig(os.path.join(out_dir, f"time_vs_error-{scene}.png"), dpi=90)
            plt.close()


if __name__ == "__main__":
    main()
