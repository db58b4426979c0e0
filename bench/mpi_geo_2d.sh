#!/usr/bin/env bash
# A plane gmsh script on ranks (doc/parallel.md, "Plane gmsh scripts meshed once for the
# ranks"): the disk of input/disk_plate_fine.nml (RKPM over the mesh's median-dual cells)
# meshed at H (default 0.04 mm: some 60,000 nodes) striking the plate at 1/8 mm, a few
# steps, on each rank count given, one thread a rank. Prints, per run, the log's gmsh lines,
# the summary's set-up and time-loop seconds, mfcd_mpi's resident memory after the set-up
# and at the end (the smallest and largest over the ranks), and every rank's peak resident
# memory (GNU time's %M). Run it with the builds before and after a change to compare them.
# With BODY=cylinder: the cylinder of input/hertz_cylinder_fem.nml (linear triangles, a
# slave of the rigid wall: read per part on ranks since 2026-12-07, tri_file_m) meshed
# uniformly at H (hc = hf = H; 0.04 mm: some 50,000 nodes) instead of the disk; with
# BODY=cylinder_rkpm the same cylinder by RKPM over its median-dual cells
# (input/hertz_cylinder_rkpm.nml). With BODY=cylinder_file the same cylinder's triangles
# meshed once by tools/mesh_body.py into a particle file the deck reads (&body shape =
# 'file': a user's file, read per part on ranks since 2026-12-08; the meshing not timed).
# Usage: [H=metres] [BODY=disk|cylinder|cylinder_rkpm|cylinder_file] bash bench/mpi_geo_2d.sh MPI_BIN_DIR [RANKS ...]
# (default ranks 1 2 4)
# More ranks than cores run oversubscribed: the memory holds, the set-up's seconds are then
# the ranks sharing a core.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bin=$(cd "$1" && pwd)
shift
ranks=("$@")
[ ${#ranks[@]} -gt 0 ] || ranks=(1 2 4)
[ -x /usr/bin/time ] || { echo "mpi_geo_2d: needs GNU time (apt-get install time)" >&2; exit 2; }
h=${H:-0.04e-3}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
body=${BODY:-disk}
if [ "$body" = cylinder_file ]; then
  "$root/.venv/bin/python" "$root/tools/mesh_body.py" --trusted --set "hc=$h" --set "hf=$h" \
    --set b=0.185e-3 "$root/input/hertz_cylinder.geo" "$work/cylinder.hdf5" | sed -e 's/^/# /'
  sed -e "s#file = 'output/#file = '$work/#" \
    -e "s#shape = 'geo'#shape = 'file'#" \
    -e "s#file = 'input/hertz_cylinder.geo'#file = '$work/cylinder.hdf5'#" \
    -e '/geo_names/d' -e '/geo_values/d' \
    -e 's/t_end = 12.0e-6/t_end = 2.0e-8/' \
    "$root/input/hertz_cylinder_fem.nml" > "$work/t.nml"
  what="the cylinder of hertz_cylinder_fem.nml from a particle file"
elif [ "$body" = cylinder ] || [ "$body" = cylinder_rkpm ]; then
  deck=hertz_cylinder_fem
  [ "$body" = cylinder ] || deck=hertz_cylinder_rkpm
  cp "$root/input/hertz_cylinder.geo" "$work/"
  sed -e "s#file = 'output/#file = '$work/#" \
    -e "s#file = 'input/hertz_cylinder.geo'#file = '$work/hertz_cylinder.geo'#" \
    -e "s/geo_names = 'hc', 'b'/geo_names = 'hc', 'hf', 'b'/" \
    -e "s/geo_values = 0.046e-3, 0.185e-3/geo_values = $h, $h, 0.185e-3\n  geo_max_elements = 10000000/" \
    -e 's/t_end = 12.0e-6/t_end = 2.0e-8/' \
    "$root/input/$deck.nml" > "$work/t.nml"
  what="the cylinder of $deck.nml"
else
  cp "$root/input/disk.geo" "$work/"
  sed -e "s#file = 'output/#file = '$work/#" -e "s#file = 'input/disk.geo'#file = '$work/disk.geo'#" \
    -e "s/geo_values = 0.125e-3/geo_values = $h\n  geo_max_elements = 10000000/" \
    -e 's/t_end = 40.0e-6/t_end = 2.0e-8/' -e '/snapshot_times/d' \
    "$root/input/disk_plate_fine.nml" > "$work/t.nml"
  what="the disk of disk_plate_fine.nml"
fi
grep -q -e "geo_values = $h" -e "cylinder.hdf5" "$work/t.nml" ||
  { echo "mpi_geo_2d: the deck was not resized" >&2; exit 1; }
echo "# mfcd_mpi: $what meshed by gmsh at h = $h m, t_end 2e-8 s"
echo "- date: $(date -Iseconds); repository at $(git -C "$root" rev-parse --short HEAD 2>/dev/null); bin: $bin (its commit: each run's first log line)"
echo "- cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), nproc $(nproc --all)"
for n in "${ranks[@]}"; do
  echo "== $n rank(s)"
  rm -f "$work"/mem.*
  (cd "$work" && mpiexec --oversubscribe --bind-to none -n "$n" sh -c \
    'exec /usr/bin/time -o "mem.$OMPI_COMM_WORLD_RANK" -f "%M" "$1" t.nml' sh \
    "$bin/mfcd_mpi" > log.txt 2> err.txt) || { tail -5 "$work/err.txt"; exit 1; }
  grep -m1 -E "^mfcd .*\(git " "$work/log.txt" | sed -e 's/^/  /'
  grep -E "gmsh|facts|made per rank|summary: [0-9]+ steps|resident memory" "$work/log.txt" | cut -c1-220 | sed -e 's/^/  /'
  for r in $(seq 0 $((n - 1))); do
    printf '  mem rank %d %s kB\n' "$r" "$(cat "$work/mem.$r")"
  done
done
