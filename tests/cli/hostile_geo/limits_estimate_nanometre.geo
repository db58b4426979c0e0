// limit (hangs): elements of 1 nm on a unit square (10^18 triangles; gmsh took 2.4 GB in 8 s): refused from the sizes before gmsh runs
// expect: variable geo_max_elements = 2000000
// expect: ask for at least about
h = 1e-9;
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
