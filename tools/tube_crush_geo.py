"""Writes input/tube_crush.geo: mfcd's .geo subset has no loops or list variables, so the
quarter tube's rings are written out one by one here (python3 tools/tube_crush_geo.py)."""

import sys

NB = 6          # conical segments over the trigger bulge

HEAD = """\
// mfcd geometry (gmsh), written by tools/tube_crush_geo.py: a quarter of a thin-walled
// tube (mean radius R, wall t, length L, its axis on z, its ends at z = 0 and z = L) for
// unstructured linear tetrahedra of size h (input/tube_crush.nml, issue 24's Fig. 1
// case). Its flat sides lie on the symmetry planes y = 0 and x = 0. The trigger: over the
// top 2 H (H about a fold's half-wavelength) the wall bulges outwards, its mid-surface at
// R + a (1 - cos(pi s / H)) / 2 (s = L - z, the wall keeping its thickness), in %d conical
// rings (a Coons patch between two coaxial circles joined by straight lines is the cone
// itself): a small axisymmetric imperfection that starts the first fold at the ram's end
// with an outward lobe, as a concertina fold starts.
// Parser numbers (&body geo_names, geo_values): R, t, L, H, a, h.
If (!Exists(R))
  R = 10.0e-3;
EndIf
If (!Exists(t))
  t = 1.0e-3;
EndIf
If (!Exists(L))
  L = 20.0e-3;
EndIf
If (!Exists(H))
  H = 4.25e-3;
EndIf
If (!Exists(a))
  a = 0.1e-3;
EndIf
If (!Exists(h))
  h = 0.33e-3;
EndIf
""" % NB


def main() -> int:
    out = [HEAD]
    w = out.append
    # levels 0 (z = 0), 1 (z = L - 2H), ..., NB + 1 (z = L); the centre, outer and inner
    # points at y = 0 (x-axis) and at x = 0 (y-axis) of each
    nlev = NB + 2
    for k in range(nlev):
        if k == 0:
            w("z%d = 0;\nw%d = 0;\n" % (k, k))
        else:
            j = k - 1                     # 0 .. NB: s = 2H (NB - j) / NB
            w("s%d = 2 * H * %d / %d;\n" % (k, NB - j, NB))
            w("z%d = L - s%d;\nw%d = a * (1 - Cos(Pi * s%d / H)) / 2;\n" % (k, k, k, k))
        p = 10 * k
        w("Point(%d) = {0, 0, z%d, h};\n" % (p + 1, k))
        w("Point(%d) = {R + t / 2 + w%d, 0, z%d, h};\n" % (p + 2, k, k))
        w("Point(%d) = {0, R + t / 2 + w%d, z%d, h};\n" % (p + 3, k, k))
        w("Point(%d) = {R - t / 2 + w%d, 0, z%d, h};\n" % (p + 4, k, k))
        w("Point(%d) = {0, R - t / 2 + w%d, z%d, h};\n" % (p + 5, k, k))
        # the level's curves: outer arc, inner arc, the two radial lines
        w("Circle(%d) = {%d, %d, %d};\n" % (p + 1, p + 2, p + 1, p + 3))
        w("Circle(%d) = {%d, %d, %d};\n" % (p + 2, p + 4, p + 1, p + 5))
        w("Line(%d) = {%d, %d};\n" % (p + 3, p + 4, p + 2))   # y = 0, inner to outer
        w("Line(%d) = {%d, %d};\n" % (p + 4, p + 5, p + 3))   # x = 0
    surf = []
    # the bottom and top rings (plane)
    w("Curve Loop(1) = {3, 1, -4, -2};\nPlane Surface(1) = {1};\n")
    top = 10 * (nlev - 1)
    w("Curve Loop(2) = {%d, %d, %d, %d};\nPlane Surface(2) = {2};\n"
      % (top + 3, top + 1, -(top + 4), -(top + 2)))
    surf += [1, 2]
    for k in range(nlev - 1):
        p, q = 10 * k, 10 * (k + 1)
        # vertical lines between level k and k + 1: 5 outer-x, 6 outer-y, 7 inner-x, 8 inner-y
        w("Line(%d) = {%d, %d};\n" % (p + 5, p + 2, q + 2))
        w("Line(%d) = {%d, %d};\n" % (p + 6, p + 3, q + 3))
        w("Line(%d) = {%d, %d};\n" % (p + 7, p + 4, q + 4))
        w("Line(%d) = {%d, %d};\n" % (p + 8, p + 5, q + 5))
        s = 100 + 10 * k
        w("Curve Loop(%d) = {%d, %d, %d, %d};\nSurface(%d) = {%d};\n"          # outer
          % (s + 1, p + 1, p + 6, -(q + 1), -(p + 5), s + 1, s + 1))
        w("Curve Loop(%d) = {%d, %d, %d, %d};\nSurface(%d) = {%d};\n"          # inner
          % (s + 2, p + 2, p + 8, -(q + 2), -(p + 7), s + 2, s + 2))
        w("Curve Loop(%d) = {%d, %d, %d, %d};\nPlane Surface(%d) = {%d};\n"    # y = 0
          % (s + 3, p + 3, p + 5, -(q + 3), -(p + 7), s + 3, s + 3))
        w("Curve Loop(%d) = {%d, %d, %d, %d};\nPlane Surface(%d) = {%d};\n"    # x = 0
          % (s + 4, p + 4, p + 6, -(q + 4), -(p + 8), s + 4, s + 4))
        surf += [s + 1, s + 2, s + 3, s + 4]
    w("Surface Loop(1) = {%s};\nVolume(1) = {1};\n" % ", ".join(map(str, surf)))
    path = sys.argv[1] if len(sys.argv) > 1 else "input/tube_crush.geo"
    with open(path, "w") as fh:
        fh.write("".join(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
