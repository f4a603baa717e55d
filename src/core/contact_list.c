/* The candidate pairs of short-range contact (include/peri/contact_list.h): a cell list over
 * the deformed positions finds, for every node, the nodes within the largest contact distance
 * plus the skin; the list is kept until a node has moved half the skin, since two nodes that
 * each moved less than skin/2 are still farther apart than d_ij if they were farther than
 * d_ij + skin at the build. The pruned list applies the same argument with a smaller skin to
 * the built list's pairs: fewer pairs for the forces to visit at every evaluation, and a
 * prune is a pass over the built list, not over the cells. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/contact_list.h"
#include "peri/error.h"
#ifdef _OPENMP
#include <omp.h>
#endif

peri_contact_list_need peri_contact_list_needs(const peri_contact_list *l, const double *x, const double *u, int32_t n,
                                               double skin, double prune_skin, double *y) {
  double moved2 = 0.0, moved_prune2 = 0.0; /* the largest squared displacements since the build and the prune */
#pragma omp parallel for schedule(static) reduction(max : moved2, moved_prune2)
  for (int32_t i = 0; i < n; ++i) {
    const size_t k = 3 * (size_t)i;
    for (int a = 0; a < 3; ++a) y[k + a] = x[k + a] + u[k + a];
    if (!l->u_built || l->n != n) continue;
    const double *b = &l->u_built[k], *c = &l->u_pruned[k];
    const double d0 = u[k] - b[0], d1 = u[k + 1] - b[1], d2 = u[k + 2] - b[2];
    const double e0 = u[k] - c[0], e1 = u[k + 1] - c[1], e2 = u[k + 2] - c[2];
    const double d = d0 * d0 + d1 * d1 + d2 * d2, e = e0 * e0 + e1 * e1 + e2 * e2;
    moved2 = d > moved2 ? d : moved2;
    moved_prune2 = e > moved_prune2 ? e : moved_prune2;
  }
  if (!l->u_built || l->n != n || moved2 > 0.25 * skin * skin) return PERI_CONTACT_LIST_BUILD;
  return moved_prune2 > 0.25 * prune_skin * prune_skin ? PERI_CONTACT_LIST_PRUNE : PERI_CONTACT_LIST_FRESH;
}

/* The cell grid over the deformed positions: cells at least `h` wide, at most 8n + 2^16 of
 * them, 8 bytes each (a fragment that flew far widens the cells beyond that). */
typedef struct {
  double lo[3], h;
  int64_t nc[3];
  int64_t *start;   /* [cells+1] */
  int32_t *node;    /* [n] nodes by cell, in index order within a cell */
} cell_grid;

static int64_t cell_coord(const cell_grid *g, const double *y, int a) {
  const double c = floor((y[a] - g->lo[a]) / g->h); /* not finite: clamped (the run stops after the step) */
  return !(c >= 0.0) ? 0 : c >= (double)g->nc[a] ? g->nc[a] - 1 : (int64_t)c;
}

/* Cells along one axis: at least 1, at most max_cells (an extent that is not finite). */
static double cells_along(double extent, double h, double max_cells) {
  const double c = floor(extent / h);
  return !(c >= 1.0) ? 1.0 : c > max_cells ? max_cells : c;
}

static int64_t cell_of(const cell_grid *g, const double *y) {
  return (cell_coord(g, y, 2) * g->nc[1] + cell_coord(g, y, 1)) * g->nc[0] + cell_coord(g, y, 0);
}

static void grid_build(cell_grid *g, const double *y, int32_t n, double h) {
  double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
  for (int32_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      lo[a] = fmin(lo[a], y[3 * (size_t)i + a]);
      hi[a] = fmax(hi[a], y[3 * (size_t)i + a]);
    }
  const double max_cells = 8.0 * n + 65536.0;
  for (int widen = 0; widen < 400; ++widen) {
    double cells = 1.0;
    for (int a = 0; a < 3; ++a) cells *= cells_along(hi[a] - lo[a], h, max_cells);
    if (cells <= max_cells) break;
    h *= 1.26;
  }
  g->h = h;
  int64_t total = 1;
  for (int a = 0; a < 3; ++a) {
    g->lo[a] = lo[a];
    g->nc[a] = (int64_t)cells_along(hi[a] - lo[a], h, max_cells);
    total *= g->nc[a];
  }
  /* a counting sort by cell keeps the index order within each cell */
  g->start = peri_calloc((size_t)total + 1, sizeof(int64_t));
  g->node = peri_malloc(sizeof(int32_t) * (n > 0 ? (size_t)n : 1));
  int64_t *cell = peri_malloc(sizeof(int64_t) * (n > 0 ? (size_t)n : 1));
  for (int32_t i = 0; i < n; ++i) {
    cell[i] = cell_of(g, &y[3 * (size_t)i]);
    ++g->start[cell[i] + 1];
  }
  for (int64_t c = 0; c < total; ++c) g->start[c + 1] += g->start[c];
  int64_t *fill = peri_malloc(sizeof(int64_t) * (size_t)total);
  memcpy(fill, g->start, sizeof(int64_t) * (size_t)total);
  for (int32_t i = 0; i < n; ++i) g->node[fill[cell[i]]++] = i;
  free(fill);
  free(cell);
}

/* A thread's entries, grown as it goes. */
typedef struct {
  int32_t *partner;
  double *reach;
  int64_t size, capacity;
} entry_buffer;

static void buffer_reserve(entry_buffer *b, int64_t more) {
  if (b->size + more <= b->capacity) return;
  b->capacity = 2 * (b->size + more) + 64;
  b->partner = peri_realloc(b->partner, sizeof(int32_t) * (size_t)b->capacity);
  b->reach = peri_realloc(b->reach, sizeof(double) * (size_t)b->capacity);
}

/* Cells are at least half of max_reach + skin wide, and the 5 x 5 x 5 cells around a node's
 * cell hold every node within max_reach + skin: 58% of the volume of 3 x 3 x 3 cells of the
 * full width, so fewer candidates. */
#define STENCIL 2

/* Appends the listed partners of node i to buf; returns their number. */
static int64_t scan_node(const cell_grid *g, const double *x, const double *y, int32_t i,
                         const peri_contact_reach *r, entry_buffer *buf) {
  const double *yi = &y[3 * (size_t)i], *xi = &x[3 * (size_t)i];
  int64_t c[3], count = 0;
  const double farthest2 = (r->max_reach + r->skin) * (r->max_reach + r->skin);
  for (int a = 0; a < 3; ++a) c[a] = cell_coord(g, yi, a);
  /* the stencil's cells along x are consecutive in the cell order, and so are their nodes:
   * one range of nodes per row of cells */
  const int64_t x0 = c[0] > STENCIL ? c[0] - STENCIL : 0, x1 = c[0] + STENCIL < g->nc[0] ? c[0] + STENCIL : g->nc[0] - 1;
  for (int64_t cz = c[2] > STENCIL ? c[2] - STENCIL : 0; cz <= c[2] + STENCIL && cz < g->nc[2]; ++cz)
    for (int64_t cy = c[1] > STENCIL ? c[1] - STENCIL : 0; cy <= c[1] + STENCIL && cy < g->nc[1]; ++cy) {
      const int64_t row = (cz * g->nc[1] + cy) * g->nc[0];
      const int64_t k0 = g->start[row + x0], k1 = g->start[row + x1 + 1];
      if (k1 <= k0) continue; /* (an empty row: the buffer may not be allocated yet) */
      buffer_reserve(buf, count + k1 - k0);
      int32_t *out = &buf->partner[buf->size];
      double *reach_out = &buf->reach[buf->size];
      for (int64_t k = k0; k < k1; ++k) {
        const int32_t j = g->node[k];
        if (j == i) continue;
        const double *yj = &y[3 * (size_t)j], *xj = &x[3 * (size_t)j];
        const double r2 = (yi[0] - yj[0]) * (yi[0] - yj[0]) + (yi[1] - yj[1]) * (yi[1] - yj[1]) +
                          (yi[2] - yj[2]) * (yi[2] - yj[2]);
        if (r2 >= farthest2) continue; /* most candidates: no square root */
        const double r02 = (xi[0] - xj[0]) * (xi[0] - xj[0]) + (xi[1] - xj[1]) * (xi[1] - xj[1]) +
                           (xi[2] - xj[2]) * (xi[2] - xj[2]);
        const double d = fmin(r->ratio * sqrt(r02), r->max_reach), listed = d + r->skin;
        if (r2 >= listed * listed) continue;
        out[count] = j;
        reach_out[count] = d;
        ++count;
      }
    }
  return count;
}

/* Sorts one node's partners by index (insertion: a few tens of entries), so that the sums
 * over them do not depend on the cells of the build. */
static void sort_partners(int32_t *partner, double *reach, int64_t m) {
  for (int64_t a = 1; a < m; ++a) {
    const int32_t j = partner[a];
    const double d = reach[a];
    int64_t b = a;
    for (; b > 0 && partner[b - 1] > j; --b) {
      partner[b] = partner[b - 1];
      reach[b] = reach[b - 1];
    }
    partner[b] = j;
    reach[b] = d;
  }
}

void peri_contact_list_build(peri_contact_list *l, const double *x, const double *y, int32_t n, int32_t first_row,
                             int32_t rows, const double *u_rows, const peri_contact_reach *reach) {
  cell_grid g;
  grid_build(&g, y, n, (reach->max_reach + reach->skin) / STENCIL);
  if (l->n != rows || !l->offset) {
    free(l->offset);
    free(l->u_built);
    free(l->pruned_end);
    free(l->u_pruned);
    l->offset = peri_malloc(sizeof(int64_t) * ((size_t)rows + 1));
    l->u_built = peri_malloc(sizeof(double) * 3 * (rows > 0 ? (size_t)rows : 1));
    l->pruned_end = peri_malloc(sizeof(int64_t) * (rows > 0 ? (size_t)rows : 1));
    l->u_pruned = peri_malloc(sizeof(double) * 3 * (rows > 0 ? (size_t)rows : 1));
    l->n = rows;
  }
  l->offset[0] = 0;
  /* one pass: each thread scans a contiguous range of nodes into its own buffer, the
   * ranges are then laid end to end in node order */
  int threads = 1, used = 1;
#ifdef _OPENMP
  threads = omp_get_max_threads();
#endif
  entry_buffer *buffers = peri_calloc((size_t)threads, sizeof(entry_buffer));
#pragma omp parallel num_threads(threads)
  {
    int t = 0, nt = 1;
#ifdef _OPENMP
    t = omp_get_thread_num();
    nt = omp_get_num_threads();
#endif
    if (t == 0) used = nt; /* the team may be smaller than asked */
    const int32_t i0 = (int32_t)((int64_t)rows * t / nt), i1 = (int32_t)((int64_t)rows * (t + 1) / nt);
    entry_buffer *b = &buffers[t];
    for (int32_t i = i0; i < i1; ++i) {
      const int64_t m = scan_node(&g, x, y, first_row + i, reach, b);
      sort_partners(&b->partner[b->size], &b->reach[b->size], m);
      b->size += m;
      l->offset[i + 1] = m;
    }
  }
  for (int32_t i = 0; i < rows; ++i) l->offset[i + 1] += l->offset[i];
  const int64_t entries = l->offset[rows];
  if (entries > l->capacity || !l->partner) {
    free(l->partner);
    free(l->reach);
    free(l->pruned_partner);
    free(l->pruned_reach);
    l->capacity = entries + entries / 4 + 16;
    l->partner = peri_malloc(sizeof(int32_t) * (size_t)l->capacity);
    l->reach = peri_malloc(sizeof(double) * (size_t)l->capacity);
    l->pruned_partner = peri_malloc(sizeof(int32_t) * (size_t)l->capacity);
    l->pruned_reach = peri_malloc(sizeof(double) * (size_t)l->capacity);
  }
#pragma omp parallel for schedule(static, 1) num_threads(used)
  for (int t = 0; t < used; ++t) {
    const int32_t i0 = (int32_t)((int64_t)rows * t / used);
    if (buffers[t].size > 0) {
      memcpy(&l->partner[l->offset[i0]], buffers[t].partner, sizeof(int32_t) * (size_t)buffers[t].size);
      memcpy(&l->reach[l->offset[i0]], buffers[t].reach, sizeof(double) * (size_t)buffers[t].size);
    }
  }
  for (int t = 0; t < threads; ++t) {
    free(buffers[t].partner);
    free(buffers[t].reach);
  }
  free(buffers);
  memcpy(l->u_built, u_rows, sizeof(double) * 3 * (size_t)rows);
  ++l->builds;
  free(g.start);
  free(g.node);
}

/* Each row writes only its own range, so the rows are pruned in parallel; a row keeps its
 * partners' index order. */
void peri_contact_list_prune(peri_contact_list *l, const double *y, int32_t first_row, const double *u_rows,
                             double prune_skin) {
  const int32_t rows = l->n;
#pragma omp parallel for schedule(static)
  for (int32_t row = 0; row < rows; ++row) {
    const size_t i = (size_t)first_row + (size_t)row;
    const double yi0 = y[3 * i], yi1 = y[3 * i + 1], yi2 = y[3 * i + 2];
    int64_t end = l->offset[row];
    for (int64_t k = l->offset[row]; k < l->offset[row + 1]; ++k) {
      const int32_t j = l->partner[k];
      const double d0 = yi0 - y[3 * (size_t)j], d1 = yi1 - y[3 * (size_t)j + 1], d2 = yi2 - y[3 * (size_t)j + 2];
      const double listed = l->reach[k] + prune_skin;
      if (d0 * d0 + d1 * d1 + d2 * d2 >= listed * listed) continue;
      l->pruned_partner[end] = j;
      l->pruned_reach[end] = l->reach[k];
      ++end;
    }
    l->pruned_end[row] = end;
  }
  memcpy(l->u_pruned, u_rows, sizeof(double) * 3 * (size_t)rows);
  ++l->prunes;
}

void peri_contact_list_free(peri_contact_list *l) {
  free(l->offset);
  free(l->partner);
  free(l->reach);
  free(l->u_built);
  free(l->pruned_end);
  free(l->pruned_partner);
  free(l->pruned_reach);
  free(l->u_pruned);
  memset(l, 0, sizeof *l);
}
