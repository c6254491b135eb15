"""Groups a `perf report --stdio --no-children --sort symbol` of a ptview frame (bench/profile_frame.sh): prints every
symbol above 0.5% and the share of ray casting (issue 11, target 5), writes a CSV of all symbols.

usage: profile_frame.py REPORT.txt OUT.csv
"""
import csv
import re
import sys

# Ray casting: the BVH traversal and the entry points a ray goes through (src/accel). Anything else is shading,
# sampling or bookkeeping.
RAY_CASTING = re.compile(
    r"\btraverse<|\bintersect_bvh8\b|\boccluded_bvh8\b|\bintersect_closest\b|\bintersect_any\b|"
    r"\btrace_spheres\b|\bintersect_sphere|\bintersect_tri4\b|\boccluded_tri4\b|\bintersect_node8")
LINE = re.compile(r"^\s*([0-9.]+)%\s+\[[.k]\]\s+(.*?)(?:\s+-)*\s*$")  # perf may add "-" columns


def short(symbol):
    """The symbol without its argument list and namespaces, for the table."""
    depth, out = 0, []
    for ch in symbol.replace("(anonymous namespace)::", ""):  # drop (...) argument lists, keep template arguments
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        elif depth == 0:
            out.append(ch)
    return "".join(out).replace("pt::", "").strip()[:90]


def main():
    rows = []
    with open(sys.argv[1]) as f:
        for line in f:
            m = LINE.match(line)
            if m:
                symbol = m.group(2)
                rows.append((symbol, float(m.group(1)), "ray casting" if RAY_CASTING.search(symbol) else ""))
    if not rows:
        sys.exit("profile_frame: perf recorded no samples")
    total = sum(p for _, p, _ in rows)
    casting = sum(p for _, p, group in rows if group)
    print(f"{'percent':>8}  {'group':<12}  symbol")
    for s, p, group in rows:
        if p >= 0.5:
            print(f"{p:7.1f}%  {group:<12}  {short(s)}")
    print(f"\nray casting (BVH traversal and its entry points): {100 * casting / total:.1f}% of the frame "
          f"(target 5: at least 50%: {'met' if casting >= 0.5 * total else 'missed'})")
    with open(sys.argv[2], "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["symbol", "percent", "group"])
        for s, p, group in rows:
            w.writerow([s, p, group or "other"])
    print(f"wrote {sys.argv[2]}")


if __name__ == "__main__":
    main()
