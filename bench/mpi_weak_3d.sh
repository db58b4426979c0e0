#!/usr/bin/env bash
# Weak scaling of mfcd_mpi's set-up and memory (doc/parallel.md, "Weak scaling of the set-up"):
# the 3D Taylor bench's bar (bench/decks/taylor_bar_3d_rkpm_bench.nml, a quarter cylinder
# of radius 5 mm at 1/3 mm spacing) made 30 mm long per rank (18,747 particles a rank: 2
# ranks hold the bench's bar), 10 steps, on each rank count given, one thread a rank. The
# part per rank stays the same while the whole body grows with the ranks, so what every rank
# holds or does for the whole body shows as the growth of its peak memory and set-up time.
# Prints, per run, the particles, the summary's set-up and time-loop seconds, every rank's
# resident memory after the set-up and at the end (the smallest and largest, mfcd_mpi's log),
# what the ranks have read by then (a mesh file's reading, MESH=1), the most facets of the
# bar's surface a rank holds (its rows of them), and every rank's peak resident memory (GNU
# time's %M).
# SELF=1 adds the bar's self-contact (a &contact group of the bar with itself: 3D
# self-contact's sides, which hold arrays over all their particles on every rank).
# FEM=1 makes the bar of linear tetrahedra on the same lattice (discretization = 'fem': the
# quarter disk's prisms, three tetrahedra each) instead of RKPM particles.
# MESH=1 makes it of gmsh's unstructured tetrahedra read from a mesh file (the quarter bar
# of input/taylor_bar_quarter.geo, radius 5 mm, 30 mm a rank, elements of H m, 1/3 mm by
# default, meshed once a run by tools/mesh_body.py --3d with .venv's gmsh; the deck
# input/taylor_bar_3d_fem_geo.nml given the file): a body each rank reads per part.
# Usage: [STEPS=N] [SELF=1] [FEM=1 | MESH=1 [H=h]] bash bench/mpi_weak_3d.sh [MPI_BIN_DIR] [RANKS ...]
#   default: build-mpi-rel/bin (bench/mpi_scaling.sh builds it), ranks 2 4 8, 10 steps of 15 ns
#   (more steps, e.g. STEPS=50, to time the time loop's weak scaling too)
# More ranks than cores run oversubscribed: the memory holds, the set-up's seconds are then
# the ranks sharing a core (divide by ranks / cores for one core's work).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bin=$(cd "${1:-$root/build-mpi-rel/bin}" && pwd)
shift || true
ranks=("$@")
[ ${#ranks[@]} -gt 0 ] || ranks=(2 4 8)
[ -x /usr/bin/time ] || { echo "mpi_weak_3d: needs GNU time (apt-get install time)" >&2; exit 2; }
steps=${STEPS:-10}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
h=${H:-0.333e-3}
echo "# mfcd_mpi weak scaling of the set-up, 3D Taylor bar 30 mm a rank, $steps steps$([ "${FEM:-0}" = 1 ] && echo ', tetrahedra')$([ "${MESH:-0}" = 1 ] && echo ", gmsh tetrahedra of $h m from a mesh file")$([ "${SELF:-0}" = 1 ] && echo ', with its self-contact')"
echo "- date: $(date -Iseconds); repository at $(git -C "$root" rev-parse --short HEAD 2>/dev/null); bin: $bin (its commit: each run's first log line)"
echo "- cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), nproc $(nproc --all)"
for n in "${ranks[@]}"; do
  len=$(python3 -c "print(f'{0.03*$n:.4f}')")
  sed -e "s#file = 'output/#file = '$work/#" -e "s/t_end = 4.5e-6/t_end = $(python3 -c "print(f'{15e-9*$steps:.4e}')")/" \
    -e "s/extrude = 0.0, 0.06/extrude = 0.0, $len/" \
    "$root/bench/decks/taylor_bar_3d_rkpm_bench.nml" > "$work/t.nml"
  if [ "${FEM:-0}" = 1 ]; then
    sed -i "s/^  material = 'steel'/  material = 'steel'\n  discretization = 'fem'/" "$work/t.nml"
  fi
  if [ "${MESH:-0}" = 1 ]; then
    "$root/.venv/bin/python" "$root/tools/mesh_body.py" --trusted --3d --set "L=$len" \
      --set "h=$h" "$root/input/taylor_bar_quarter.geo" "$work/bar.hdf5" | sed -e 's/^/  /'
    sed -e "s#file = 'output/#file = '$work/#" -e "s#shape = 'geo'#shape = 'file'#" \
      -e "s#file = 'input/taylor_bar_quarter.geo'#file = '$work/bar.hdf5'#" \
      -e "/geo_names/d" -e "/geo_values/d" \
      -e "s/t_end = 24.0e-6/t_end = $(python3 -c "print(f'{15e-9*$steps:.4e}')")/" \
      -e "s/snapshot_times = .*/snapshot_times = 0.0/" \
      "$root/input/taylor_bar_3d_fem_geo.nml" > "$work/t.nml"
    # (its output under the bench deck's name, which the loop clears)
    sed -i "s#$work/taylor_bar_3d_fem_geo.h5#$work/taylor_bar_3d_rkpm_bench.h5#" "$work/t.nml"
  fi
  if [ "${SELF:-0}" = 1 ]; then
    printf "&contact\n  master = 'bar'\n  slave = 'bar'\n/\n" >> "$work/t.nml"
  fi
  echo "== $n rank(s), bar $len m long"
  rm -f "$work"/mem.* "$work"/taylor_bar_3d_rkpm_bench*
  (cd "$work" && mpiexec --oversubscribe --bind-to none -n "$n" sh -c \
    'exec /usr/bin/time -o "mem.$OMPI_COMM_WORLD_RANK" -f "%M" "$1" t.nml' sh \
    "$bin/mfcd_mpi" > log.txt 2> err.txt) || { tail -5 "$work/err.txt"; exit 1; }
  grep -m1 -E "^mfcd .*\(git " "$work/log.txt" | sed -e 's/^/  /'
  grep -E "body 'bar':.*nodes|summary: [0-9]+ steps|summary: time loop|resident memory|mfcd_mpi: read|facets in rows|facets of the sides|facets near each rank" "$work/log.txt" \
    | sed -e 's/^/  /' -e 's/, material.*kg;/;/'
  for r in $(seq 0 $((n - 1))); do
    printf '  mem rank %d %s kB\n' "$r" "$(cat "$work/mem.$r")"
  done
done
