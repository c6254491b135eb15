#!/usr/bin/env bash
# End-to-end throughput of ptview against the Embree path tracer tutorial (Debian's embree-tools,
# /usr/bin/pathtracer) on the same scene: bench/data/cornell36.obj (36 triangles), 512x512, path length 8, the same
# camera, and a uniform white background for both (ptview: "background": [1,1,1] in bench/data/cornell36.json;
# Embree: --ambientlight 1 1 1). Prints a table (renderer, threads, spp/s, Mrays/s, ratio ptview/Embree at the same
# thread count, ptview scaling 1 -> 2 threads), writes BUILD_DIR/e2e_vs_embree.csv and one image per renderer
# (BUILD_DIR/e2e-ptview.png, BUILD_DIR/e2e-embree.ppm or .png).
#   bench/e2e_vs_embree.sh [BUILD_DIR]        (default: build; needs BUILD_DIR/ptview)
# Environment: FRAMES (timed frames per run, 1 spp each; default 24), REPEAT (rounds; each row keeps its best;
# default 1), PTVIEW_ARGS (extra ptview options),
# EMBREE_PATHTRACER (default /usr/bin/pathtracer; absent: the Embree rows are skipped with a message).
#
# The MTL has no emission (Embree's OBJ loader ignores `Ke`), so the background is the only light in both. Path length:
# ptview's --max-depth 8 (pbrt convention) and Embree's --max-path-length 8 (1 = primary + shadow) both allow up to 8
# scattering vertices with light sampling at each; ptview adds Russian roulette, Embree stops when the throughput
# falls below 0.01. Each renderer runs its own default sampler and integrator (ptview: MIS, Sobol; Embree: cosine
# BRDF sampling plus one ambient-light shadow ray per vertex). ptview has no area light here, so it casts no shadow
# rays and gathers the background when a path escapes: fewer rays per sample than Embree (see the Mrays/s column),
# and a different noise per sample; this table compares samples per second only.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-build}"
build="$(cd "$build" && pwd)"
ptview="$build/ptview"
embree="${EMBREE_PATHTRACER:-/usr/bin/pathtracer}"
frames="${FRAMES:-24}"
repeat="${REPEAT:-1}"
scene_json="$root/bench/data/cornell36.json"
scene_obj="$root/bench/data/cornell36.obj"
csv="$build/e2e_vs_embree.csv"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

if [ ! -x "$ptview" ]; then
  echo "e2e_vs_embree: $ptview not found (build first: make build)" >&2
  exit 1
fi
py=/usr/bin/python3
[ -x "$py" ] || py=python3

echo "e2e: cornell36 (36 triangles), 512x512, path length 8, uniform background 1; $frames frames of 1 spp per run," \
  "best of $repeat round(s)"
# Idle check: the share of CPU time other processes used over one second (the load average lags by minutes).
cpu_busy() {
  local a b
  read -r _ a1 a2 a3 a4 a5 a6 a7 _ < /proc/stat; sleep 1
  read -r _ b1 b2 b3 b4 b5 b6 b7 _ < /proc/stat
  a=$((a1 + a2 + a3 + a4 + a5 + a6 + a7)); b=$((b1 + b2 + b3 + b4 + b5 + b6 + b7))
  awk -v busy=$(((b - a) - (b4 - a4) - (b5 - a5))) -v total=$((b - a)) 'BEGIN {printf "%.0f", 100 * busy / total}'
}
busy=$(cpu_busy)
echo "e2e: machine: $(nproc) cores, $busy% busy before the runs, load average $(cut -d' ' -f1-3 /proc/loadavg)"
if [ "$busy" -gt 10 ]; then
  echo "e2e: warning: the machine is not idle ($busy% busy): the figures, the 2-thread ones above all, will be low"
fi

# ptview: spp/s and Mrays/s from --stats-json (render time only: loading and the BVH build are excluded).
run_ptview() {  # THREADS OUT_IMAGE -> "spp/s Mrays/s"
  # shellcheck disable=SC2086
  "$ptview" "$scene_json" --frames "$frames" --size 512x512 --max-depth 8 --threads "$1" \
    --out "$2" --stats-json "$tmp/ptview.json" ${PTVIEW_ARGS:-} >&2
  "$py" -c 'import json,sys; j=json.load(open(sys.argv[1])); print(j["spp_per_s"], j["mrays_per_s"])' "$tmp/ptview.json"
}

# Embree: benchmark mode, 1 spp per frame, so frames/s = spp/s (2 warm-up frames skipped).
embree_args=(-i "$scene_obj" --vp 278 273 -800 --vi 278 273 0 --vu 0 1 0 --fov 37 --size 512 512
             --max-path-length 8 --ambientlight 1 1 1)
run_embree() {  # THREADS -> "spp/s Mrays/s"
  "$embree" "${embree_args[@]}" --threads "$1" --spp 1 --benchmark 2 "$frames" > "$tmp/embree.log" 2>&1
  if ! grep -q '^BENCHMARK_RENDER_AVG ' "$tmp/embree.log"; then
    echo "e2e_vs_embree: no BENCHMARK_RENDER_AVG in the output of $embree:" >&2
    cat "$tmp/embree.log" >&2
    return 1
  fi
  awk '$1 == "BENCHMARK_RENDER_AVG" {s = $2} $1 == "BENCHMARK_RENDER_MRAYPS_AVG" {m = $2} END {print s, m}' \
    "$tmp/embree.log"
}

renderers=(ptview)
if [ -x "$embree" ]; then
  renderers+=(embree)
else
  echo "e2e: $embree not found: Embree rows skipped (install embree-tools: PTVIEW_WITH_BENCH_DEPS=1 bash scripts/install-deps.sh)"
fi

# REPEAT rounds, the renderers interleaved so that a burst of other work hits both; each row keeps its best round.
declare -A spp mrays
for ((round = 1; round <= repeat; ++round)); do
  for t in 1 2; do
    for r in "${renderers[@]}"; do
      if [ "$r" = ptview ]; then
        out="$tmp/ptview.png"; [ "$t" = 2 ] && out="$build/e2e-ptview.png"
        read -r s m < <(run_ptview "$t" "$out")
      else
        read -r s m < <(run_embree "$t")
      fi
      [ -n "$s" ] || exit 1
      if [ -z "${spp[$r,$t]:-}" ] || awk -v a="$s" -v b="${spp[$r,$t]}" 'BEGIN {exit !(a > b)}'; then
        spp[$r,$t]=$s; mrays[$r,$t]=$m
      fi
    done
  done
done
rows=()
for r in "${renderers[@]}"; do rows+=("$r,1" "$r,2"); done

if [ -x "$embree" ]; then
  # The same number of samples as the ptview image, for a side-by-side look (Embree writes linear 8-bit values).
  "$embree" "${embree_args[@]}" --spp "$frames" -o "$build/e2e-embree.ppm" > "$tmp/embree-img.log" 2>&1
  if "$py" -c 'import sys; from PIL import Image; Image.open(sys.argv[1]).save(sys.argv[2])' \
       "$build/e2e-embree.ppm" "$build/e2e-embree.png" 2>/dev/null; then
    rm -f "$build/e2e-embree.ppm"  # PNG when Pillow is there (python3-matplotlib brings it), else the PPM stays
  fi
fi

echo "renderer,threads,spp_per_s,mrays_per_s,ratio_ptview_over_embree,scaling_1_to_2" > "$csv"
printf '%-8s %7s %9s %9s %17s %15s\n' renderer threads spp/s Mrays/s ptview/Embree "scaling 1->2"
for r in "${rows[@]}"; do
  name=${r%,*}; t=${r#*,}
  ratio=""; scaling=""
  if [ "$name" = ptview ] && [ -n "${spp[embree,$t]:-}" ]; then
    ratio=$(awk -v a="${spp[ptview,$t]}" -v b="${spp[embree,$t]}" 'BEGIN {printf "%.3f", a / b}')
  fi
  if [ "$t" = 2 ]; then
    scaling=$(awk -v a="${spp[$name,2]}" -v b="${spp[$name,1]}" 'BEGIN {printf "%.3f", a / b}')
  fi
  printf '%-8s %7s %9.3f %9.3f %17s %15s\n' "$name" "$t" "${spp[$r]}" "${mrays[$r]}" "${ratio:--}" "${scaling:--}"
  echo "$name,$t,${spp[$r]},${mrays[$r]},$ratio,$scaling" >> "$csv"
done
echo "e2e: wrote $csv"
