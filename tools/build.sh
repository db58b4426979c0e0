#!/usr/bin/env bash
# Configures and builds mfcd: tools/build.sh [Release|Debug] [build dir]
# Release goes to build/ (program at build/bin/mfcd), Debug to build-debug/. gmsh's API
# (&body shape = 'geo') is built in when .venv has it (bash tools/setup.sh --gmsh): MFCD_GMSH
# is AUTO, looking under MFCD_GMSH_ROOT = .venv.
set -euo pipefail
cd "$(dirname "$0")/.."
type=${1:-Release}
dir=${2:-build}
[ "$type" = Debug ] && [ -z "${2:-}" ] && dir=build-debug
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE="$type" -DMFCD_PYTHON="$PWD/.venv/bin/python" \
  -DMFCD_GMSH_ROOT="$PWD/.venv" | { grep '^-- mfcd: ' || true; }
ninja -C "$dir"
