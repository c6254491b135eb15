#!/usr/bin/env bash
# Restart latency of the viewer (edit -> first frame of the new epoch shown, p50 / p95 from the viewer's
# --stats-json) under a scripted edit storm (80 orbits, 25 ms apart): one process against 2 MPI ranks (the viewer
# offload, docs/CLUSTER.md), both with the default threads (all cores for one process, the cores shared among the
# ranks under mpirun). Runs alternated and repeated: compare within a pair on a shared machine. Needs xvfb-run.
# Table on stdout, CSV in BUILD_DIR/offload_latency.csv.
# Usage: bench/offload_latency.sh [BUILD_DIR] [REPEATS] [SIZE]
set -euo pipefail
build=${1:-build}
repeats=${2:-3}
size=${3:-512x512}
exe=$build/ptview
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_vader_single_copy_mechanism=none
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 - "$tmp/storm.txt" <<'PY'
import sys
s = "wait-frames 2\n"
for i in range(80):
    s += ("orbit 3 1" if i % 2 == 0 else "orbit -3 -1") + "\nwait-ms 25\n"
open(sys.argv[1], "w").write(s + "wait-frames 2\nquit\n")
PY
xvfb="xvfb-run -a -n $((300 + $$ % 500)) -s '-screen 0 1280x1024x24'"
lat() { python3 -c "import json,sys; l=json.load(open(sys.argv[1]))['restart_latency_ms']; print(f\"{l['p50']:.1f} {l['p95']:.1f} {l['count']}\")" "$1"; }
csv=$build/offload_latency.csv
echo "run,one_p50_ms,one_p95_ms,two_ranks_p50_ms,two_ranks_p95_ms" >"$csv"
printf "%4s %12s %12s %14s %14s\n" run "1 p50 ms" "1 p95 ms" "2 ranks p50" "2 ranks p95"
for i in $(seq 1 "$repeats"); do
  eval "$xvfb" "$exe" --size "$size" --script "$tmp/storm.txt" --stats-json "$tmp/one.json"
  eval "$xvfb" mpirun -q --oversubscribe --bind-to none -np 2 "$exe" --size "$size" --script "$tmp/storm.txt" \
    --stats-json "$tmp/two.json"
  read -r a50 a95 _ <<<"$(lat "$tmp/one.json")"
  read -r b50 b95 _ <<<"$(lat "$tmp/two.json")"
  printf "%4d %12s %12s %14s %14s\n" "$i" "$a50" "$a95" "$b50" "$b95"
  echo "$i,$a50,$a95,$b50,$b95" >>"$csv"
done
echo "CSV: $csv"
