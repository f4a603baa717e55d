/* The node lattice and its structured finite-element mesh: the FEM nodes coincide with the
 * PD grid (002_b20c318388227af9.txt §2.1), so each element is a cell of the lattice whose
 * corners are nodes. Nodes are found by their integer lattice coordinates in a dense table
 * over the bounding box of the nodes. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include "peri/error.h"
#include "lattice_mesh.h"

/* corner offsets in the order of include/peri/fem.h */
static const int corner_offset[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                        {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};

void peri_lattice_free(peri_lattice *l) {
  free(l->cell);
  free(l->at);
  l->cell = NULL, l->at = NULL;
}

int peri_lattice_build(const peri_particles *p, int dim, double dx, peri_lattice *l, char *why, size_t n) {
  const int32_t nn = p->n_owned;
  *l = (peri_lattice){.dim = dim, .extent = {1, 1, 1}};
  double lo[3] = {0, 0, 0};
  for (int d = 0; d < dim; ++d) {
    lo[d] = INFINITY;
    for (int32_t i = 0; i < nn; ++i) lo[d] = fmin(lo[d], p->x[3 * (size_t)i + d]);
  }
  l->cell = peri_malloc(sizeof(int64_t) * 3 * (size_t)(nn > 0 ? nn : 1));
  for (int32_t i = 0; i < nn; ++i)
    for (int d = 0; d < 3; ++d) {
      if (d >= dim) {
        l->cell[3 * (size_t)i + d] = 0;
        continue;
      }
      const double t = (p->x[3 * (size_t)i + d] - lo[d]) / dx;
      const double k = nearbyint(t);
      if (fabs(t - k) > 1e-6) {
        snprintf(why, n, "node %d at (%g, %g, %g) is not on the lattice of spacing %g through the lowest node: "
                 "the finite elements join lattice nodes", (int)i, p->x[3 * (size_t)i], p->x[3 * (size_t)i + 1],
                 p->x[3 * (size_t)i + 2], dx);
        peri_lattice_free(l);
        return PERI_ERR_INPUT;
      }
      l->cell[3 * (size_t)i + d] = (int64_t)k;
      if ((int64_t)k + 1 > l->extent[d]) l->extent[d] = (int64_t)k + 1;
    }
  const int64_t boxes = l->extent[0] * l->extent[1] * l->extent[2];
  if (boxes > 64 * (int64_t)nn + 4096) {
    snprintf(why, n, "the nodes fill %.3g%% of their bounding box: the structured mesh needs a compact lattice",
             100.0 * (double)nn / (double)boxes);
    peri_lattice_free(l);
    return PERI_ERR_INPUT;
  }
  l->at = peri_malloc(sizeof(int32_t) * (size_t)boxes);
  for (int64_t b = 0; b < boxes; ++b) l->at[b] = -1;
  for (int32_t i = 0; i < nn; ++i) {
    const int64_t *k = &l->cell[3 * (size_t)i];
    l->at[(k[2] * l->extent[1] + k[1]) * l->extent[0] + k[0]] = i;
  }
  return PERI_OK;
}

int peri_lattice_elements(const peri_lattice *l, const peri_particles *p, const int32_t *node_type, int32_t **nodes,
                          int32_t *count, char *why, size_t n) {
  const int32_t nn = p->n_owned;
  const int corners = 1 << l->dim;
  *nodes = NULL, *count = 0;
  int32_t capacity = 1024, found = 0;
  int32_t *list = peri_malloc(sizeof(int32_t) * (size_t)capacity * corners);
  uint8_t *covered = peri_calloc((size_t)(nn > 0 ? nn : 1), 1);
  for (int32_t i = 0; i < nn; ++i) {
    int32_t e[8];
    bool complete = true, fem = false;
    for (int c = 0; c < corners && complete; ++c) {
      int64_t k[3];
      for (int d = 0; d < 3; ++d) k[d] = l->cell[3 * (size_t)i + d] + corner_offset[c][d];
      e[c] = peri_lattice_node(l, k);
      complete = e[c] >= 0;
      if (complete) fem |= node_type[e[c]] == 0;
    }
    if (!complete || !fem) continue;
    if (found == capacity) {
      capacity *= 2;
      list = peri_realloc(list, sizeof(int32_t) * (size_t)capacity * corners);
    }
    for (int c = 0; c < corners; ++c) list[(size_t)found * corners + c] = e[c], covered[e[c]] = 1;
    ++found;
  }
  int rc = PERI_OK;
  for (int32_t i = 0; i < nn && rc == PERI_OK; ++i)
    if (node_type[i] == 0 && !covered[i]) {
      snprintf(why, n, "FEM node %d at (%g, %g, %g) belongs to no element: the lattice cells around it are "
               "incomplete (make it a PD node, or fill the grid around it)", (int)i, p->x[3 * (size_t)i],
               p->x[3 * (size_t)i + 1], p->x[3 * (size_t)i + 2]);
      rc = PERI_ERR_INPUT;
    }
  free(covered);
  if (rc != PERI_OK) {
    free(list);
    return rc;
  }
  *nodes = list;
  *count = found;
  return PERI_OK;
}
