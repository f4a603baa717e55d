/* The structured finite-element mesh of a node lattice (src/fem/lattice_mesh.c). */
#ifndef PERI_FEM_LATTICE_MESH_H
#define PERI_FEM_LATTICE_MESH_H
#include <stddef.h>
#include <stdint.h>
#include "peri/particles.h"

/* The elements of the lattice of spacing dx formed by the owned nodes of p: the bars (dim 1),
 * squares (2) or cubes (3) whose 2^dim corners are all nodes and at least one of which has
 * node_type 0 (FEM). Corners in the order of include/peri/fem.h. On success *nodes holds
 * count * 2^dim node indices. Returns PERI_ERR_INPUT with a message in why (size n) when a
 * node is off the lattice (further than 1e-6 dx) or an FEM node belongs to no element. */
int peri_lattice_elements(const peri_particles *p, int dim, double dx, const int32_t *node_type, int32_t **nodes,
                          int32_t *count, char *why, size_t n);

#endif
