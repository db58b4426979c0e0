// limit (hangs): a Threshold field of 1 nm over the whole square, points of size 1: refused from the field before gmsh runs
// expect: variable geo_max_elements = 2000000
// expect: ask for at least about
h = 1;
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
Field[1] = Distance;
Field[1].PointsList = {1};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = 1e-9;
Field[2].SizeMax = 1e-8;
Field[2].DistMin = 2;
Field[2].DistMax = 3;
Background Field = 2;
