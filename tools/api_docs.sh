#!/usr/bin/env bash
# API documentation of mfcd's Fortran modules with FORD (https://forddocs.readthedocs.io),
# from the `!>`/`!!`/`!<` comments in src/; the project file is doc/api.md.
#
#   bash tools/api_docs.sh          # from anywhere; writes output/api/index.html
#
# Installs FORD (PyPI `ford`) into .venv when it is missing there (creating .venv when there
# is none; set MFCD_DOCS_VENV to use another virtual environment). FORD is needed by nothing
# else: the build, the main job and the tests never use it. Exits non-zero when FORD fails
# or reports an error in a source file; its warnings are printed and counted.
set -euo pipefail
cd "$(dirname "$0")/.."

venv=${MFCD_DOCS_VENV:-.venv}
if [ ! -x "$venv/bin/python" ]; then
  echo "api_docs: creating $venv"
  python3 -m venv "$venv"
fi
if ! "$venv/bin/python" -c 'import ford' >/dev/null 2>&1; then
  echo "api_docs: installing ford into $venv"
  "$venv/bin/python" -m pip install -q ford
fi

version=$(sed -n 's/^project(mfcd VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
revision=$(git describe --always --dirty --abbrev=12 2>/dev/null || echo unknown)
log=$(mktemp)
trap 'rm -f "$log"' EXIT
t0=$(date +%s)
# Not --quiet: it would swallow FORD's warnings and errors with its progress bars. The log is
# printed without the progress bars and the "Preprocessing" lines; wide, so no message wraps.
status=0
COLUMNS=200 "$venv/bin/python" -m ford --revision "$revision" --config "version='$version'" \
  doc/api.md > "$log" 2>&1 || status=$?
grep -vE '^(Preprocessing |  |$|Browse the generated)' "$log" || true
if [ "$status" -ne 0 ] || grep -qE '^(ERROR|Error)|Error parsing|Traceback' "$log"; then
  echo "api_docs: error: FORD failed (exit $status); see the messages above" >&2
  exit 1
fi
if [ ! -f output/api/index.html ]; then
  echo "api_docs: error: FORD wrote no output/api/index.html" >&2
  exit 1
fi
warnings=$(grep -c '^Warning' "$log" || true)
echo "api_docs: done in $(($(date +%s) - t0)) s, $warnings warnings: open output/api/index.html"
