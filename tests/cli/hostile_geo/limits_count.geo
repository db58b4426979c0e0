// limit (sizes): a mesh whose sizes promise at least 100 triangles and give about 230, more than geo_max_elements = 150: refused after meshing
// deck: geo_max_elements = 150
// requires: gmsh
// expect: variable geo_max_elements = 150
// expect: gmsh made
h = 0.1;
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
