#!/usr/bin/env bash
# What the cores of one machine take from each other (doc/parallel.md, "3D on 16 cores"):
# N independent one-rank runs of the weak-scaling bar (bench/mpi_weak_3d.sh's 30 mm bar,
# 18,837 particles, STEPS steps) at once, with no message between them. Their set-up and
# time-loop seconds against one run alone are what sharing the machine (memory bandwidth,
# caches) costs; the weak scaling's loss beyond that is the parallel code's.
# Usage: [STEPS=N] bash bench/mpi_contention_3d.sh [MPI_BIN_DIR] [N ...]
#   default: build-mpi-rel/bin, N = 1 2, 50 steps
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bin=$(cd "${1:-$root/build-mpi-rel/bin}" && pwd)
shift || true
counts=("$@")
[ ${#counts[@]} -gt 0 ] || counts=(1 2)
steps=${STEPS:-50}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "# independent one-rank runs at once, 3D Taylor bar 30 mm, $steps steps"
echo "- date: $(date -Iseconds); commit: $(git -C "$root" rev-parse --short HEAD 2>/dev/null)"
echo "- cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), nproc $(nproc --all)"
for n in "${counts[@]}"; do
  echo "== $n run(s) at once"
  for i in $(seq 1 "$n"); do
    mkdir -p "$work/$i"
    sed -e "s#file = 'output/#file = '$work/$i/#" \
      -e "s/t_end = 4.5e-6/t_end = $(python3 -c "print(f'{15e-9*$steps:.4e}')")/" \
      -e "s/extrude = 0.0, 0.06/extrude = 0.0, 0.03/" \
      "$root/bench/decks/taylor_bar_3d_rkpm_bench.nml" > "$work/$i/t.nml"
    (cd "$work/$i" && mpirun --bind-to none -np 1 "$bin/mfcd_mpi" t.nml > log.txt 2>&1) &
  done
  wait
  for i in $(seq 1 "$n"); do
    grep -hE "summary: [0-9]+ steps|summary: time loop" "$work/$i/log.txt" \
      | sed -E 's/.*in +([0-9.]+) s wall \(set-up +([0-9.]+) s\).*/set-up \2/;
                s/.*time loop +([0-9.]+) s.*/loop \1/' | tr '\n' ' '
    echo
  done | sort | awk '{print "  run " NR ": " $0}'
done
