#!/usr/bin/env python3
"""Plots and tabulates the convergence sections of bench_time_vs_error (issue 12).

usage: python3 bench/plot_convergence.py STEM OUT_DIR [SPP_MAP.pfm ERROR_MAP.pfm] > tables.md
Reads STEM-estimator.csv and STEM-adaptive.csv; writes OUT_DIR/estimator-accuracy.png (est_rel_mse against the
true rel_mse, with the 1.5x band), OUT_DIR/adaptive-vs-uniform.png (rel_mse against seconds) and, given the two
PFM maps of an adaptive run, OUT_DIR/adaptive-maps.png.
"""
import csv
import os
import struct
import sys


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        ch = 3 if kind == b"PF" else 1
        fmt = ("<" if scale < 0 else ">") + "f" * (w * h * ch)
        data = struct.unpack(fmt, f.read(4 * w * h * ch))
    rows = [[data[(y * w + x) * ch] for x in range(w)] for y in range(h)]
    return rows[::-1]  # PFM stores rows bottom to top


def main():
    stem, out_dir = sys.argv[1], sys.argv[2]
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    os.makedirs(out_dir, exist_ok=True)

    est = list(csv.DictReader(open(stem + "-estimator.csv")))
    print("| scene | sampler | spp | rel_mse | est_rel_mse | est / rel | pair (ref-free) |")
    print("| --- | --- | ---: | ---: | ---: | ---: | ---: |")
    for r in est:
        print(f"| {r['scene']} | {r['sampler']} | {r['spp']} | {float(r['rel_mse']):.3g} | "
              f"{float(r['est_rel_mse']):.3g} | {float(r['ratio']):.2f} | {float(r['pair_rel_mse']):.3g} |")
    plt.figure(figsize=(5.5, 4.5))
    for key in sorted({(r["scene"], r["sampler"]) for r in est}):
        pts = [r for r in est if (r["scene"], r["sampler"]) == key]
        plt.loglog([float(r["rel_mse"]) for r in pts], [float(r["est_rel_mse"]) for r in pts],
                   marker="o" if key[1] == "sobol" else "s", ls="-" if key[1] == "sobol" else "--", ms=4,
                   label=f"{key[0]} / {key[1]}")
    lo = min(float(r["rel_mse"]) for r in est) / 2
    hi = max(float(r["rel_mse"]) for r in est) * 2
    plt.plot([lo, hi], [lo, hi], "k-", lw=0.8)
    plt.fill_between([lo, hi], [lo / 1.5, hi / 1.5], [lo * 1.5, hi * 1.5], color="grey", alpha=0.2, label="1.5x")
    plt.xlabel("true rel_mse (against the reference)")
    plt.ylabel("est_rel_mse (from the film alone)")
    plt.title("error estimate at 16, 64, 256 spp")
    plt.grid(True, which="both", alpha=0.3)
    plt.legend(fontsize=6)
    plt.tight_layout()
    plt.savefig(os.path.join(out_dir, "estimator-accuracy.png"), dpi=90)
    plt.close()

    ad = list(csv.DictReader(open(stem + "-adaptive.csv")))
    print()
    print("| mode | threshold | spp mean | spp max | seconds | rel_mse | est_rel_mse | converged |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for r in ad:
        print(f"| {r['mode']} | {r['threshold']} | {float(r['spp_mean']):.1f} | {r['spp_max']} | "
              f"{float(r['seconds']):.2f} | {float(r['rel_mse']):.3g} | {float(r['est_rel_mse']):.3g} | "
              f"{float(r['converged_fraction']):.2f} |")
    plt.figure(figsize=(5.5, 4.2))
    for mode, style in (("adaptive", "o-"), ("uniform", "s--"), ("uni-spp", "^:")):
        pts = [r for r in ad if r["mode"] == mode]
        plt.loglog([float(r["seconds"]) for r in pts], [float(r["rel_mse"]) for r in pts], style,
                   label={"uni-spp": "uniform, equal samples"}.get(mode, mode))
    for r in ad:
        if r["mode"] == "adaptive":
            plt.annotate(f"T={r['threshold']}", (float(r["seconds"]), float(r["rel_mse"])), fontsize=7)
    plt.xlabel("seconds")
    plt.ylabel("rel_mse against the reference")
    plt.title(f"adaptive vs uniform, {ad[0]['scene']}")
    plt.grid(True, which="both", alpha=0.3)
    plt.legend(fontsize=7)
    plt.tight_layout()
    plt.savefig(os.path.join(out_dir, "adaptive-vs-uniform.png"), dpi=90)
    plt.close()

    if len(sys.argv) >= 5:
        spp, err = read_pfm(sys.argv[3]), read_pfm(sys.argv[4])
        fig, axes = plt.subplots(1, 2, figsize=(9, 4))
        im = axes[0].imshow(spp, cmap="viridis")
        axes[0].set_title("samples per pixel")
        fig.colorbar(im, ax=axes[0], fraction=0.046)
        im = axes[1].imshow(err, cmap="inferno")
        axes[1].set_title("relative standard error")
        fig.colorbar(im, ax=axes[1], fraction=0.046)
        for a in axes:
            a.axis("off")
        plt.tight_layout()
        plt.savefig(os.path.join(out_dir, "adaptive-maps.png"), dpi=90)
        plt.close()


if __name__ == "__main__":
    main()
