// examples/meshes/plate_with_hole.geo with triangles half the size (about 4 times the nodes).
lc = 0.3e-3;
Include "plate_with_hole.geo";
