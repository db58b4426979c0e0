#!/usr/bin/env bash
# Solver benchmarks (issue 3 item 10, issue 4 item 8): not tests, they time.
#  1. particle-steps per second of the Taylor bar half-section (31 x 361, axisymmetric,
#     viscoplastic, no contact: bench/decks/taylor_bar_free.nml) on 1 and 2 threads, best of
#     two runs each, with the time-loop breakdown the summary prints;
#  2. the whole main job's run (input/taylor_bar_rkpm.nml, with contact and det(M) fields)
#     on 2 threads, wall time.
# Results go to bench/results/solver_<date>.txt; doc/benchmarks.md quotes them.
# Run on an otherwise idle machine: OpenMP threads sharing a core with another busy process
# spin at barriers and the numbers mean nothing.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C build mfcd >/dev/null
mkdir -p bench/results output
out="bench/results/solver_$(date +%Y-%m-%d_%H%M%S).txt"
{
  echo "# mfcd solver benchmark $(date -Iseconds)"
  echo "# commit $(git rev-parse --short HEAD) $(git diff --quiet || echo dirty)"
  echo "# machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
  echo "# load before: $(cut -d' ' -f1-3 /proc/loadavg)"
  for threads in 1 2; do
    for rep in 1 2; do
      line=$(OMP_NUM_THREADS=$threads ./build/bin/mfcd bench/decks/taylor_bar_free.nml \
        | grep -E '^summary: ([0-9]+ steps|time loop)' | tr '\n' ' ')
      echo "RESULT bench=solver_free threads=$threads rep=$rep $line"
    done
  done
  start=$(date +%s.%N)
  OMP_NUM_THREADS=2 ./build/bin/mfcd input/taylor_bar_rkpm.nml \
    | grep -E '^summary: ([0-9]+ steps|time loop)' | sed 's/^/RESULT bench=main_job threads=2 /'
  end=$(date +%s.%N)
  echo "RESULT bench=main_job_run wall_s=$(awk -v a="$start" -v b="$end" 'BEGIN{print b - a}')"
} | tee "$out"
echo "wrote $out"
