// mfcd geometry (gmsh): an elastic sphere of radius R in full 3D, resting on its pole at the
// origin (centre at z = R), for Hertz impact on a rigid wall (input/hertz_sphere_3d.nml).
// Eight octant surfaces bounded by circle arcs of one centre (gmsh puts their mesh nodes on
// the sphere), one volume of linear tetrahedra. Element size hc at the pole, growing to hf
// beyond the contact zone (a Distance + Threshold field from the pole), so the contact
// radius holds several elements.
// Parser numbers (&body geo_names, geo_values): R, hc, hf, a (the expected contact radius:
// the fine zone extends to 3 a).
If (!Exists(R))
  R = 5.0e-3;
EndIf
If (!Exists(hc))
  hc = 0.2e-3;
EndIf
If (!Exists(hf))
  hf = 1.0e-3;
EndIf
If (!Exists(a))
  a = 0.4e-3;
EndIf
Point(1) = {0, 0, R, hf};        // centre
Point(2) = {0, 0, 0, hc};        // pole (contact point)
Point(3) = {R, 0, R, hf};        // equator, +x
Point(4) = {0, R, R, hf};        // equator, +y
Point(5) = {-R, 0, R, hf};       // equator, -x
Point(6) = {0, -R, R, hf};       // equator, -y
Point(7) = {0, 0, 2 * R, hf};    // top pole
Circle(1) = {2, 1, 3};
Circle(2) = {2, 1, 4};
Circle(3) = {2, 1, 5};
Circle(4) = {2, 1, 6};
Circle(5) = {3, 1, 4};
Circle(6) = {4, 1, 5};
Circle(7) = {5, 1, 6};
Circle(8) = {6, 1, 3};
Circle(9) = {7, 1, 3};
Circle(10) = {7, 1, 4};
Circle(11) = {7, 1, 5};
Circle(12) = {7, 1, 6};
Curve Loop(1) = {1, 5, -2};
Curve Loop(2) = {2, 6, -3};
Curve Loop(3) = {3, 7, -4};
Curve Loop(4) = {4, 8, -1};
Curve Loop(5) = {9, 5, -10};
Curve Loop(6) = {10, 6, -11};
Curve Loop(7) = {11, 7, -12};
Curve Loop(8) = {12, 8, -9};
Surface(1) = {1};
Surface(2) = {2};
Surface(3) = {3};
Surface(4) = {4};
Surface(5) = {5};
Surface(6) = {6};
Surface(7) = {7};
Surface(8) = {8};
Surface Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8};
Volume(1) = {1};
Field[1] = Distance;
Field[1].PointsList = {2};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hc;
Field[2].SizeMax = hf;
Field[2].DistMin = 3 * a;
Field[2].DistMax = 3 * a + 10 * hf;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
