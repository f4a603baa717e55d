/* The normal traction across interfaces and the interface strength (include/peri/interface_strength.h,
 * docs/thin_films.md section 6). */
#include <math.h>
#include <stdlib.h>
#include "peri/comm.h"
#include "peri/error.h"
#include "peri/interface_strength.h"
#include "peri/model.h"

/* The lattice columns: index of a node's column from its reference position. */
typedef struct columns {
  double lo[2], dx;
  int64_t n[2], count;
} columns;

static columns lattice_columns(const peri_sim *s) {
  const peri_particles *p = &s->disc.p;
  const int across = s->disc.geom.dim == 3 ? 2 : 1; /* the axes along the interface: x (and y in 3D) */
  columns c = {.dx = s->disc.family.spacing, .n = {1, 1}, .count = 1};
  if (!(c.dx > 0.0)) { /* no lattice spacing: one column (a 1D bar across its interface) */
    c.dx = 1.0;
    return c;
  }
  for (int d = 0; d < across; ++d) {
    double lo = INFINITY, hi = -INFINITY;
    for (int32_t i = 0; i < p->n_owned; ++i) lo = fmin(lo, p->x[3 * i + d]), hi = fmax(hi, p->x[3 * i + d]);
    lo = peri_comm_min(lo), hi = peri_comm_max(hi);
    c.lo[d] = isfinite(lo) ? lo : 0.0;
    c.n[d] = isfinite(lo) ? llround((hi - lo) / c.dx) + 1 : 1;
  }
  c.count = c.n[0] * c.n[1];
  return c;
}

/* The column of node i (ghosts included: their reference positions are there). */
static int64_t column_of(const columns *c, const peri_sim *s, int32_t i) {
  int64_t k[2] = {0, 0};
  const int across = s->disc.geom.dim == 3 ? 2 : 1;
  for (int d = 0; d < across; ++d) {
    k[d] = llround((s->disc.p.x[3 * i + d] - c->lo[d]) / c->dx);
    k[d] = k[d] < 0 ? 0 : k[d] >= c->n[d] ? c->n[d] - 1 : k[d];
  }
  return k[0] + c->n[0] * k[1];
}

/* The strength of the bond between materials a and b: 0 when the pair has none (or when only
 * pairs with a strength count and this one has none), INFINITY when every pair counts. */
static double pair_limit(const peri_sim *s, int a, int b, bool strength_only) {
  if (a == b) return 0.0;
  if (!strength_only) return INFINITY;
  return s->mat.pair_strength[a * s->mat.n_materials + b];
}

/* out[3 * col + 0/1]: the normal traction on column col's nodes that have the other
 * material above (0) or below (1) them, over the pairs that count; out[3 * col + 2]: the
 * smallest strength of those pairs there (INFINITY: none). Summed (minimum) over all ranks in
 * rank order: the same on every rank. */
static double *column_tractions(const peri_sim *s, const columns *c, bool strength_only) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int up = s->disc.geom.dim == 3 ? 2 : 1;
  const double dx = c->dx;
  const size_t room = (size_t)(3 * c->count);
  double *local = peri_calloc(room, sizeof(double));
  for (int64_t k = 0; k < c->count; ++k) local[3 * k + 2] = INFINITY;
  /* one pass in node order (a few interface nodes; the order keeps the sums reproducible) */
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (p->flags[i] & (PERI_NODE_FICTITIOUS | PERI_NODE_NO_FAIL)) continue;
    const int a = p->material[i];
    /* which side the other material lies on, from the reference bonds */
    double side = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      if (pair_limit(s, a, p->material[j], strength_only) > 0.0) side += p->x[3 * j + up] - p->x[3 * i + up];
    }
    if (side == 0.0) continue;
    side = side > 0.0 ? 1.0 : -1.0;
    const double face = s->disc.geom.dim == 3 ? dx * dx : p->volume[i] / dx;
    double normal = 0.0, strength = INFINITY;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      const double lim = pair_limit(s, a, p->material[j], strength_only);
      if (!(lim > 0.0) || b->broken[k]) continue;
      double y[3];
      for (int d = 0; d < 3; ++d) y[d] = p->x[3 * j + d] + p->u[3 * j + d] - p->x[3 * i + d] - p->u[3 * i + d];
      const double r = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
      if (!(r > 0.0)) continue;
      const double force = s->mat.model->pair_force(s, i, k, r) * peri_bonds_beta(b, peri_bond_length(p->x, i, j)) *
                           p->volume[i] * p->volume[j];
      normal += force * y[up] / r * side; /* the pull towards the other material */
      strength = fmin(strength, lim);
    }
    const int64_t col = column_of(c, s, i);
    local[3 * col + (side > 0.0 ? 0 : 1)] += normal / face;
    local[3 * col + 2] = fmin(local[3 * col + 2], strength);
  }
  const int ranks = peri_comm_size();
  if (ranks == 1) return local;
  int64_t *counts = peri_malloc(sizeof(int64_t) * (size_t)ranks);
  for (int r = 0; r < ranks; ++r) counts[r] = (int64_t)room;
  double *every = peri_malloc(sizeof(double) * room * (size_t)ranks);
  peri_comm_allgather_doubles(local, (int64_t)room, counts, every);
  for (int64_t k = 0; k < c->count; ++k) {
    local[3 * k] = local[3 * k + 1] = 0.0;
    for (int r = 0; r < ranks; ++r) {
      const double *e = &every[(size_t)r * room + 3 * (size_t)k];
      local[3 * k] += e[0], local[3 * k + 1] += e[1], local[3 * k + 2] = fmin(local[3 * k + 2], e[2]);
    }
  }
  free(every);
  free(counts);
  return local;
}

double peri_interface_max_traction(const peri_sim *s) {
  const columns c = lattice_columns(s);
  double *trac = column_tractions(s, &c, false);
  double largest = 0.0;
  for (int64_t k = 0; k < c.count; ++k) largest = fmax(largest, fmax(trac[3 * k], trac[3 * k + 1]));
  free(trac);
  return largest;
}

long peri_break_interfaces_by_traction(peri_sim *s) {
  if (!s->mat.pair_strength) return 0;
  const columns c = lattice_columns(s);
  double *trac = column_tractions(s, &c, true);
  uint8_t *failed = peri_calloc((size_t)c.count, 1);
  bool any = false;
  for (int64_t k = 0; k < c.count; ++k) {
    failed[k] = isfinite(trac[3 * k + 2]) && fmax(trac[3 * k], trac[3 * k + 1]) >= trac[3 * k + 2];
    any = any || failed[k];
  }
  long broken = 0;
  if (any) {
    /* the pair's bonds of a failed column: from its nodes, and to them from the other side */
    peri_particles *p = &s->disc.p;
    peri_bonds *b = &s->disc.bonds;
    for (int32_t i = 0; i < p->n_owned; ++i) {
      if (p->flags[i] & PERI_NODE_NO_FAIL) continue;
      const int64_t ci = column_of(&c, s, i);
      for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
        const int32_t j = b->neighbor[k];
        if (b->broken[k] || !(pair_limit(s, p->material[i], p->material[j], true) > 0.0)) continue;
        if ((p->flags[j] & PERI_NODE_NO_FAIL)) continue;
        if (failed[ci] && !(p->flags[i] & PERI_NODE_FICTITIOUS)) {
          b->broken[k] = 1, ++broken;
        } else {
          const int64_t cj = column_of(&c, s, j);
          if (failed[cj] && !(p->flags[j] & PERI_NODE_FICTITIOUS)) b->broken[k] = 1, ++broken;
        }
      }
    }
    ++b->broken_edits;
  }
  free(failed);
  free(trac);
  return peri_comm_size() > 1 ? peri_comm_sum_long(broken) : broken;
}
