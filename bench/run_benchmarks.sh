#!/usr/bin/env bash
# Build mfcd in Release and run the contact-detection benchmark (bench/README.md).
# Usage: bash bench/run_benchmarks.sh [bench_detect options, default: --rounds 3]
# Writes bench/results/detect_<date>.txt (git-ignored) and prints it.
# Environment: BUILD_DIR (default build).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
build=${BUILD_DIR:-build}
args=("$@")
if [ ${#args[@]} -eq 0 ]; then
  args=(--rounds 3)
fi

cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
ninja -C "$build" bench_detect

mkdir -p bench/results
stamp=$(date +%Y-%m-%d_%H%M%S)
out=bench/results/detect_${stamp}.txt

# One BLAS thread: dpotrf is called per point from inside OpenMP loops.
export OPENBLAS_NUM_THREADS=1

{
  echo "# mfcd contact-detection benchmark"
  echo "# date: $(date -Iseconds)"
  echo "# commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet HEAD -- src bench 2>/dev/null || echo ' (src/ or bench/ modified)')"
  echo "# host: $(uname -n), nproc $(nproc), cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
  echo "# compiler: $(gfortran --version | head -1)"
  echo "# build: $build ($(grep -E '^(CMAKE_BUILD_TYPE|MFCD_NATIVE)' "$build/CMakeCache.txt" | tr '\n' ' '))"
  echo "# load average before the run: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "# command: $build/bin/bench_detect ${args[*]}"
  "$build/bin/bench_detect" "${args[@]}"
  echo "# load average after the run: $(cut -d' ' -f1-3 /proc/loadavg)"
} 2>&1 | tee "$out"

echo "# written: $out"
