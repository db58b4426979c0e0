// limit (hangs): a valid script whose mesh (about 3.6 million triangles) takes minutes: stopped at geo_time_limit
// deck: geo_time_limit = 1, geo_max_elements = 10000000
// requires: gmsh
// within: 15
// expect: variable geo_time_limit = 1.00000
// expect: took longer than 1.00000 s and was stopped
h = 0.0008;
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
