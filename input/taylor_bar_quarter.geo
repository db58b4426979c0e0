// mfcd geometry (gmsh): a quarter of the Taylor bar (radius R, length L; the sector
// 0 <= theta <= 90 degrees of the cylinder, its axis on z, its impact face at z = 0), for
// unstructured linear tetrahedra of size h (input/taylor_bar_3d_fem_geo.nml). The
// straight sides lie on the symmetry planes x = 0 and y = 0 (the deck holds the normal
// velocity there). The curved side is a filling of two arcs and two straight lines: its
// Coons patch is the cylinder itself.
// Parser numbers (&body geo_names, geo_values): R, L, h.
If (!Exists(R))
  R = 5.0e-3;
EndIf
If (!Exists(L))
  L = 60.0e-3;
EndIf
If (!Exists(h))
  h = 1.0e-3;
EndIf
Point(1) = {0, 0, 0, h};
Point(2) = {R, 0, 0, h};
Point(3) = {0, R, 0, h};
Point(4) = {0, 0, L, h};
Point(5) = {R, 0, L, h};
Point(6) = {0, R, L, h};
Line(1) = {1, 2};
Circle(2) = {2, 1, 3};
Line(3) = {3, 1};
Line(4) = {4, 5};
Circle(5) = {5, 4, 6};
Line(6) = {6, 4};
Line(7) = {1, 4};
Line(8) = {2, 5};
Line(9) = {3, 6};
Curve Loop(1) = {1, 2, 3};          // bottom, z = 0
Curve Loop(2) = {4, 5, 6};          // top, z = L
Curve Loop(3) = {1, 8, -4, -7};     // y = 0
Curve Loop(4) = {-3, 9, 6, -7};     // x = 0
Curve Loop(5) = {2, 9, -5, -8};     // the curved side
Plane Surface(1) = {1};
Plane Surface(2) = {2};
Plane Surface(3) = {3};
Plane Surface(4) = {4};
Surface(5) = {5};
Surface Loop(1) = {1, 2, 3, 4, 5};
Volume(1) = {1};
