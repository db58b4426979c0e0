#!/usr/bin/env bash
# Weak scaling of mfcd_mpi's set-up and memory in the plane (doc/parallel.md, "Rectangles
# made per rank"): the fine RKPM Taylor bar's deck (input/taylor_bar_rkpm_fine.nml, an
# axisymmetric bar of radius 5 mm on a rigid target) with the bar at 1/24 mm spacing,
# 121 particles across, made 30 mm long per rank (87,120 particles a rank: 2 ranks hold a
# bar of the deck's 60 mm), a few steps, on each rank count given, one thread a rank. The
# part per rank stays the same while the whole bar grows with the ranks, so what every rank
# holds or does for the whole body shows as the growth of its peak memory and set-up time.
# FEM=1 makes the bar of CST4 elements on the same lattice (the coarse FEM Taylor bar's
# deck, input/taylor_bar_fem_coarse.nml, without its det(M) fields, which would keep the
# whole solids on rank 0 to draw them).
# POLYGON=1 takes the C of input/c_shape_fold.nml (RKPM, self-contact) at 1/16 mm spacing
# instead, its two arms 20 mm longer for each rank (the spine 6 x 30 mm, the arms 6 mm
# thick: some 61,000 particles a rank more), made per rank from its lattice's rows.
# RING=1 takes the CST4 ring of input/ring_crush.nml (self-contact) instead, refined for each
# rank count so that it holds some 61,000 nodes a rank (n = 1 + 46 sqrt(ranks/2) corners
# across the wall, 28.3 times as many boxes around: near-square boxes), made per rank from
# its polar lattice.
# Prints, per run, the bar's size, the summary's set-up and time-loop seconds, every rank's
# resident memory after the set-up and at the end (the smallest and largest, mfcd_mpi's
# log), the log's line on the bar made per rank, and every rank's peak resident memory (GNU
# time's %M).
# Usage: [STEPS=N] [FEM=1] bash bench/mpi_weak_2d.sh [MPI_BIN_DIR] [RANKS ...]
#   default: build-mpi-rel/bin (bench/mpi_scaling.sh builds it), ranks 2 4 8, 3 steps
#   (POLYGON=1, RING=1: t_end 2e-8 s, a few steps)
# More ranks than cores run oversubscribed: the memory holds, the set-up's seconds are then
# the ranks sharing a core.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bin=$(cd "${1:-$root/build-mpi-rel/bin}" && pwd)
shift || true
ranks=("$@")
[ ${#ranks[@]} -gt 0 ] || ranks=(2 4 8)
[ -x /usr/bin/time ] || { echo "mpi_weak_2d: needs GNU time (apt-get install time)" >&2; exit 2; }
steps=${STEPS:-3}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ "${RING:-0}" = 1 ]; then
  echo "# mfcd_mpi weak scaling of the set-up, the CST4 ring of ring_crush.nml, some 61,000 nodes a rank, t_end 2e-8 s"
elif [ "${POLYGON:-0}" = 1 ]; then
  echo "# mfcd_mpi weak scaling of the set-up, the C of c_shape_fold.nml, arms 20 mm longer a rank at 1/16 mm, t_end 2e-8 s"
else
  echo "# mfcd_mpi weak scaling of the set-up, plane Taylor bar 30 mm a rank at 1/24 mm, $steps steps$([ "${FEM:-0}" = 1 ] && echo ', CST4')"
fi
echo "- date: $(date -Iseconds); repository at $(git -C "$root" rev-parse --short HEAD 2>/dev/null); bin: $bin (its commit: each run's first log line)"
echo "- cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), nproc $(nproc --all)"
for n in "${ranks[@]}"; do
  len=$(python3 -c "print(f'{0.03*$n:.4f}')")
  ny=$((720 * n + 1))
  if [ "${RING:-0}" = 1 ]; then
    n1=$(python3 -c "print(1 + round(46 * ($n / 2) ** 0.5))")
    n2=$(python3 -c "print(4 * round(28.3 * ($n1 - 1) / 4))")
    sed -e "s#file = 'output/#file = '$work/#" -e "s/  n = 5, 112/  n = $n1, $n2/" \
      -e 's/t_end = 860.0e-6/t_end = 2.0e-8/' -e '/snapshot_times/d' \
      "$root/input/ring_crush.nml" > "$work/t.nml"
    grep -q "n = $n1, $n2" "$work/t.nml" || { echo "mpi_weak_2d: the deck was not resized" >&2; exit 1; }
    echo "== $n rank(s), the ring's polar lattice $n1 x $n2"
  elif [ "${POLYGON:-0}" = 1 ]; then
    xr=$(python3 -c "print(f'{0.006 + 0.02*$n:.4f}')")
    sed -e "s#file = 'output/#file = '$work/#" -e "s/0\.040,/$xr,/g" \
      -e 's/spacing = 0.001, 0.001/spacing = 0.0000625, 0.0000625/' \
      -e 's/t_end = 400.0e-6/t_end = 2.0e-8/' -e '/snapshot_times/d' \
      "$root/input/c_shape_fold.nml" > "$work/t.nml"
    grep -q "$xr, 0.006" "$work/t.nml" || { echo "mpi_weak_2d: the deck was not resized" >&2; exit 1; }
    echo "== $n rank(s), the C's arms to x = $xr m at 1/16 mm"
  elif [ "${FEM:-0}" = 1 ]; then
    # (the adaptive step: a few steps' time at the coarse deck's first step, shrunk with
    # the spacing)
    sed -e "s#file = 'output/#file = '$work/#" -e '/det_fields/d' -e '/det_grid/d' \
      -e "s/  n = 16, 181/  n = 121, $ny/" -e "s/hi = 0.005, 0.06/hi = 0.005, $len/" \
      -e "s/t_end = 24.0e-6/t_end = $(python3 -c "print(f'{1.0e-9*$steps:.4e}')")/" \
      -e '/snapshot_times/d' "$root/input/taylor_bar_fem_coarse.nml" > "$work/t.nml"
  else
    sed -e "s#file = 'output/#file = '$work/#" -e "s/  n = 61, 721/  n = 121, $ny/" \
      -e "s/hi = 0.005, 0.06/hi = 0.005, $len/" -e 's/dt = 1.25e-9/dt = 0.625e-9/' \
      -e "s/t_end = 24.0e-6/t_end = $(python3 -c "print(f'{0.625e-9*$steps:.4e}')")/" \
      -e '/snapshot_times/d' "$root/input/taylor_bar_rkpm_fine.nml" > "$work/t.nml"
  fi
  if [ "${POLYGON:-0}" != 1 ] && [ "${RING:-0}" != 1 ]; then
    grep -q "n = 121, $ny" "$work/t.nml" || { echo "mpi_weak_2d: the deck was not resized" >&2; exit 1; }
    echo "== $n rank(s), bar $len m long, 121 x $ny"
  fi
  rm -f "$work"/mem.*
  (cd "$work" && mpiexec --oversubscribe --bind-to none -n "$n" sh -c \
    'exec /usr/bin/time -o "mem.$OMPI_COMM_WORLD_RANK" -f "%M" "$1" t.nml' sh \
    "$bin/mfcd_mpi" > log.txt 2> err.txt) || { tail -5 "$work/err.txt"; exit 1; }
  grep -m1 -E "^mfcd .*\(git " "$work/log.txt" | sed -e 's/^/  /'
  grep -E "made per rank|summary: [0-9]+ steps|summary: time loop|resident memory" "$work/log.txt" \
    | sed -e 's/^/  /'
  for r in $(seq 0 $((n - 1))); do
    printf '  mem rank %d %s kB\n' "$r" "$(cat "$work/mem.$r")"
  done
done
