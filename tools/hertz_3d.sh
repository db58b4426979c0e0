#!/usr/bin/env bash
# Hertz impact of an elastic sphere on a rigid wall in full 3D (linear tetrahedra with
# averaged nodal pressure, meshed by gmsh in memory from input/hertz_sphere_3d.geo), at
# three contact element sizes, against the closed forms (post/hertz_impact.py; results in
# doc/verification.md), and the axisymmetric FEM run (input/hertz_sphere_fem.nml) at the
# same sizes beside it.
#
#   bash tools/hertz_3d.sh          # from anywhere; on a fresh clone: sets up gmsh, builds
#
# hc = 0.2, 0.133 and 0.1 mm (a/2, a/3 and a/4 of the Hertz contact radius a = 0.40 mm):
# the decks with hc (the first of their geo_values) and the output file swapped in, and
# the outputs, go to output/hertz_3d/; the table output/hertz_sphere_3d.md is printed too.
# About 20 minutes on 2 cores (the a/4 run: 12,800 nodes, 71,000 tetrahedra, 5,900 steps).
# No mesh file is written. Exits non-zero when a step fails.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh --gmsh
# a build from before gmsh was installed has it not: build again (AUTO finds it now)
if ! { [ -x build/bin/mfcd ] && ./build/bin/mfcd --version | grep -q '^gmsh 4'; }; then
  bash tools/build.sh Release
fi
if ! ./build/bin/mfcd --version | grep -q '^gmsh 4'; then
  echo "hertz_3d: build/bin/mfcd is built without gmsh (see the configure message above)" >&2
  exit 1
fi
py=.venv/bin/python
mkdir -p output/hertz_3d
files3=()
files2=()
for hc in 0.2 0.133 0.1; do
  for d in hertz_sphere_3d hertz_sphere_fem; do
    deck=output/hertz_3d/${d}_hc${hc}.nml
    sed -e "s#^\(  geo_values = \)[^,]*,#\1${hc}e-3,#" \
        -e "s#output/${d}.h5#output/hertz_3d/${d}_hc${hc}.h5#" \
        "input/${d}.nml" > "$deck"
    grep -q "^  geo_values = ${hc}e-3," "$deck" || {
      echo "hertz_3d: input/${d}.nml: no '  geo_values = hc, ...' line to set" >&2
      exit 1
    }
    echo "== mfcd $deck"
    ./build/bin/mfcd "$deck" | grep -E '^(summary: (energy|[0-9]+ steps)|mfcd:)'
  done
  files3+=("output/hertz_3d/hertz_sphere_3d_hc${hc}.h5")
  files2+=("output/hertz_3d/hertz_sphere_fem_hc${hc}.h5")
done
$py post/hertz_impact.py "${files3[@]}" "${files2[@]}" --table output/hertz_sphere_3d.md
echo "hertz_3d: table in output/hertz_sphere_3d.md"
