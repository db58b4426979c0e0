#!/usr/bin/env bash
# Every test: set up what is missing, build Release and Debug (-fcheck=all, FPE traps),
# and run the whole CTest suite in both.
set -euo pipefail
cd "$(dirname "$0")/.."
# gmsh into .venv: build.sh then builds it in (MFCD_GMSH AUTO), and the decks that mesh a
# .geo in memory (&body shape = 'geo': regression_hertz_impact, _cylinder,
# regression_geo_equivalence, the gmsh cases of cli_bad_decks) run instead of being skipped
bash tools/setup.sh --gmsh
jobs=$(nproc 2>/dev/null || echo 2)
bash tools/build.sh Release
(cd build && ctest --output-on-failure -j "$jobs")
bash tools/build.sh Debug
(cd build-debug && ctest --output-on-failure -j "$jobs")
