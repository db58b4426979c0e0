#!/usr/bin/env bash
# Strong and weak scaling of mfcd_mpi on this machine's cores (doc/parallel.md, issue 12).
# Usage: bash bench/mpi_scaling.sh [ROUNDS]   (default 2 rounds, alternating the runs)
# Builds Release with MPI in build-mpi-rel (tools/setup.sh --mpi installs OpenMPI) and the
# serial mfcd in it, then times the time loop (the summary's "time loop") of:
#   strong: the paper's FEM Taylor mesh, 1,000 steps (bench/decks/taylor_bar_fem_1000.nml),
#           and a slab striking a deforming block (slab_on_block_bench.nml: contact with
#           ghost master particles), by serial mfcd, and mfcd_mpi on 1 and 2 ranks;
#           and the 3D Taylor bar's quarter by TL-RKPM at 1/3 mm, 300 steps
#           (taylor_bar_3d_rkpm_bench.nml: 37,000 particles, symmetry planes, contact);
#   weak:   the same per rank on 2 ranks: the bar twice as long, the slab and block twice
#           as wide (taylor_bar_fem_1000_long.nml, slab_on_block_bench_wide.nml,
#           taylor_bar_3d_rkpm_bench_long.nml);
#   hybrid: 1 rank with 2 OpenMP threads, against 2 ranks of 1 thread.
# One OpenMP thread per rank but in the hybrid runs. Writes bench/results/mpi_scaling_<date>.md (git-ignored) and
# prints it; the figures in doc/parallel.md come from it.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
rounds=${1:-2}
build=build-mpi-rel
py=.venv/bin/python
[ -x "$py" ] || py=python3
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMFCD_MPI=ON -DMFCD_GMSH=OFF \
  -DMFCD_PYTHON="$root/$py" > /dev/null
ninja -C "$build" mfcd mfcd_mpi > /dev/null

export OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p bench/results
stamp=$(date +%Y-%m-%d_%H%M%S)
out=bench/results/mpi_scaling_${stamp}.md

# time_loop RUNNER... DECK: the seconds of the run's time loop (its output into $work)
time_loop() {
  local deck=${*: -1} copy
  copy=$work/$(basename "$deck")
  sed "s#file = 'output/#file = '$work/#" "$deck" > "$copy"
  "${@:1:$#-1}" "$copy" > "$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }
  grep -m1 'summary: time loop' "$work/log" | awk '{print $4}'
}
mpi() { local n=$1; shift; mpirun --bind-to none -np "$n" "$build/bin/mfcd_mpi" "$@"; }

declare -A t
cases=(fem contact 3d)
declare -A deck=([fem]=bench/decks/taylor_bar_fem_1000.nml
  [contact]=bench/decks/slab_on_block_bench.nml [3d]=bench/decks/taylor_bar_3d_rkpm_bench.nml)
declare -A wide=([fem]=bench/decks/taylor_bar_fem_1000_long.nml
  [contact]=bench/decks/slab_on_block_bench_wide.nml
  [3d]=bench/decks/taylor_bar_3d_rkpm_bench_long.nml)
for r in $(seq "$rounds"); do
  for c in "${cases[@]}"; do
    t[$c,serial]+="$(time_loop "$build/bin/mfcd" "${deck[$c]}") "
    t[$c,1]+="$(time_loop mpi 1 "${deck[$c]}") "
    t[$c,2]+="$(time_loop mpi 2 "${deck[$c]}") "
    t[$c,w2]+="$(time_loop mpi 2 "${wide[$c]}") "
    t[$c,h]+="$(OMP_NUM_THREADS=2 time_loop mpi 1 "${deck[$c]}") "
  done
done

# the fastest of the rounds of each run (the least disturbed)
best() { tr ' ' '\n' <<< "$1" | grep -v '^$' | sort -g | head -1; }
{
  echo "# mfcd_mpi scaling"
  echo
  echo "- date: $(date -Iseconds)"
  echo "- commit: $(git rev-parse --short HEAD)$(git diff --quiet HEAD -- src bench || echo ' (src/ or bench/ modified)')"
  echo "- cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), nproc $(nproc --all)"
  echo "- compiler: $(gfortran --version | head -1); $(mpirun --version | head -1)"
  echo "- command: bash bench/mpi_scaling.sh $rounds (one thread per rank; the time loop of each round, s; the ratios from the fastest of each)"
  echo
  echo "| case | serial mfcd | 1 rank | 2 ranks | strong speed-up (1 rank / 2 ranks) | 2 ranks, twice the size | weak efficiency (1 rank / 2 ranks, twice the size) | 1 rank x 2 threads | speed-up (1 rank / 1 rank x 2 threads) |"
  echo "|---|---|---|---|---|---|---|---|---|"
  for c in "${cases[@]}"; do
    s=$(best "${t[$c,serial]}"); one=$(best "${t[$c,1]}"); two=$(best "${t[$c,2]}")
    w=$(best "${t[$c,w2]}"); hy=$(best "${t[$c,h]}")
    printf '| %s | %s| %s| %s| %sx | %s| %s%% | %s| %sx |\n' "${deck[$c]##*/}" \
      "${t[$c,serial]}" "${t[$c,1]}" "${t[$c,2]}" \
      "$(awk "BEGIN { printf \"%.2f\", $one / $two }")" "${t[$c,w2]}" \
      "$(awk "BEGIN { printf \"%.0f\", 100 * $one / $w }")" "${t[$c,h]}" \
      "$(awk "BEGIN { printf \"%.2f\", $one / $hy }")"
  done
} | tee "$out"
echo "# written: $out"
