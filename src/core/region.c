/* Regions: the owned nodes inside a shape, or a given node list; booleans of node lists. */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include "peri/region.h"
#include "peri/error.h"

void peri_region_collect(peri_region *r, const peri_particles *p, double tol) {
  free(r->nodes); /* a previous collection, or NULL */
  int32_t cnt = 0;
  for (int32_t i = 0; i < p->n_owned; i++)
    if (peri_shape_contains(&r->shape, p->dim, p->x + 3 * (size_t)i, tol)) cnt++;
  r->nodes = peri_malloc(sizeof(int32_t) * (size_t)(cnt > 0 ? cnt : 1));
  r->count = cnt;
  int32_t k = 0;
  for (int32_t i = 0; i < p->n_owned && k < cnt; i++)
    if (peri_shape_contains(&r->shape, p->dim, p->x + 3 * (size_t)i, tol)) r->nodes[k++] = i;
}

void peri_region_free(peri_region *r) {
  free(r->name);
  peri_shape_free(&r->shape);
  free(r->nodes);
  memset(r, 0, sizeof *r);
}

void peri_region_set_nodes(peri_region *r, const int32_t *nodes, int32_t count) {
  free(r->nodes);
  r->nodes = peri_malloc(sizeof(int32_t) * (size_t)(count > 0 ? count : 1));
  if (count > 0) memcpy(r->nodes, nodes, sizeof(int32_t) * (size_t)count);
  r->count = count;
  r->shape.kind = PERI_SHAPE_ALL; /* no shape: the nodes are the region */
}

/* One merge of the two ascending lists: a node is kept when the operation keeps the pair
 * (in a, in b) it falls in. */
int32_t peri_region_combine(peri_region_op op, const int32_t *a, int32_t na, const int32_t *b, int32_t nb,
                            int32_t *out) {
  int32_t i = 0, j = 0, n = 0;
  while (i < na || j < nb) {
    int32_t node;
    bool in_a = false, in_b = false;
    if (j >= nb || (i < na && a[i] < b[j])) node = a[i++], in_a = true;
    else if (i >= na || b[j] < a[i]) node = b[j++], in_b = true;
    else node = a[i++], j++, in_a = in_b = true;
    const bool keep = op == PERI_REGION_UNION ? true : op == PERI_REGION_INTERSECTION ? in_a && in_b : in_a && !in_b;
    if (keep && (n == 0 || out[n - 1] != node)) out[n++] = node;
  }
  return n;
}
