// mfcd geometry (gmsh): a solid disk of radius R centred at (xc, yc), element size h, for
// the tutorial's oblique impact of a steel disk on an aluminium plate (doc/tutorial.md,
// input/disk_plate.nml). Parser numbers (&body geo_names / geo_values): R, xc, yc, h.
If (!Exists(R))
  R = 5.0e-3;
EndIf
If (!Exists(xc))
  xc = 0.0;
EndIf
If (!Exists(yc))
  yc = 5.1e-3;
EndIf
If (!Exists(h))
  h = 0.25e-3;
EndIf
Point(1) = {xc, yc, 0, h};
Point(2) = {xc, yc - R, 0, h};
Point(3) = {xc + R, yc, 0, h};
Point(4) = {xc, yc + R, 0, h};
Point(5) = {xc - R, yc, 0, h};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};
Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
