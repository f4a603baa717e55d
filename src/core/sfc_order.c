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

/* A node's place in the order: its row's cell on the Morton curve, where its column starts
 * along the row, its column, its position along the row. */
typedef struct {
  uint64_t row;
  uint32_t start, along;
  int32_t column, index;
} row_keyed;

static int cmp_row_keyed(const void *a, const void *b) {
  const row_keyed *p = a, *q = b;
  if (p->row != q->row) return p->row < q->row ? -1 : 1;
  if (p->start != q->start) return p->start < q->start ? -1 : 1;
  if (p->column != q->column) return p->column < q->column ? -1 : 1;
  if (p->along != q->along) return p->along < q->along ? -1 : 1;
  return (p->index > q->index) - (p->index < q->index);
}

/* Columns are found to this fraction of the spacing: far below the distance between two
 * columns of any node set with columns, far above the jitter a node file adds to break
 * symmetry (Peridigm's cylinder: 10^-3 of its cells). */
#define COLUMN_TOLERANCE (1.0 / 16.0)

static int32_t column_root(int32_t *parent, int32_t c) {
  while (parent[c] != c) c = parent[c] = parent[parent[c]];
  return c;
}

/* The columns of the node set: nodes whose coordinates across the rows (axes s and t) agree
 * to COLUMN_TOLERANCE h, as a line of nodes along the row axis does. Returns for each node
 * the smallest index in its column. On a lattice a column is a row of cells; in a node set of
 * columns that do not follow the cells (the rings of a cylinder) two columns can share a cell,
 * and sorting the cell's nodes along the axis alone interleaved them, so that no eight
 * consecutive nodes had translated families. */
static int32_t *columns_of(const peri_particles *p, int s, int t, const double lo[3], double h) {
  const int32_t n = p->n;
  const double tol = COLUMN_TOLERANCE * h, inv_tol = tol > 0 ? 1.0 / tol : 0.0;
  /* the nodes by fine cell (of size tol) across the rows */
  keyed *fine = peri_malloc(sizeof(keyed) * (size_t)n);
  for (int32_t i = 0; i < n; i++) {
    double a = floor((p->x[3 * i + s] - lo[s]) * inv_tol), b = floor((p->x[3 * i + t] - lo[t]) * inv_tol);
    a = a > 0 ? fmin(a, (double)INT32_MAX) : 0, b = b > 0 ? fmin(b, (double)INT32_MAX) : 0;
    fine[i].key = (uint64_t)a << 32 | (uint64_t)b;
    fine[i].index = i;
  }
  qsort(fine, (size_t)n, sizeof *fine, cmp_keyed);
  int32_t *cell = peri_malloc(sizeof(int32_t) * (size_t)n), *parent = peri_malloc(sizeof(int32_t) * (size_t)n),
          *first = peri_malloc(sizeof(int32_t) * (size_t)n + sizeof(int32_t));
  uint64_t *cell_key = peri_malloc(sizeof(uint64_t) * (size_t)n);
  int32_t cells = 0;
  for (int32_t k = 0; k < n; k++) {
    if (k == 0 || fine[k].key != fine[k - 1].key) {
      cell_key[cells] = fine[k].key;
      first[cells] = k;
      parent[cells] = cells;
      ++cells;
    }
    cell[fine[k].index] = cells - 1;
  }
  first[cells] = n;
  /* a column on a boundary of the fine cells lies in two or four of them: join neighbouring
   * cells whose first nodes are within tol */
  static const int64_t step[4][2] = {{0, 1}, {1, -1}, {1, 0}, {1, 1}};
  for (int32_t c = 0; c < cells; c++) {
    const int64_t a = (int64_t)(cell_key[c] >> 32), b = (int64_t)(cell_key[c] & 0xffffffffu);
    const double *xc = &p->x[3 * fine[first[c]].index];
    for (int d = 0; d < 4; d++) {
      const int64_t na = a + step[d][0], nb = b + step[d][1];
      if (nb < 0 || nb > UINT32_MAX) continue;
      const uint64_t want = (uint64_t)na << 32 | (uint64_t)nb;
      int32_t lo_c = c + 1, hi_c = cells;
      while (lo_c < hi_c) {
        const int32_t mid = lo_c + (hi_c - lo_c) / 2;
        if (cell_key[mid] < want) lo_c = mid + 1;
        else hi_c = mid;
      }
      if (lo_c == cells || cell_key[lo_c] != want) continue;
      const double *xe = &p->x[3 * fine[first[lo_c]].index];
      if (hypot(xe[s] - xc[s], xe[t] - xc[t]) >= tol) continue;
      const int32_t r1 = column_root(parent, c), r2 = column_root(parent, lo_c);
      if (r1 < r2) parent[r2] = r1;
      else parent[r1] = r2;
    }
  }
  /* a column's name: its smallest node index */
  int32_t *name = peri_malloc(sizeof(int32_t) * (size_t)cells), *column = peri_malloc(sizeof(int32_t) * (size_t)n);
  for (int32_t c = 0; c < cells; c++) name[c] = INT32_MAX;
  for (int32_t i = 0; i < n; i++) {
    const int32_t r = column_root(parent, cell[i]);
    if (i < name[r]) name[r] = i;
  }
  for (int32_t i = 0; i < n; i++) column[i] = name[column_root(parent, cell[i])];
  free(name);
  free(cell_key);
  free(first);
  free(parent);
  free(cell);
  free(fine);
  return column;
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
  int32_t *column = columns_of(p, s, t, lo, h);
  const double along = ext > 0 ? (double)CELL_MAX / ext : 0.0; /* fine position within a row */
  /* a column's row: the cell of its first node; its first position along the axis */
  uint64_t *row = peri_malloc(sizeof(uint64_t) * (size_t)n);
  uint32_t *start = peri_malloc(sizeof(uint32_t) * (size_t)n);
  row_keyed *k = peri_malloc(sizeof(row_keyed) * (size_t)n);
  for (int32_t i = 0; i < n; i++) {
    double q = (p->x[3 * i + axis] - lo[axis]) * along;
    if (!(q > 0)) q = 0;
    if (q > CELL_MAX) q = CELL_MAX;
    k[i].along = (uint32_t)q;
    if (column[i] == i) {
      row[i] = spread2(cell_of(p->x[3 * i + s], lo[s], inv_h)) | spread2(cell_of(p->x[3 * i + t], lo[t], inv_h)) << 1;
      start[i] = UINT32_MAX;
    }
  }
  for (int32_t i = 0; i < n; i++)
    if (k[i].along < start[column[i]]) start[column[i]] = k[i].along;
  for (int32_t i = 0; i < n; i++) {
    k[i].row = row[column[i]];
    k[i].start = start[column[i]];
    k[i].column = column[i];
    k[i].index = i;
  }
  qsort(k, (size_t)n, sizeof *k, cmp_row_keyed);
  for (int32_t i = 0; i < n; i++) perm[i] = k[i].index;
  free(k);
  free(start);
  free(row);
  free(column);
}
