// mfcd geometry (gmsh): a quarter of a thick-walled tube (radii Ri < Ro, length L, its
// axis on z, its ends at z = 0 and z = L), for unstructured linear tetrahedra of size h
// (input/tube_crush_quarter.nml, the start of issue 24's Fig. 1 case). The straight sides
// lie on the symmetry planes x = 0 and y = 0; the curved sides are fillings of two arcs
// and two straight lines (their Coons patches are the cylinders themselves).
// Parser numbers (&body geo_names, geo_values): Ri, Ro, L, h.
If (!Exists(Ri))
  Ri = 9.25e-3;
EndIf
If (!Exists(Ro))
  Ro = 10.75e-3;
EndIf
If (!Exists(L))
  L = 30.0e-3;
EndIf
If (!Exists(h))
  h = 0.75e-3;
EndIf
Point(1) = {0, 0, 0, h};
Point(2) = {Ri, 0, 0, h};
Point(3) = {Ro, 0, 0, h};
Point(4) = {0, Ro, 0, h};
Point(5) = {0, Ri, 0, h};
Point(6) = {0, 0, L, h};
Point(7) = {Ri, 0, L, h};
Point(8) = {Ro, 0, L, h};
Point(9) = {0, Ro, L, h};
Point(10) = {0, Ri, L, h};
Line(1) = {2, 3};
Circle(2) = {3, 1, 4};
Line(3) = {4, 5};
Circle(4) = {5, 1, 2};
Line(5) = {7, 8};
Circle(6) = {8, 6, 9};
Line(7) = {9, 10};
Circle(8) = {10, 6, 7};
Line(9) = {2, 7};
Line(10) = {3, 8};
Line(11) = {4, 9};
Line(12) = {5, 10};
Curve Loop(1) = {1, 2, 3, 4};        // bottom, z = 0
Curve Loop(2) = {5, 6, 7, 8};        // top, z = L
Curve Loop(3) = {1, 10, -5, -9};     // y = 0
Curve Loop(4) = {3, 12, -7, -11};    // x = 0
Curve Loop(5) = {2, 11, -6, -10};    // outer side
Curve Loop(6) = {4, 9, -8, -12};     // inner side
Plane Surface(1) = {1};
Plane Surface(2) = {2};
Plane Surface(3) = {3};
Plane Surface(4) = {4};
Surface(5) = {5};
Surface(6) = {6};
Surface Loop(1) = {1, 2, 3, 4, 5, 6};
Volume(1) = {1};
