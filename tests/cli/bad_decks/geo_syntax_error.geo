// A gmsh script with a syntax error on line 3 (a brace left open).
Point(1) = {0, 0, 0, 0.25};
Point(2) = {1, 0, 0, 0.25;
