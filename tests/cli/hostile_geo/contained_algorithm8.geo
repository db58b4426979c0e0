// contained (options): a valid script with Mesh.Algorithm 8 (which, with General.Verbosity 99, made gmsh write bgm-1.pos and cross-1.pos): it runs, and nothing is written anywhere but the run's output
// exit: 0
// requires: gmsh
h = 0.25;
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
Mesh.Algorithm = 8;
