#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer, then the worker pool, the progressive
# session and the restart logic under ThreadSanitizer. Any report fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="$(nproc 2>/dev/null || echo 2)"
echo "sanitizers: ASan + UBSan build"
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$jobs" >/dev/null
ctest --preset asan -j "$jobs" --timeout 1800
echo "sanitizers: TSan build"
cmake --preset tsan >/dev/null
cmake --build --preset tsan -j "$jobs" --target test_session test_determinism test_stability test_integrator ptview test_cli >/dev/null
# setarch -R: TSan in LLVM 14 / GCC 12 cannot map its shadow memory with high ASLR entropy on newer kernels.
runner=()
if command -v setarch >/dev/null 2>&1 && setarch "$(uname -m)" -R true 2>/dev/null; then runner=(setarch "$(uname -m)" -R); fi
TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" "${runner[@]}" ctest --test-dir build-tsan -j "$jobs" \
  --output-on-failure -R 'Session|Determinism|ThreadCount|Stability|Furnace'
