#!/usr/bin/env bash
# Hertz impact of an elastic sphere on a rigid wall (axisymmetric), from a gmsh mesh, by
# finite elements and by RKPM on the same nodes, at three resolutions, against the closed
# forms (post/hertz_impact.py; results in doc/verification.md).
#
#   bash tools/hertz.sh          # from anywhere; on a fresh clone: sets up gmsh, builds
#
# Meshes input/hertz_sphere.geo with tools/mesh_body.py at contact element sizes hc =
# 0.1, 0.05 and 0.025 mm (a/4, a/8 and a/16 of the Hertz contact radius a = 0.40 mm) into
# output/meshes/, runs input/hertz_sphere_fem.nml and input/hertz_sphere_rkpm.nml on each
# (decks written to output/hertz/ with the mesh file swapped in), and prints and writes the
# table output/hertz_sphere.md. Exits non-zero when a step fails.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh --gmsh
[ -x build/bin/mfcd ] || bash tools/build.sh Release
py=.venv/bin/python
mkdir -p output/meshes output/hertz
files=()
for hc in 0.1 0.05 0.025; do
  mesh=output/meshes/hertz_sphere_hc${hc}.h5
  $py tools/mesh_body.py input/hertz_sphere.geo "$mesh" --set hc=${hc}e-3 --set a=0.4e-3
  for d in fem rkpm; do
    deck=output/hertz/hertz_sphere_${d}_hc${hc}.nml
    sed -e "s#output/meshes/hertz_sphere_c.h5#$mesh#" \
        -e "s#output/hertz_sphere_${d}.h5#output/hertz/hertz_sphere_${d}_hc${hc}.h5#" \
        "input/hertz_sphere_${d}.nml" > "$deck"
    echo "== mfcd $deck"
    ./build/bin/mfcd "$deck" | grep -E '^(summary: energy|mfcd:)'
    files+=("output/hertz/hertz_sphere_${d}_hc${hc}.h5")
  done
done
$py post/hertz_impact.py "${files[@]}" --table output/hertz_sphere.md
echo "hertz: table in output/hertz_sphere.md"
