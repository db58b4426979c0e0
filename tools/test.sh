#!/usr/bin/env bash
# Every test: set up what is missing, build Release and Debug (-fcheck=all, FPE traps),
# and run the whole CTest suite in both; then the MPI option's tests in a Debug MPI build.
set -euo pipefail
cd "$(dirname "$0")/.."
# gmsh into .venv: build.sh then builds it in (MFCD_GMSH AUTO), and the decks that mesh a
# .geo in memory (&body shape = 'geo': regression_hertz_impact, _cylinder,
# regression_geo_equivalence, the gmsh cases of cli_bad_decks) run instead of being skipped
# OpenMPI: the distributed-memory option's tests (doc/parallel.md), in a build of their own
bash tools/setup.sh --gmsh --mpi
jobs=$(nproc 2>/dev/null || echo 2)
bash tools/build.sh Release
(cd build && ctest --output-on-failure -j "$jobs")
bash tools/build.sh Debug
(cd build-debug && ctest --output-on-failure -j "$jobs")
# -DMFCD_MPI=ON (off in the builds above): the halo exchange, and whole runs of mfcd_mpi
# against the serial mfcd, on 1-4 ranks, oversubscribed
cmake -S . -B build-mpi -G Ninja -DCMAKE_BUILD_TYPE=Debug -DMFCD_MPI=ON -DMFCD_GMSH=AUTO \
  -DMFCD_PYTHON="$PWD/.venv/bin/python" >/dev/null
ninja -C build-mpi halo_check mfcd mfcd_mpi
# (two tests at a time: oversubscribed ranks yield when they wait, and one test's serial
# parts, its mfcd run and comparisons, overlap the other's ranks: 299 s against 343 s one
# at a time on a 2-core guest, 2026-11-30)
(cd build-mpi && ctest --output-on-failure -R '^mpi_' -j "$jobs")
