#!/usr/bin/env bash
# The paper's Taylor bar in 3D at 1/3 mm (a quarter with symmetry planes, about 37,000
# particles: input/taylor_bar_3d_rkpm.nml) beside the axisymmetric run at the same spacing
# (input/taylor_bar_rkpm_coarse.nml), then the figure and the table of post/plot_taylor_3d.py
# (output/figures/taylor_3d_third_mm.png; doc/3d.md). A few minutes on two cores: a long run,
# not part of the tests (regression_taylor_3d checks the 1 mm pair).
#
#   bash tools/taylor_3d.sh        # from anywhere; on a fresh clone: sets up and builds first
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
[ -x build/bin/mfcd ] || bash tools/build.sh Release
./build/bin/mfcd input/taylor_bar_3d_rkpm.nml | grep -E '^(summary|mfcd)'
./build/bin/mfcd input/taylor_bar_rkpm_coarse.nml | grep -E '^(summary|mfcd)'
.venv/bin/python post/plot_taylor_3d.py output/taylor_bar_3d_rkpm.h5 \
  output/taylor_bar_rkpm_coarse.h5 --out output/figures --name taylor_3d_third_mm
