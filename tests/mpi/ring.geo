// mfcd geometry (gmsh): a ring of radii ri < ro centred at the origin, element size h, for
// the ring crushed onto itself read per part on ranks (tests/mpi/ring_crush_geo.nml).
// Parser numbers (&body geo_names / geo_values): ri, ro, h.
If (!Exists(ri))
  ri = 8.0e-3;
EndIf
If (!Exists(ro))
  ro = 10.0e-3;
EndIf
If (!Exists(h))
  h = 1.0e-3;
EndIf
Point(1) = {0, 0, 0, h};
Point(2) = {ro, 0, 0, h};
Point(3) = {0, ro, 0, h};
Point(4) = {-ro, 0, 0, h};
Point(5) = {0, -ro, 0, h};
Point(6) = {ri, 0, 0, h};
Point(7) = {0, ri, 0, h};
Point(8) = {-ri, 0, 0, h};
Point(9) = {0, -ri, 0, h};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};
Circle(4) = {5, 1, 2};
Circle(5) = {6, 1, 7};
Circle(6) = {7, 1, 8};
Circle(7) = {8, 1, 9};
Circle(8) = {9, 1, 6};
Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2};
