#!/usr/bin/env bash
# Draw the figures of doc/examples.md: Example 2.1 (Figs. 2-3) and Example 2.2, convex and
# concave (Figs. 4-7, 11), their 3D counterparts (a box and a C-shaped block), and of doc/verification.md: the elastic stress wave's profiles
# against the closed form and its energy history, from output/*.h5 into output/figures/
# (git-ignored; bash tools/doc_figures.sh copies them into doc/figures/).
#
#   post/make_figures.sh                 # from anywhere; works in the repository root
#   PYTHON=python3 post/make_figures.sh  # another interpreter (default .venv/bin/python)
#   MFCD=build/bin/mfcd                  # the solver used when an output file is missing
#   OUT=DIR post/make_figures.sh         # another figure directory (default output/figures)
#
# An output file that is missing is made first by running its deck input/<name>.nml.
# Exits non-zero when a run or a figure fails.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

PYTHON="${PYTHON:-.venv/bin/python}"
MFCD="${MFCD:-build/bin/mfcd}"
OUT="${OUT:-output/figures}"
examples=(example_2_1 example_2_2 example_2_2_concave example_3d_box example_3d_l_block example_3d_cylinder)
dynamic=(elastic_wave)

if ! command -v "$PYTHON" >/dev/null 2>&1 && [ ! -x "$PYTHON" ]; then
  echo "make_figures: error: Python interpreter '$PYTHON' not found; set PYTHON=... or" \
       "create the venv (python3 -m venv .venv && .venv/bin/pip install -r post/requirements.txt)" >&2
  exit 2
fi

files=()
for name in "${examples[@]}" "${dynamic[@]}"; do
  h5="output/${name}.h5"
  if [ ! -f "$h5" ]; then
    if [ ! -x "$MFCD" ]; then
      echo "make_figures: error: $h5 is missing and the solver '$MFCD' is not built" \
           "(cmake --build build, or set MFCD=...)" >&2
      exit 1
    fi
    echo "make_figures: $h5 missing: running $MFCD input/${name}.nml"
    "$MFCD" "input/${name}.nml" > /dev/null
  fi
  files+=("$h5")
done

mkdir -p "$OUT"
"$PYTHON" post/plot_detection.py "${files[@]:0:${#examples[@]}}" --out "$OUT" --format png
# elastic wave: <stem>_profiles (closed form) and <stem>_energy (history)
"$PYTHON" post/plot_wave.py output/elastic_wave.h5 --out "$OUT" --format png
"$PYTHON" post/plot_snapshots.py output/elastic_wave.h5 --out "$OUT" --format png \
  --history --no-snapshots
echo "make_figures: figures in $OUT"
