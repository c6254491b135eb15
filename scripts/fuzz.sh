#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (preset "fuzz") and runs each for SECONDS (default 60).
# Any crash is copied into tests/data/bad/fuzz-<target>-<hash> so it becomes a regression input, and the script fails.
# fuzz_render (the whole pipeline: load, BVH, render) grows its corpus in the repository (fuzz/corpus/render), so
# fuzzing time accumulates across runs; the others start from their seeds each time.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$(nproc)" >/dev/null
status=0
for target in fuzz_json fuzz_obj fuzz_cli fuzz_gltf fuzz_render; do
  corpus_dir="fuzz/corpus/${target#fuzz_}"
  work="build-fuzz/work-$target"
  mkdir -p "$work/corpus" "$work/artifacts"
  cp -n "$corpus_dir"/* "$work/corpus/" 2>/dev/null || true
  corpus="$work/corpus"
  limits=(-max_len=4096 -timeout=10 -rss_limit_mb=2048)
  if [ "$target" = fuzz_render ]; then
    # Scene JSON plus OBJ/MTL text; one input renders 6 x 8x8 pixels at 2 spp, so 10 s means a hang. An input
    # that allocates more than 1 GiB at once or holds more than 2 GiB is a finding.
    corpus="$corpus_dir"
    limits=(-max_len=8192 -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024)
  fi
  echo "fuzz: $target for ${seconds}s"
  if ! "build-fuzz/fuzz/$target" "$corpus" -max_total_time="$seconds" "${limits[@]}" \
       -artifact_prefix="$work/artifacts/" -print_final_stats=1 >"$work/log.txt" 2>&1; then
    status=1
    tail -n 30 "$work/log.txt"
    for a in "$work"/artifacts/*; do
      [ -f "$a" ] && cp "$a" "tests/data/bad/fuzz-$target-$(basename "$a" | tr -c 'a-zA-Z0-9\n-' '_')"
    done
  fi
  grep -E "stat::number_of_executed_units|stat::new_units_added" "$work/log.txt" | sed "s/^/fuzz: $target /" || true
done
exit $status
