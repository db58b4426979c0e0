#!/usr/bin/env bash
# Strong scaling of mfcd_mpi past 2 ranks (doc/parallel.md, "3D on 16 cores"): the 3D Taylor
# bench (bench/decks/taylor_bar_3d_rkpm_bench.nml, 37,467 particles) cut to its first 100
# steps, on each RANKSxTHREADS given, with every rank's peak resident memory.
# Usage: bash bench/mpi_strong_3d.sh [MPI_BIN_DIR] [RxT ...]
#   default: build-mpi-rel/bin (bench/mpi_scaling.sh builds it), 1x1 2x1 4x1 8x1 16x1 1x16 4x4
#   T_END=1.5e-7 for 10 steps instead of 100 (steps of 15 ns)
# Prints, for each run, the summary's set-up and time-loop seconds, the ghosts and halo bytes,
# and "mem rank R KB" per rank (GNU time's %M); the table in doc/parallel.md is made from it.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bin=${1:-$root/build-mpi-rel/bin}
shift || true
runs=("$@")
[ ${#runs[@]} -gt 0 ] || runs=(1x1 2x1 4x1 8x1 16x1 1x16 4x4)
timer=$(command -v time || true)
[ -x /usr/bin/time ] && timer=/usr/bin/time
[ -x "$timer" ] || { echo "mpi_strong_3d: needs GNU time (apt-get install time)" >&2; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed -e "s#file = 'output/#file = '$work/#" -e "s/t_end = 4.5e-6/t_end = ${T_END:-1.5e-6}/" \
  -e 's/log_every = 100/log_every = 50/' "$root/bench/decks/taylor_bar_3d_rkpm_bench.nml" \
  > "$work/t.nml"
echo "# mfcd_mpi strong scaling, 3D Taylor bench, to t = ${T_END:-1.5e-6} s (15 ns steps)"
echo "- date: $(date -Iseconds); commit: $(git -C "$root" rev-parse --short HEAD 2>/dev/null)"
echo "- cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), nproc $(nproc)"
for rt in "${runs[@]}"; do
  n=${rt%x*}
  th=${rt#*x}
  echo "== $n ranks x $th threads"
  rm -f "$work"/mem.*
  # each rank's peak into its own file (one stream would interleave the ranks' lines)
  OMP_NUM_THREADS=$th mpirun --oversubscribe --bind-to none -np "$n" sh -c \
    'exec "$1" -o "$4/mem.$OMPI_COMM_WORLD_RANK" -f "%M" "$2" "$3"' sh "$timer" \
    "$bin/mfcd_mpi" "$work/t.nml" "$work" > "$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }
  grep -E 'summary: (MPI|[0-9]+ steps|time loop)' "$work/log"
  for r in $(seq 0 $((n - 1))); do
    printf 'mem rank %d %s kB\n' "$r" "$(cat "$work/mem.$r")"
  done
done
