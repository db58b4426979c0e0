// mfcd geometry (gmsh): the cross-section of an elastic cylinder (plane strain), a full
// disk of radius R resting on its lowest point at y = 0, centre at y = R, for Hertz impact
// on a rigid flat. The whole disk, not a half with a symmetry condition: RK shape functions
// do not interpolate, so a u_x = 0 condition on the coefficients of the x = 0 row would not
// make the field symmetric (doc/deck.md, &bc). Element size hc at the contact point, growing
// to hf beyond the contact zone (a Distance + Threshold field from that point), so the
// contact half-width holds several elements.
// Parser numbers (tools/mesh_body.py --set name=value): R, hc, hf, b (the expected contact
// half-width: the fine zone extends to 3 b).
If (!Exists(R))
  R = 5.0e-3;
EndIf
If (!Exists(hc))
  hc = 0.05e-3;
EndIf
If (!Exists(hf))
  hf = 0.5e-3;
EndIf
If (!Exists(b))
  b = 0.185e-3;
EndIf
Point(1) = {0, R, 0, hf};        // centre
Point(2) = {0, 0, 0, hc};        // lowest point (contact point)
Point(3) = {R, R, 0, hf};
Point(4) = {0, 2 * R, 0, hf};
Point(5) = {-R, R, 0, hf};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};
Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Field[1] = Distance;
Field[1].PointsList = {2};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hc;
Field[2].SizeMax = hf;
Field[2].DistMin = 3 * b;
Field[2].DistMax = 3 * b + 10 * hf;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
