// A gmsh script that meshes no surface: points and lines only, no triangles.
Point(1) = {0, 0, 0, 0.25};
Point(2) = {1, 0, 0, 0.25};
Line(1) = {1, 2};
