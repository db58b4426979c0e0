#!/usr/bin/env bash
# FEM (CST4) solver benchmark (issue 7): triangle-steps per second of the paper's Taylor bar
# mesh (43,200 triangles, viscoplastic, contact with the rigid target) over its first 1,000
# steps at the paper's dt, on 1 and 2 threads, twice each; then the whole runs on 2 threads:
# the CFL variant (adaptive step, input/taylor_bar_fem_cfl.nml) and the paper-dt run
# (38,400 steps; MFCD_BENCH_FULL=0 skips both). Results go to bench/results/ and, by hand,
# doc/benchmarks.md.
# Run on an otherwise idle machine: OpenMP threads sharing a core slow down tenfold.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C build mfcd >/dev/null
mkdir -p bench/results output
out="bench/results/fem_$(date +%Y-%m-%d_%H%M%S).txt"
{
  echo "# mfcd FEM benchmark $(date -Iseconds)"
  echo "# commit $(git rev-parse --short HEAD) $(git diff --quiet || echo dirty)"
  echo "# machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
  echo "# load before: $(cut -d' ' -f1-3 /proc/loadavg)"
  for threads in 1 2; do
    for rep in 1 2; do
      line=$(OMP_NUM_THREADS=$threads ./build/bin/mfcd bench/decks/taylor_bar_fem_1000.nml \
        | grep -E '^summary: ([0-9]+ steps|time loop)' | tr '\n' ' ')
      echo "RESULT bench=fem_1000 threads=$threads rep=$rep $line"
    done
  done
  if [ "${MFCD_BENCH_FULL:-1}" = 1 ]; then
    OMP_NUM_THREADS=2 ./build/bin/mfcd input/taylor_bar_fem_cfl.nml \
      | grep -E '^summary: ([0-9]+ steps|time loop|dt )' | sed 's/^/RESULT bench=fem_cfl threads=2 /'
    OMP_NUM_THREADS=2 ./build/bin/mfcd input/taylor_bar_fem.nml \
      | grep -E '^summary: ([0-9]+ steps|time loop)' | sed 's/^/RESULT bench=fem_paper threads=2 /'
  fi
} | tee "$out"
echo "wrote $out"
