/* The node lattice and its structured finite-element mesh (src/fem/lattice_mesh.c). */
#ifndef PERI_FEM_LATTICE_MESH_H
#define PERI_FEM_LATTICE_MESH_H
#include <stddef.h>
#include <stdint.h>
#include "peri/particles.h"

/* The owned nodes of p as points of a lattice of spacing dx through the lowest node: the
 * integer coordinates of each node and the node at each lattice point of the bounding box. */
typedef struct peri_lattice {
  int dim;
  int64_t extent[3];    /* lattice points per axis */
  int64_t *cell;        /* [3 n_owned] integer coordinates */
  int32_t *at;          /* [extent product] node at a point, -1 where there is none */
} peri_lattice;

/* Returns PERI_ERR_INPUT with a message in why (size n) when a node is off the lattice
 * (further than 1e-6 dx) or the nodes fill too little of their bounding box. */
int peri_lattice_build(const peri_particles *p, int dim, double dx, peri_lattice *l, char *why, size_t n);
void peri_lattice_free(peri_lattice *l);
/* The node at integer coordinates k, or -1 (outside the box or no node there). */
static inline int32_t peri_lattice_node(const peri_lattice *l, const int64_t k[3]) {
  for (int d = 0; d < 3; ++d)
    if (k[d] < 0 || k[d] >= l->extent[d]) return -1;
  return l->at[(k[2] * l->extent[1] + k[1]) * l->extent[0] + k[0]];
}

/* The elements of the lattice: the bars (dim 1), squares (2) or cubes (3) whose 2^dim corners
 * are all nodes and at least one of which has node_type 0 (FEM). Corners in the order of
 * include/peri/fem.h. On success *nodes holds count * 2^dim node indices. Returns
 * PERI_ERR_INPUT with a message in why when an FEM node belongs to no element. */
int peri_lattice_elements(const peri_lattice *l, const peri_particles *p, const int32_t *node_type, int32_t **nodes,
                          int32_t *count, char *why, size_t n);

#endif
