#!/usr/bin/env bash
# The main job: set up what is missing, build, run the example decks, draw their figures.
# Output: output/*.h5 and doc/figures/*.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
bash tools/build.sh Release
for deck in example_2_1 example_2_2 example_2_2_concave; do
  echo "== mfcd input/$deck.nml"
  ./build/bin/mfcd "input/$deck.nml" | grep -v '^deck| '
done
PYTHON=.venv/bin/python bash post/make_figures.sh
echo "main: done. HDF5 files in output/, figures in doc/figures/"
