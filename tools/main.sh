#!/usr/bin/env bash
# The main job: set up what is missing, build, run the paper's Taylor bar by RKPM
# (input/taylor_bar_rkpm.nml) and draw its figures (Figs. 9, 10 and 14, contact and energy
# histories), the FEM twin at the paper's mesh on the adaptive, subcycled step (Fig. 15,
# RKPM beside FEM), plus the Section 2 examples (Figs. 2-7, 11).
# Output: output/*.h5 (+ .xdmf for ParaView) and output/figures/ (PNG files and the RKPM-FEM
# table taylor_comparison_cfl.md). It writes nothing in the repository's tracked files: the
# committed copies in doc/figures/ are refreshed by bash tools/doc_figures.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
bash tools/build.sh Release
echo "== mfcd input/taylor_bar_rkpm.nml"
./build/bin/mfcd input/taylor_bar_rkpm.nml | grep -v '^deck| '
py=.venv/bin/python
figs=output/figures
$py post/plot_taylor.py output/taylor_bar_rkpm.h5 --out $figs
$py post/plot_snapshots.py output/taylor_bar_rkpm.h5 --out $figs --snapshots 0002,0003,0004,0005 --history
$py post/plot_snapshots.py output/taylor_bar_rkpm.h5 --out $figs --snapshots 0002,0003,0004,0005 \
  --mirror --vmax 2.0 --window=-0.012,0.012,-0.003,0.012 --suffix _foot
# The FEM twin (CST4, Fig. 15) at the paper's mesh, on the default time step (cfl 0.5 of the
# critical step, which follows the deformation) with the flattened elements at the lip
# subcycled (3,242 steps against the paper's fixed 38,400 of input/taylor_bar_fem.nml, which
# makes the main job longer than 3 minutes), then RKPM beside FEM (doc/taylor.md).
echo "== mfcd input/taylor_bar_fem_cfl.nml"
./build/bin/mfcd input/taylor_bar_fem_cfl.nml | grep -E '^(summary|mfcd)'
$py post/plot_fem.py output/taylor_bar_fem_cfl.h5 --out $figs
$py post/compare_taylor.py output/taylor_bar_rkpm.h5 output/taylor_bar_fem_cfl.h5 \
  --out $figs --name taylor_rkpm_vs_fem_cfl --table $figs/taylor_comparison_cfl.md
PYTHON=$py OUT=$figs bash post/make_figures.sh
echo "main: done. HDF5 files in output/, figures in $figs/"
