#!/usr/bin/env bash
# Installs the Debian packages ptview needs to build, test and run (idempotent: installs only what is missing).
# Runs apt-get as root, or through sudo when not root.
set -euo pipefail

packages=(
  build-essential cmake pkg-config python3
  libglm-dev libtinyobjloader-dev libtinygltf-dev libcli11-dev nlohmann-json3-dev libstb-dev libopenexr-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libglfw3-dev libimgui-dev python3-glad libgl-dev
  xvfb xauth libgl1-mesa-dri
  openmpi-bin libopenmpi-dev  # MPI: optional at build time, installed so make test runs the MPI tests
)
if [ "${PTVIEW_WITH_CI_TOOLS:-0}" = "1" ]; then
  packages+=(clang libclang-rt-14-dev util-linux)  # fuzzing (libFuzzer) and setarch for ThreadSanitizer
fi
if [ "${PTVIEW_WITH_BENCH_DEPS:-0}" = "1" ]; then
  packages+=(libembree-dev embree-tools python3-matplotlib linux-perf)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then missing+=("$p"); fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then sudo_cmd=(sudo); else
    echo "install-deps: need root (or sudo) to install: ${missing[*]}" >&2
    exit 1
  fi
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
