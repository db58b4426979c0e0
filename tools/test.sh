#!/usr/bin/env bash
# Every test: set up what is missing, build Release and run the CTest suite in it (but the
# command-line tests); then one Debug build (-fcheck=all, FPE traps) with the MPI option
# on, and in it the whole suite again (the serial program under the checks) and the MPI
# option's tests.
set -euo pipefail
cd "$(dirname "$0")/.."
# gmsh into .venv: build.sh then builds it in (MFCD_GMSH AUTO), and the decks that mesh a
# .geo in memory (&body shape = 'geo': regression_hertz_impact, _cylinder,
# regression_geo_equivalence, the gmsh cases of cli_bad_decks) run instead of being skipped
# OpenMPI: the distributed-memory option's tests (doc/parallel.md)
bash tools/setup.sh --gmsh --mpi
jobs=$(nproc 2>/dev/null || echo 2)
bash tools/build.sh Release
# (the command-line tests, cli_*: a deck's or a file's refusal, its message and exit code,
# nothing written, a hostile .geo contained; no optimization changes what they check, and
# the Debug stage below runs them all under the bounds checks, where their paths matter:
# 50 s of the Release stage's tests on a 2-core guest, 2026-12-07)
(cd build && ctest --output-on-failure -E '^cli_' -j "$jobs")
# -DMFCD_MPI=ON (off in the Release build above, which so keeps the serial HDF5 library):
# the halo exchange, and whole runs of mfcd_mpi against the serial mfcd, on 1-4 ranks,
# oversubscribed. One Debug build serves both stages (the serial sources are the same with
# the option on: it adds src/parallel and mfcd_mpi, and links HDF5's parallel library): one
# Debug build fewer than a Debug build of its own for the serial suite, some 70 s on a
# 2-core guest (2026-12-08)
cmake -S . -B build-mpi -G Ninja -DCMAKE_BUILD_TYPE=Debug -DMFCD_MPI=ON -DMFCD_GMSH=AUTO \
  -DMFCD_PYTHON="$PWD/.venv/bin/python" >/dev/null
ninja -C build-mpi
# the serial suite first, then the MPI tests apart: an oversubscribed run on ranks beside a
# serial test slows far more than the two share (mpi_run_self_contact_2d: 89 s beside the
# other MPI tests, 312 s beside the serial suite's, 2026-12-08)
(cd build-mpi && ctest --output-on-failure -E '^mpi_' -j "$jobs")
# (two tests at a time: oversubscribed ranks yield when they wait, and one test's serial
# parts, its mfcd run and comparisons, overlap the other's ranks: 299 s against 343 s one
# at a time on a 2-core guest, 2026-11-30)
(cd build-mpi && ctest --output-on-failure -R '^mpi_' -j "$jobs")
