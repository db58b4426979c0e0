#!/usr/bin/env bash
# Every test: set up what is missing, build Release and Debug (-fcheck=all, FPE traps),
# and run the whole CTest suite in both.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh --gmsh   # gmsh: the mesh-built bodies of regression_hertz_impact and _cylinder
jobs=$(nproc 2>/dev/null || echo 2)
bash tools/build.sh Release
(cd build && ctest --output-on-failure -j "$jobs")
bash tools/build.sh Debug
(cd build-debug && ctest --output-on-failure -j "$jobs")
