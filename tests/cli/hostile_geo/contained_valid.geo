// contained (files-read): a valid script run beside a planted .petscrc and petscrc (PETSc, linked into gmsh, reads them from the working directory when gmsh starts; -info and -log_view would write files): it runs, and nothing is written anywhere but the run's output, HOME stays empty
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
