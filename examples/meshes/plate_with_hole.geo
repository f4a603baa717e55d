// A 50 x 20 mm plate with a 6 mm hole at its centre, for examples/mesh_plate.yaml. peri reads
// this geometry through the Gmsh library, which meshes it in triangles of about lc (metres).
// Physical groups: the surface "plate" (the block), its edges "left" and "right".
// plate_with_hole_fine.geo sets lc to half this and includes this file.
If (!Exists(lc))
  lc = 0.6e-3;
EndIf
Point(1) = {0, 0, 0, lc}; Point(2) = {0.05, 0, 0, lc}; Point(3) = {0.05, 0.02, 0, lc}; Point(4) = {0, 0.02, 0, lc};
Point(5) = {0.025, 0.01, 0, lc}; Point(6) = {0.028, 0.01, 0, lc}; Point(7) = {0.025, 0.013, 0, lc};
Point(8) = {0.022, 0.01, 0, lc}; Point(9) = {0.025, 0.007, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Circle(5) = {6, 5, 7}; Circle(6) = {7, 5, 8}; Circle(7) = {8, 5, 9}; Circle(8) = {9, 5, 6};
Curve Loop(1) = {1, 2, 3, 4}; Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2};
Physical Surface("plate") = {1};
Physical Curve("left") = {4};
Physical Curve("right") = {2};
