/* Finite-element meshes of the FEM part of a coupled model other than the lattice's own cells
 * (docs/coupling.md, "Graded meshes"): a list of elements over the nodes, each a bar (2
 * corners, 1D), a triangle (3) or a quadrilateral (4) in 2D, a hexahedron (8) in 3D, corners
 * counter-clockwise as in include/peri/fem.h. The nodes are those of the discretization. */
#ifndef PERI_FEM_MESH_H
#define PERI_FEM_MESH_H
#include <stddef.h>
#include <stdint.h>
#include "peri/particles.h"
#include "peri/shape.h"

typedef struct peri_fem_mesh {
  int32_t n_elements;
  int64_t *offset;      /* [n_elements + 1]: the corners of element e are nodes[offset[e] .. offset[e + 1]) */
  int32_t *nodes;
  uint8_t *coarse;      /* [n_elements] 1: an element larger than a lattice cell (its Q4s take the
                         * incompatible modes, fem.h) */
  int32_t n_nodes;      /* the nodes of the discretization the mesh was made for */
  uint8_t *fem_only;    /* [n_nodes] 1: the node may not become a PD node (a coarse node, or one whose
                         * horizon reaches a coarse node or a lattice point the mesh left out) */
  int32_t coarse_nodes; /* nodes of coarse elements (for the summary) */
  int32_t removed;      /* lattice nodes the coarse elements replaced */
} peri_fem_mesh;

void peri_fem_mesh_free(peri_fem_mesh *m);
/* Renumbers the mesh after the nodes were reordered: new node k is old node perm[k]. */
void peri_fem_mesh_permute(peri_fem_mesh *m, const int32_t *perm);

/* The graded structured mesh of a 2D body on the node lattice of spacing dx
 * (src/fem/graded_mesh.c): a balanced quadtree of square cells of sides 2^l dx (l = 0 ..
 * levels), level 0 (the lattice's own cells) in the cells whose centre lies in one of the
 * n_fine_shapes shapes `fine`, and
 * coarser away from it: a cell at Chebyshev distance d cells from the fine zone may belong to
 * an element of level l when layers (2^l - 2) < d, so that each level is about `layers`
 * elements deep; neighbouring elements differ by one level at most, and a coarse cell with a
 * finer neighbour (a node in the middle of one of its sides) is split into triangles about its
 * centre. Every element corner is a lattice node, every lattice point of a coarse element is a
 * node of the body (else the cell is refined), and the lattice nodes inside coarse elements are
 * removed from p. A coarse node's volume becomes its share of its elements' areas times the
 * thickness h; the others keep theirs. fem_only marks the coarse nodes and every node within
 * `reach` of a coarse node or a removed point. Returns PERI_ERR_INPUT with a message in why
 * when the nodes are not on the lattice or the fine zone holds no cell. */
int peri_graded_mesh_build(peri_particles *p, double dx, double reach, double h, const peri_shape *fine, int n_fine_shapes,
                           int levels, int layers, peri_fem_mesh *m, char *why, size_t n);

#endif
