// The FEM part of examples/coupling_gmsh_plate.yaml: a 16 x 12 plate whose middle
// [4, 12] x [2.5, 9.5] is a structured grid of 0.5 x 0.5 quadrangles (its nodes are those of
// the PD grid of spacing 0.5 with placement lattice), and whose outer ring is meshed by
// Gmsh's frontal-Delaunay algorithm (6) with elements of about 1.2, recombined into quadrangles
// (nodes off the grid; algorithm 8, frontal-Delaunay for quads, crashes Gmsh 4.8 here).
// Made with: gmsh coupling_gmsh_plate.geo -2 -format msh41 -o coupling_gmsh_plate.msh
lc = 1.2;
Point(1) = {0, 0, 0, lc};
Point(2) = {16, 0, 0, lc};
Point(3) = {16, 12, 0, lc};
Point(4) = {0, 12, 0, lc};
Point(5) = {4, 2.5, 0, lc};
Point(6) = {12, 2.5, 0, lc};
Point(7) = {12, 9.5, 0, lc};
Point(8) = {4, 9.5, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Line(5) = {5, 6};
Line(6) = {6, 7};
Line(7) = {7, 8};
Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2};
Plane Surface(2) = {2};
Transfinite Curve{5, 7} = 17;
Transfinite Curve{6, 8} = 15;
Transfinite Surface{2};
Recombine Surface{1, 2};
Mesh.Algorithm = 6;
Physical Surface("plate") = {1, 2};
