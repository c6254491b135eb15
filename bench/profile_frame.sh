#!/usr/bin/env bash
# Where a Cornell frame's time goes (issue 11, target 5: ray casting at least half of the frame). Renders
# bench/data/cornell36.obj with its ceiling light emitting (17, 12, 4) and no background, the set-up of
# `make bench-cornell36`, headless at 256x256, depth 8, 1 thread, under `perf record -e cpu-clock:u`, then prints the
# share of every function above 0.5% and the share of ray casting: the BVH traversal and its entry points (every
# function of src/accel that a ray goes through). Writes BUILD_DIR/profile_frame.csv (symbol, percent, group).
#   bench/profile_frame.sh [BUILD_DIR]        (default: build; needs BUILD_DIR/ptview and perf, from linux-perf)
# Environment: SPP (samples per pixel rendered under the profiler; default 128), FREQ (samples per second; 4000),
# PTVIEW_ARGS (extra ptview options, e.g. "--sampler independent").
#
# cpu-clock is a software event, so this works in virtual machines without hardware counters; :u keeps user-space
# samples only, which a user may record without lowering perf_event_paranoid. Shares are of the ptview process's
# samples, loading and BVH build included (under 1% at 128 spp). The run's wall time is printed too: on a shared
# machine the shares move with its state (docs/BENCHMARKS.md, fifteenth round), so read them together.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$(cd "${1:-build}" && pwd)"
ptview="$build/ptview"
spp="${SPP:-128}"
freq="${FREQ:-4000}"
if [ ! -x "$ptview" ]; then
  echo "profile_frame: $ptview not found (build first: make build)" >&2
  exit 2
fi
if ! command -v perf > /dev/null; then
  echo "profile_frame: perf not found (Debian: apt-get install linux-perf)" >&2
  exit 2
fi
py=/usr/bin/python3
[ -x "$py" ] || py=python3
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# The lit box: the same OBJ, its MTL with the light's emission added, and cornell36.json without its background.
cp "$root/bench/data/cornell36.obj" "$tmp/"
sed '/^newmtl light/a Ke 17 12 4' "$root/bench/data/cornell36.mtl" > "$tmp/cornell36.mtl"
"$py" -c 'import json, sys; s = json.load(open(sys.argv[1])); s.pop("background", None); json.dump(s, sys.stdout)' \
  "$root/bench/data/cornell36.json" > "$tmp/scene.json"

start=$(date +%s.%N)
# shellcheck disable=SC2086
perf record -q -e cpu-clock:u -F "$freq" -o "$tmp/perf.data" -- "$ptview" "$tmp/scene.json" --frames "$spp" \
  --size 256x256 --max-depth 8 --threads 1 --out "$tmp/frame.pfm" ${PTVIEW_ARGS:-} > /dev/null
perf report -q -i "$tmp/perf.data" --stdio --no-children --sort symbol --percent-limit 0 2> /dev/null \
  > "$tmp/report.txt"
seconds=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')
echo "profiled: $spp spp of 256x256 in $seconds s (wall, under perf)"
"$py" "$root/bench/profile_frame.py" "$tmp/report.txt" "$build/profile_frame.csv"
