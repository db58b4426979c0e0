#!/usr/bin/env bash
# The paper's Taylor bar in 3D (a quarter with symmetry planes) beside the axisymmetric run
# at the same spacing, then the figure and the table of post/plot_taylor_3d.py
# (output/figures/; doc/3d.md). Long runs, not part of the tests (regression_taylor_3d and
# regression_taylor_3d_fem check the 1 mm pairs).
#
#   bash tools/taylor_3d.sh          # RKPM at 1/3 mm: input/taylor_bar_3d_rkpm.nml (37,467
#                                    # particles) and input/taylor_bar_rkpm_coarse.nml; a few
#                                    # minutes on two cores
#   bash tools/taylor_3d.sh sixth    # RKPM at the paper's 1/6 mm:
#                                    # input/taylor_bar_3d_rkpm_sixth.nml (276,526 particles,
#                                    # about 20 GB) and input/taylor_bar_rkpm.nml; about 40
#                                    # minutes on two cores
#   bash tools/taylor_3d.sh fem      # gmsh's unstructured tetrahedra at 0.5 mm
#                                    # (input/taylor_bar_3d_fem_geo.nml with h = 0.5 mm) and
#                                    # CST4 at 0.5 mm (input/taylor_bar_fem_1mm.nml with its
#                                    # lattices halved); about 5 minutes
#
# From anywhere; on a fresh clone it sets up and builds first (fem: with gmsh). The decks
# that are not in input/ as they run are written to output/taylor_3d/ (sed of the inputs).
set -euo pipefail
cd "$(dirname "$0")/.."
which=${1:-third}
case "$which" in
  third|sixth|fem) ;;
  *) echo "usage: bash tools/taylor_3d.sh [third|sixth|fem]" >&2; exit 2 ;;
esac
if [ "$which" = fem ]; then
  bash tools/setup.sh --gmsh
  if ! { [ -x build/bin/mfcd ] && ./build/bin/mfcd --version | grep -q '^gmsh 4'; }; then
    bash tools/build.sh Release
  fi
else
  bash tools/setup.sh
  [ -x build/bin/mfcd ] || bash tools/build.sh Release
fi
mkdir -p output/taylor_3d
run() {
  ./build/bin/mfcd "$1" | grep -E '^(summary|mfcd)'
}
case "$which" in
  third)
    run input/taylor_bar_3d_rkpm.nml
    run input/taylor_bar_rkpm_coarse.nml
    a=output/taylor_bar_3d_rkpm.h5 b=output/taylor_bar_rkpm_coarse.h5 name=taylor_3d_third_mm
    ;;
  sixth)
    run input/taylor_bar_3d_rkpm_sixth.nml
    run input/taylor_bar_rkpm.nml
    a=output/taylor_bar_3d_rkpm_sixth.h5 b=output/taylor_bar_rkpm.h5 name=taylor_3d_sixth_mm
    ;;
  fem)
    sed -e "s#^\(  geo_values = \)[^ ]*#\10.5e-3#" -e "s#^  spacing = 0.001 #  spacing = 0.0005 #" \
        -e "s#^  n = 15, 15, 5#  n = 29, 29, 9#" \
        -e "s#output/taylor_bar_3d_fem_geo.h5#output/taylor_3d/fem_geo_half_mm.h5#" \
        input/taylor_bar_3d_fem_geo.nml > output/taylor_3d/fem_geo_half_mm.nml
    sed -e "s#^  n = 6, 61#  n = 11, 121#" -e "s#^  n = 76, 6#  n = 151, 11#" \
        -e "s#output/taylor_bar_fem_1mm.h5#output/taylor_3d/cst4_half_mm.h5#" \
        input/taylor_bar_fem_1mm.nml > output/taylor_3d/cst4_half_mm.nml
    for f in output/taylor_3d/fem_geo_half_mm.nml output/taylor_3d/cst4_half_mm.nml; do
      grep -q "taylor_3d/" "$f" || { echo "taylor_3d: $f: the output line was not set" >&2; exit 1; }
    done
    grep -q "^  geo_values = 0.5e-3" output/taylor_3d/fem_geo_half_mm.nml
    grep -q "^  n = 11, 121" output/taylor_3d/cst4_half_mm.nml
    run output/taylor_3d/fem_geo_half_mm.nml
    run output/taylor_3d/cst4_half_mm.nml
    a=output/taylor_3d/fem_geo_half_mm.h5 b=output/taylor_3d/cst4_half_mm.h5
    name=taylor_3d_fem_half_mm
    ;;
esac
.venv/bin/python post/plot_taylor_3d.py "$a" "$b" --out output/figures --name "$name"
