#!/usr/bin/env bash
# Hertz impact on a rigid wall from a gmsh mesh, by finite elements and by RKPM on the same
# nodes, at three resolutions, against the closed forms (post/hertz_impact.py; results in
# doc/verification.md): an elastic sphere (axisymmetric) and an elastic cylinder (plane
# strain); and the sphere in full 3D (doc/3d.md).
#
#   bash tools/hertz.sh            # sphere and cylinder; from anywhere; on a fresh clone:
#                                  # sets up gmsh, builds
#   bash tools/hertz.sh sphere     # or: cylinder, or sphere3d
#
# Sphere: runs input/hertz_sphere_fem.nml and input/hertz_sphere_rkpm.nml, which mesh
# input/hertz_sphere.geo themselves (&body shape = 'geo'), at contact element sizes
# hc = 0.1, 0.05 and 0.025 mm (a/4, a/8 and a/16 of the Hertz contact radius a = 0.40 mm),
# and writes the table output/hertz_sphere.md. Cylinder: input/hertz_cylinder_{fem,rkpm}.nml
# (input/hertz_cylinder.geo) at hc = 0.046, 0.023 and 0.0115 mm (b/4, b/8 and b/16 of the
# contact half-width b = 0.185 mm), table output/hertz_cylinder.md. The decks, with hc (the
# first of their geo_values) and the output file swapped in, and the outputs go to
# output/hertz/; the tables are printed too. Sphere in 3D (sphere3d, not part of the default
# run: about 40 minutes on 2 cores): input/hertz_sphere_3d.nml (linear tetrahedra of
# input/hertz_sphere_3d.geo) and input/hertz_sphere_3d_rkpm.nml (RKPM on their nodes)
# beside the axisymmetric input/hertz_sphere_fem.nml, at
# hc = 0.2, 0.133 and 0.1 mm (a/2, a/3, a/4), table output/hertz_sphere_3d.md. No mesh
# file is written. Exits non-zero when a step fails.
set -euo pipefail
cd "$(dirname "$0")/.."
which=${1:-all}
case "$which" in
  all|sphere|cylinder|sphere3d) ;;
  *) echo "usage: bash tools/hertz.sh [sphere|cylinder|sphere3d]" >&2; exit 2 ;;
esac
bash tools/setup.sh --gmsh
# a build from before gmsh was installed has it not: build again (AUTO finds it now)
if ! { [ -x build/bin/mfcd ] && ./build/bin/mfcd --version | grep -q '^gmsh 4'; }; then
  bash tools/build.sh Release
fi
if ! ./build/bin/mfcd --version | grep -q '^gmsh 4'; then
  echo "hertz: build/bin/mfcd is built without gmsh (see the configure message above)" >&2
  exit 1
fi
py=.venv/bin/python
mkdir -p output/hertz

# run TABLE SIZE "DECK..." HC...: run each deck input/DECK.nml (which meshes its own .geo) at
# each contact element size hc (mm), the first of its geo_values, and write output/TABLE.md
run() {
  local table=$1 size=$2 decks=$3 hc deck d
  shift 3
  local files=()
  for hc in "$@"; do
    for d in $decks; do
      deck=output/hertz/${d}_hc${hc}.nml
      sed -e "s#^\(  geo_values = \)[^,]*,#\1${hc}e-3,#" \
          -e "s#output/${d}.h5#output/hertz/${d}_hc${hc}.h5#" \
          "input/${d}.nml" > "$deck"
      grep -q "^  geo_values = ${hc}e-3," "$deck" || {
        echo "hertz: input/${d}.nml: no '  geo_values = hc, ...' line to set" >&2
        exit 1
      }
      echo "== mfcd $deck"
      ./build/bin/mfcd "$deck" | grep -E '^(summary: (energy|[0-9]+ steps)|mfcd:)'
      files+=("output/hertz/${d}_hc${hc}.h5")
    done
  done
  $py post/hertz_impact.py "${files[@]}" --table "output/$table.md"
  echo "hertz: table in output/$table.md ($size)"
}

if [ "$which" = all ] || [ "$which" = sphere ]; then
  run hertz_sphere "contact radius a = 0.40 mm" "hertz_sphere_fem hertz_sphere_rkpm" \
    0.1 0.05 0.025
fi
if [ "$which" = all ] || [ "$which" = cylinder ]; then
  run hertz_cylinder "contact half-width b = 0.185 mm" \
    "hertz_cylinder_fem hertz_cylinder_rkpm" 0.046 0.023 0.0115
fi
if [ "$which" = sphere3d ]; then
  run hertz_sphere_3d "contact radius a = 0.40 mm, full 3D" \
    "hertz_sphere_3d hertz_sphere_3d_rkpm hertz_sphere_fem" 0.2 0.133 0.1
  # the force histories of doc/3d.md's figure
  $py post/hertz_impact.py output/hertz/hertz_sphere_3d_hc0.2.h5 \
    output/hertz/hertz_sphere_3d_rkpm_hc0.2.h5 output/hertz/hertz_sphere_3d_rkpm_hc0.1.h5 \
    --plot doc/figures/hertz_sphere_3d_force.png \
    --labels "tetrahedra, a/2" "RKPM, a/2" "RKPM, a/4" > /dev/null
  echo "hertz: figure doc/figures/hertz_sphere_3d_force.png"
fi
