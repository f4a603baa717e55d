/* Node order for memory locality and for the kernels' runs of translated families: nodes
 * lie in rows along one axis (the axis with the longest rows), each row sorted along the
 * axis, and the rows follow a Morton (Z-order) curve over the other two axes. On a lattice,
 * consecutive nodes of a row have families that are translates of each other, which the
 * bond loops process eight at a time without gathers (src/model/node_blocks.c). */
#include <math.h>
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

static int cmp_u64(const void *a, const void *b) {
  const uint64_t p = *(const uint64_t *)a, q = *(const uint64_t *)b;
  return (p > q) - (p < q);
}

/* Spreads the low 21 bits of v so that there is one zero bit between each. */
static uint64_t spread2(uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 16) & 0x0000ffff0000ffffULL;
  v = (v | v << 8) & 0x00ff00ff00ff00ffULL;
  v = (v | v << 4) & 0x0f0f0f0f0f0f0f0fULL;
  v = (v | v << 2) & 0x3333333333333333ULL;
  v = (v | v << 1) & 0x5555555555555555ULL;
  return v;
}

#define CELL_MAX ((1u << 21) - 1)

/* Cell of coordinate c along an axis starting at lo, cells of size h centred on the
 * lattice points (rounding, so that round-off in a lattice coordinate does not move a node
 * to the next row). */
static uint64_t cell_of(double c, double lo, double inv_h) {
  double q = floor((c - lo) * inv_h + 0.5);
  if (!(q > 0)) return 0;
  return q > CELL_MAX ? CELL_MAX : (uint64_t)q;
}

/* Number of distinct rows along `axis`, i.e. of distinct cells of the other two axes. */
static int64_t count_rows(const peri_particles *p, int axis, const double lo[3], double inv_h, uint64_t *scratch) {
  const int s = (axis + 1) % 3, t = (axis + 2) % 3;
  for (int32_t i = 0; i < p->n; i++)
    scratch[i] = cell_of(p->x[3 * i + s], lo[s], inv_h) << 21 | cell_of(p->x[3 * i + t], lo[t], inv_h);
  qsort(scratch, (size_t)p->n, sizeof *scratch, cmp_u64);
  int64_t rows = 1;
  for (int32_t i = 1; i < p->n; i++) rows += scratch[i] != scratch[i - 1];
  return rows;
}

void peri_sfc_order(const peri_particles *p, double spacing, int32_t *perm) {
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
  double ext = 0;
  for (int d = 0; d < 3; d++)
    if (hi[d] - lo[d] > ext) ext = hi[d] - lo[d];
  /* rows are one cell wide: the node spacing, or a 2^21-th of the extent if that is coarser */
  double h = spacing > 0 && isfinite(spacing) ? spacing : ext / CELL_MAX;
  if (ext / CELL_MAX > h) h = ext / CELL_MAX;
  const double inv_h = h > 0 ? 1.0 / h : 0.0;
  /* the row axis: the one with the fewest (so the longest) rows; axes without extent
   * (2D and 1D problems) have one cell and are never chosen over one that has */
  uint64_t *scratch = peri_malloc(sizeof(uint64_t) * (size_t)n);
  int axis = 0;
  int64_t best = -1;
  for (int d = 0; d < 3; d++) {
    if (!(hi[d] > lo[d]) && ext > 0) continue;
    const int64_t rows = count_rows(p, d, lo, inv_h, scratch);
    if (best < 0 || rows < best) best = rows, axis = d;
  }
  free(scratch);
  const int s = (axis + 1) % 3, t = (axis + 2) % 3;
  const double along = ext > 0 ? (double)CELL_MAX / ext : 0.0; /* fine position within a row */
  keyed *k = peri_malloc(sizeof(keyed) * (size_t)n);
  for (int32_t i = 0; i < n; i++) {
    double q = (p->x[3 * i + axis] - lo[axis]) * along;
    if (!(q > 0)) q = 0;
    if (q > CELL_MAX) q = CELL_MAX;
    const uint64_t row = spread2(cell_of(p->x[3 * i + s], lo[s], inv_h)) |
                         spread2(cell_of(p->x[3 * i + t], lo[t], inv_h)) << 1;
    k[i].key = row << 21 | (uint64_t)q;
    k[i].index = i;
  }
  qsort(k, (size_t)n, sizeof *k, cmp_keyed);
  for (int32_t i = 0; i < n; i++) perm[i] = k[i].index;
  free(k);
}
