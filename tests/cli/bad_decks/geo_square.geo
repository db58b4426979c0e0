// A unit square meshed with triangles of size h (the bad decks' gmsh script). The size
// comes from a Box field, as in input/hertz_*.geo, so that gmsh refuses h <= 0 (a point's
// size of 0 would mean "unset" to gmsh).
If (!Exists(h))
  h = 0.25;
EndIf
Point(1) = {0, 0, 0, h};
Point(2) = {1, 0, 0, h};
Point(3) = {1, 1, 0, h};
Point(4) = {0, 1, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Field[1] = Box;
Field[1].VIn = h;
Field[1].VOut = h;
Field[1].XMax = 1;
Field[1].YMax = 1;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
