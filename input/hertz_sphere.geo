// mfcd geometry (gmsh): the meridian half-disk of an elastic sphere (axisymmetric: x = r,
// y = z) of radius R resting on its pole at z = 0, centre at z = R, for Hertz impact on a
// rigid wall. Element size hc at the pole, growing to hf beyond the contact zone (a
// Distance + Threshold field from the pole), so the contact radius holds several elements.
// Parser numbers (tools/mesh_body.py --set name=value): R, hc, hf, a (the expected contact
// radius: the fine zone extends to 3 a).
If (!Exists(R))
  R = 5.0e-3;
EndIf
If (!Exists(hc))
  hc = 0.1e-3;
EndIf
If (!Exists(hf))
  hf = 0.5e-3;
EndIf
If (!Exists(a))
  a = 0.4e-3;
EndIf
Point(1) = {0, R, 0, hf};        // centre
Point(2) = {0, 0, 0, hc};        // pole (contact point)
Point(3) = {R, R, 0, hf};        // equator
Point(4) = {0, 2 * R, 0, hf};    // top pole
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Line(3) = {4, 1};
Line(4) = {1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
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
