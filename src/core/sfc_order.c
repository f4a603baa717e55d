/* Morton (Z-order) ordering of nodes, for memory locality of neighbour accesses. */
#include <stdlib.h>
#include "peri/discretize.h"
#include "peri/error.h"

typedef struct {
  uint64_t key;
  int32_t index;
} keyed;

static int cmp_keyed(const void *a, const void *b) {
  const keyed *p = a, *q = b;
  if (p->key != q->key) return p->key < q->key ? -1 : 1;
  return (p->index > q->index) - (p->index < q->index);
}

/* Spreads the low 21 bits of v so that there are two zero bits between each. */
static uint64_t spread3(uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

void peri_sfc_order(const peri_particles *p, int32_t *perm) {
  int32_t n = p->n;
  if (n <= 0) return;
  double lo[3], hi[3];
  for (int d = 0; d < 3; d++) lo[d] = hi[d] = p->x[d];
  for (int32_t i = 1; i < n; i++)
    for (int d = 0; d < 3; d++) {
      double c = p->x[3 * i + d];
      if (c < lo[d]) lo[d] = c;
      if (c > hi[d]) hi[d] = c;
    }
  /* One scale for all axes, so curve cells are cubes and locality is isotropic. */
  double ext = 0;
  for (int d = 0; d < 3; d++)
    if (hi[d] - lo[d] > ext) ext = hi[d] - lo[d];
  const double top = (double)((1u << 21) - 1);
  double scale = ext > 0 ? top / ext : 0.0;
  keyed *k = peri_malloc(sizeof(keyed) * (size_t)n);
  for (int32_t i = 0; i < n; i++) {
    uint64_t key = 0;
    for (int d = 0; d < 3; d++) {
      double q = (p->x[3 * i + d] - lo[d]) * scale;
      if (q < 0) q = 0;
      if (q > top) q = top;
      key |= spread3((uint64_t)q) << d;
    }
    k[i].key = key;
    k[i].index = i;
  }
  qsort(k, (size_t)n, sizeof *k, cmp_keyed);
  for (int32_t i = 0; i < n; i++) perm[i] = k[i].index;
  free(k);
}
