/* Regions: the owned nodes inside a shape. */
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
