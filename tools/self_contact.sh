#!/usr/bin/env bash
# Self-contact: run the five decks with self-contact (&contact master = slave) and their
# controls without it, print how far each run passes through itself, and draw the figures.
#
#   bash tools/self_contact.sh        # from anywhere; on a fresh clone after tools/setup.sh
#
# Builds the Release solver only when build/bin/mfcd is missing (tools/build.sh Release).
# Runs, in this order, each writing output/<deck>.h5:
#   input/c_shape_fold.nml  input/c_shape_fold_free.nml   RKPM C-shape, arms driven together
#   input/ring_crush.nml    input/ring_crush_free.nml     CST4 ring crushed by a ram
#   input/torus_crush.nml   input/torus_crush_free.nml    the same, axisymmetric torus
#   input/c_shape_fold_3d.nml     input/c_shape_fold_3d_free.nml      the C in 3D (4 mm), RKPM
#   input/c_shape_fold_3d_fem.nml input/c_shape_fold_3d_fem_free.nml  the same by tetrahedra
# and prints one line per run from its log (the energy residual and mfcd's closing line;
# the full log is output/<deck>.log), then post/self_overlap.py's table for each run (the
# self-overlap area (3D: volume) and depth of the body at every snapshot: about zero with
# self-contact, growing without), then draws into output/figures/ (git-ignored;
# bash tools/doc_figures.sh copies them into doc/figures/), the plane cases with
# post/plot_self_contact.py, the 3D ones with post/plot_self_contact_3d.py:
#   <case>_shapes.png    deformed shapes with (left) and without (right), overlap in red
#                        (3D: the body seen along z)
#   <case>_det_self.png  (plane) det(M) of the non-neighbour particles where the faces meet
#   <case>_section.png   (3D) the same as _shapes at the body's mid-thickness section
# Set OMP_NUM_THREADS to the cores you own (default: what the OpenMP runtime picks).
# Exits non-zero when the build, a run, a table or a figure fails.
set -euo pipefail
cd "$(dirname "$0")/.."

py=.venv/bin/python
mfcd=build/bin/mfcd
out=output/figures
# case, self-contact body[, 3d: drawn with post/plot_self_contact_3d.py]
cases=("c_shape_fold c" "ring_crush ring" "torus_crush torus"
       "c_shape_fold_3d c 3d" "c_shape_fold_3d_fem c 3d")

if [ ! -x "$py" ]; then
  echo "self_contact: error: $py not found: run bash tools/setup.sh first" >&2
  exit 2
fi
if [ ! -x "$mfcd" ]; then
  echo "== $mfcd missing: bash tools/build.sh Release"
  bash tools/build.sh Release
fi
mkdir -p output "$out"

t0=$(date +%s)
for c in "${cases[@]}"; do
  set -- $c
  for deck in "$1" "$1_free"; do
    echo "== mfcd input/$deck.nml"
    log=output/$deck.log
    if ! "$mfcd" "input/$deck.nml" > "$log" 2>&1; then
      tail -n 20 "$log" >&2
      echo "self_contact: error: mfcd input/$deck.nml failed (log: $log)" >&2
      exit 1
    fi
    if ! grep -E '^(summary: energy|mfcd:)' "$log"; then
      echo "self_contact: error: no summary in $log" >&2
      exit 1
    fi
  done
done
t1=$(date +%s)
echo "== runs: $((t1 - t0)) s"

for c in "${cases[@]}"; do
  set -- $c
  for deck in "$1" "$1_free"; do
    echo "== self-overlap of '$2' in output/$deck.h5 (post/self_overlap.py)"
    "$py" post/self_overlap.py "output/$deck.h5" --body "$2"
  done
done

for c in "${cases[@]}"; do
  set -- $c
  if [ "${3:-}" = 3d ]; then
    echo "== figures $out/$1_shapes.png, $out/$1_section.png"
    "$py" post/plot_self_contact_3d.py "output/$1.h5" "output/$1_free.h5" --body "$2" \
      --out "$out" --format png
  else
    echo "== figures $out/$1_shapes.png, $out/$1_det_self.png"
    "$py" post/plot_self_contact.py "output/$1.h5" "output/$1_free.h5" --body "$2" \
      --out "$out" --format png
  fi
done
echo "self_contact: done in $(($(date +%s) - t0)) s: HDF5 files in output/, figures in $out/"
