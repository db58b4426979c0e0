#!/usr/bin/env bash
# Hertz impact on a rigid wall from a gmsh mesh, by finite elements and by RKPM on the same
# nodes, at three resolutions, against the closed forms (post/hertz_impact.py; results in
# doc/verification.md): an elastic sphere (axisymmetric) and an elastic cylinder (plane
# strain).
#
#   bash tools/hertz.sh            # both; from anywhere; on a fresh clone: sets up gmsh, builds
#   bash tools/hertz.sh sphere     # or: cylinder
#
# Sphere: meshes input/hertz_sphere.geo with tools/mesh_body.py at contact element sizes
# hc = 0.1, 0.05 and 0.025 mm (a/4, a/8 and a/16 of the Hertz contact radius a = 0.40 mm),
# runs input/hertz_sphere_fem.nml and input/hertz_sphere_rkpm.nml on each and writes the
# table output/hertz_sphere.md. Cylinder: input/hertz_cylinder.geo at hc = 0.046, 0.023 and
# 0.0115 mm (b/4, b/8 and b/16 of the contact half-width b = 0.185 mm),
# input/hertz_cylinder_{fem,rkpm}.nml, table output/hertz_cylinder.md. Meshes go to
# output/meshes/, decks (with the mesh file swapped in) and outputs to output/hertz/; the
# tables are printed too. Exits non-zero when a step fails.
set -euo pipefail
cd "$(dirname "$0")/.."
which=${1:-all}
case "$which" in
  all|sphere|cylinder) ;;
  *) echo "usage: bash tools/hertz.sh [sphere|cylinder]" >&2; exit 2 ;;
esac
bash tools/setup.sh --gmsh
[ -x build/bin/mfcd ] || bash tools/build.sh Release
py=.venv/bin/python
mkdir -p output/meshes output/hertz

# run NAME SIZE_SET CONTACT_SET HC...: mesh input/NAME.geo at each contact element size,
# run both decks on it and write output/NAME.md
run() {
  local name=$1 size=$2 zone=$3 hc mesh deck d
  shift 3
  local files=()
  for hc in "$@"; do
    mesh=output/meshes/${name}_hc${hc}.h5
    $py tools/mesh_body.py "input/$name.geo" "$mesh" --set hc=${hc}e-3 --set "$zone"
    for d in fem rkpm; do
      deck=output/hertz/${name}_${d}_hc${hc}.nml
      sed -e "s#output/meshes/${name}_c.h5#$mesh#" \
          -e "s#output/${name}_${d}.h5#output/hertz/${name}_${d}_hc${hc}.h5#" \
          "input/${name}_${d}.nml" > "$deck"
      echo "== mfcd $deck"
      ./build/bin/mfcd "$deck" | grep -E '^(summary: energy|mfcd:)'
      files+=("output/hertz/${name}_${d}_hc${hc}.h5")
    done
  done
  $py post/hertz_impact.py "${files[@]}" --table "output/$name.md"
  echo "hertz: table in output/$name.md ($size)"
}

if [ "$which" != cylinder ]; then
  run hertz_sphere "contact radius a = 0.40 mm" a=0.4e-3 0.1 0.05 0.025
fi
if [ "$which" != sphere ]; then
  run hertz_cylinder "contact half-width b = 0.185 mm" b=0.185e-3 0.046 0.023 0.0115
fi
