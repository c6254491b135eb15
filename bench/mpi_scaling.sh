#!/usr/bin/env bash
# spp/s of one process with 2 threads against 2 MPI ranks with 1 thread each (src/dist), same scene and total spp,
# runs alternated and repeated (timings on a shared machine are noisy: compare the ratio within a pair). Then the
# cost of one reduction (bench_mpi_reduce) for 2 ranks. Table on stdout, CSV in BUILD_DIR/mpi_scaling.csv.
# Usage: bench/mpi_scaling.sh [BUILD_DIR] [REPEATS]
set -euo pipefail
build=${1:-build}
repeats=${2:-3}
exe=$build/ptview
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_vader_single_copy_mechanism=none
mpirun="mpirun -q --oversubscribe"
scene=${PTVIEW_BENCH_SCENE:-builtin:cornell-spheres}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
args=("$scene" --frames 16 --size 256x256 --out "$tmp/x.pfm")
sps() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['spp_per_s'])" "$1"; }
comm() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['comm_ms'])" "$1"; }
csv=$build/mpi_scaling.csv
echo "run,one_process_2t_sps,two_ranks_1t_bound_sps,two_ranks_1t_unbound_sps,ratio_bound,ratio_unbound,comm_ms" >"$csv"
printf "%4s %14s %18s %20s %8s %8s %8s\n" run "1x2 spp/s" "2x1 spp/s (bind)" "2x1 spp/s (no bind)" ratio "ratio nb" comm_ms
for i in $(seq 1 "$repeats"); do
  "$exe" "${args[@]}" --threads 2 --stats-json "$tmp/a.json"
  $mpirun -np 2 "$exe" "${args[@]}" --threads 1 --stats-json "$tmp/b.json"
  $mpirun -np 2 --bind-to none "$exe" "${args[@]}" --threads 1 --stats-json "$tmp/c.json"
  a=$(sps "$tmp/a.json"); b=$(sps "$tmp/b.json"); c=$(sps "$tmp/c.json"); m=$(comm "$tmp/b.json")
  rb=$(python3 -c "print(f'{$b/$a:.3f}')"); rn=$(python3 -c "print(f'{$c/$a:.3f}')")
  printf "%4d %14.2f %18.2f %20.2f %8s %8s %8.1f\n" "$i" "$a" "$b" "$c" "$rb" "$rn" "$m"
  echo "$i,$a,$b,$c,$rb,$rn,$m" >>"$csv"
done
echo "CSV: $csv"
echo
echo "One reduction (sum of every Film buffer at rank 0), 2 ranks:"
$mpirun -np 2 "$build/bench/bench_mpi_reduce" --csv "$build/mpi_reduce.csv"
