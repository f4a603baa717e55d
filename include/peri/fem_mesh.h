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
  /* a mesh read from a file (peri_fem_mesh_from_file), else NULL: */
  char *file;           /* its path, for messages */
  int64_t *element_tag; /* [n_elements] the file's element tags */
  int64_t *node_tag;    /* [n_nodes] the file's node tag of each node, 0 for a PD grid node off the mesh */
  int64_t *fem_only_tag;/* [n_nodes] why a node is fem_only: > 0 the tag of a mesh node off the PD grid
                         * within reach; < 0 minus the tag of an element holding a PD grid point that
                         * is no node of the mesh within reach; 0 the node is itself off the PD grid */
} peri_fem_mesh;

/* A finite-element mesh as a file gives it (src/io/gmsh_fem_mesh.c, include/peri/mesh.h): nodes
 * and elements with the file's tags, each element's corners as indices into the nodes, in the
 * order of include/peri/fem.h. */
typedef struct peri_fem_mesh_file {
  char *path;
  int dim;
  int32_t n_nodes;
  int64_t *node_tag;    /* [n_nodes] */
  double *x;            /* [3 n_nodes] */
  int32_t n_elements;
  int64_t *element_tag; /* [n_elements] */
  int64_t *offset;      /* [n_elements + 1] */
  int32_t *corner;      /* [offset[n_elements]] node indices */
} peri_fem_mesh_file;

void peri_fem_mesh_file_free(peri_fem_mesh_file *f);

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

/* The FEM part of a coupled model on a mesh read from a file (src/fem/file_mesh.c; docs/coupling.md,
 * "Gmsh meshes"). The nodes of p are the PD grid: the lattice of spacing dx through the lowest
 * node. A file node within 1e-6 dx of a node of p becomes that node (two file nodes on one is
 * an error); any other file node is added to p with the material `material` and its share of
 * its elements' measures times h (the thickness in 2D, the cross-section in 1D, 1 in 3D) as
 * volume. A lattice point inside or on an element that is no file node is a hole: a node of p
 * there is removed. A node of p off the mesh stays (it must be a PD node). A file node keeps
 * the volume of its node of p when all its elements are lattice cells, else takes its share of
 * its elements. fem_only marks the added nodes and every node within `reach` of an added node
 * off the lattice or of a hole, with the cause in fem_only_tag. Returns PERI_ERR_INPUT with a message in why naming
 * the file and the element or node tag: an inverted element (det J < 0 at a Gauss point) or a
 * degenerate one (det J ~ 0), coincident file nodes, nodes of p off their lattice. */
int peri_fem_mesh_from_file(peri_particles *p, double dx, double reach, double h, int32_t material,
                            const peri_fem_mesh_file *f, peri_fem_mesh *m, char *why, size_t n);

#endif
