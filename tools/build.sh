#!/usr/bin/env bash
# Configures and builds mfcd: tools/build.sh [Release|Debug] [build dir]
# Release goes to build/ (program at build/bin/mfcd), Debug to build-debug/.
set -euo pipefail
cd "$(dirname "$0")/.."
type=${1:-Release}
dir=${2:-build}
[ "$type" = Debug ] && [ -z "${2:-}" ] && dir=build-debug
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE="$type" -DMFCD_PYTHON="$PWD/.venv/bin/python" >/dev/null
ninja -C "$dir"
