#!/usr/bin/env bash
# The tube crush (issue 24, the paper's Fig. 1 case): run the fine quarter tube with
# self-contact and its control without it, check them and draw the figures.
#
#   bash tools/tube_crush.sh           # from anywhere; on a fresh clone after tools/setup.sh
#                                      # --gmsh (the tube is a gmsh script meshed in memory)
#   bash tools/tube_crush.sh coarse    # the CI case instead (input/tube_crush_coarse.nml,
#                                      # no self-contact: post/tube_crush.py --control-only)
#
# Builds the Release solver only when build/bin/mfcd is missing (tools/build.sh Release).
# Runs input/tube_crush.nml and input/tube_crush_free.nml (about 60 and 20 minutes on one core of
# an Intel Xeon guest shared with other runs: doc/self_contact.md), each writing
# output/<deck>.h5 and its log output/<deck>.log, prints the energy line of each log,
# then post/tube_crush.py: the crush force against the ram's displacement and its mean
# against Abramowicz & Jones's estimate, the folds, the overlap with and without
# self-contact, the energy balance, each check with ok or FAIL, and the figures in
# output/figures/ (git-ignored; copy them into doc/figures/):
#   tube_crush_force.png     the crush force, its mean and the estimates
#   tube_crush_shapes.png    the deformed tube (half of it) at four times
#   tube_crush_section.png   the wall in the plane y = 0, with and without self-contact
# Set OMP_NUM_THREADS to the cores you own (default: what the OpenMP runtime picks).
# Exits non-zero when the build, a run or a check fails.
set -euo pipefail
cd "$(dirname "$0")/.."

py=.venv/bin/python
mfcd=build/bin/mfcd
out=output/figures
case=tube_crush
args=()
decks=("$case" "${case}_free")
if [ "${1:-}" = coarse ]; then
  case=tube_crush_coarse
  decks=("$case")
  args=(--control-only --min-folds 1)
fi

if [ ! -x "$py" ]; then
  echo "tube_crush: error: $py not found: run bash tools/setup.sh --gmsh first" >&2
  exit 2
fi
if [ ! -x "$mfcd" ]; then
  echo "== $mfcd missing: bash tools/build.sh Release"
  bash tools/build.sh Release
fi
mkdir -p output "$out"

t0=$(date +%s)
for deck in "${decks[@]}"; do
  echo "== mfcd input/$deck.nml"
  log=output/$deck.log
  t1=$(date +%s)
  if ! "$mfcd" "input/$deck.nml" > "$log" 2>&1; then
    tail -n 20 "$log" >&2
    echo "tube_crush: error: mfcd input/$deck.nml failed (log: $log)" >&2
    exit 1
  fi
  grep -E '^(summary: energy|mfcd:)' "$log"
  echo "== $deck: $(($(date +%s) - t1)) s"
done

echo "== post/tube_crush.py"
files=()
for deck in "${decks[@]}"; do files+=("output/$deck.h5"); done
"$py" post/tube_crush.py "${files[@]}" --out "$out" --name "$case" "${args[@]}"
echo "tube_crush: done in $(($(date +%s) - t0)) s: HDF5 files in output/, figures in $out/"
