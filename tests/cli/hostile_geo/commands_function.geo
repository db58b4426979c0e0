// hostile (commands): Function, the other spelling of Macro
// expect: line 15
// expect: 'Function' is a gmsh command
// the script: the unit square, then the payload (@MARK@: a path that must not appear)
Point(1) = {0, 0, 0, 0.25};
Point(2) = {1, 0, 0, 0.25};
Point(3) = {1, 1, 0, 0.25};
Point(4) = {0, 1, 0, 0.25};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Function F
  SystemCall "touch @MARK@";
Return
Call F;
