/* Rigid spherical indenter (LAMMPS fix indent), its reaction and its tangent. */
#include <math.h>
#include <stdlib.h>
#include "peri/contribution.h"
#include "peri/decompose.h"
#include "peri/error.h"

/* LAMMPS fix indent: force k (R - r)^2 along the outward radius for r < R, added to the
 * force density as LAMMPS peri does (its per-atom "force" is a force density). With
 * `overwrite` the pass sets b of the owned nodes instead of adding to it (no other load). */
static void apply_indenter(peri_sim *s, double t, bool overwrite) {
  peri_indenter *ind = &s->cond.indenter;
  peri_particles *p = &s->disc.p;
  double c[3] = {0.0, 0.0, 0.0};
  for (int d = 0; d < 3; ++d)
    if (ind->center[d]) c[d] = peri_expr_eval(ind->center[d], 0.0, 0.0, 0.0, t);
  const double R = ind->radius, k = ind->stiffness;
  /* reactions summed per block in node order (peri_sum_blocks): independent of threads and ranks */
  const int32_t n = p->n_owned;
  const int64_t n_blocks = peri_sum_blocks_owned(s);
  if (ind->blocks != n_blocks) {
    free(ind->block_force);
    ind->block_force = peri_malloc(sizeof(double) * 3 * (size_t)(n_blocks > 0 ? n_blocks : 1));
    ind->blocks = n_blocks;
  }
#pragma omp parallel for schedule(static)
  for (int64_t blk = 0; blk < n_blocks; ++blk) {
    const int32_t i0 = (int32_t)(blk * PERI_SUM_BLOCK), i1 = i0 + PERI_SUM_BLOCK < n ? i0 + PERI_SUM_BLOCK : n;
    double sum[3] = {0.0, 0.0, 0.0}; /* nodes outside add nothing: a sum from +0 is never -0 */
    for (int32_t i = i0; i < i1; ++i) {
      double *b = &p->b[3 * (size_t)i];
      double d[3], r2 = 0.0;
      for (int a = 0; a < 3; ++a) {
        d[a] = p->x[3 * (size_t)i + a] + p->u[3 * (size_t)i + a] - c[a];
        r2 += d[a] * d[a];
      }
      if (r2 >= R * R) {
        /* outside: b is +0 when the last pass left it so; reading spares writing every node */
        if (overwrite && (b[0] != 0.0 || b[1] != 0.0 || b[2] != 0.0 || signbit(b[0]) || signbit(b[1]) || signbit(b[2])))
          b[0] = b[1] = b[2] = 0.0;
        continue;
      }
      if (overwrite) b[0] = b[1] = b[2] = 0.0;
      double r = sqrt(r2);
      if (r == 0.0) continue;
      double mag = k * (R - r) * (R - r) / r;
      for (int a = 0; a < 3; ++a) {
        b[a] += mag * d[a];
        sum[a] += -mag * d[a] * p->volume[i];
      }
    }
    for (int a = 0; a < 3; ++a) ind->block_force[3 * blk + a] = sum[a];
  }
  peri_sum_blocks(s, ind->block_force, 3, ind->force);
}

/* The indenter's force density k (R - r)^2 n on nodes inside it depends on u_i:
 * d b_i / d u_i = k [(R - r)^2 / r (I - n n^T) - 2 (R - r) n n^T]. */
static void indenter_tangent(const peri_sim *s, peri_tangent_add_fn add, void *ctx) {
  const peri_indenter *ind = &s->cond.indenter;
  const peri_particles *p = &s->disc.p;
  double centre[3] = {0.0, 0.0, 0.0};
  for (int d = 0; d < 3; ++d)
    if (ind->center[d]) centre[d] = peri_expr_eval(ind->center[d], 0.0, 0.0, 0.0, s->state.time);
  const double R = ind->radius, k = ind->stiffness;
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double y[3], r2 = 0.0;
    for (int d = 0; d < 3; ++d) {
      y[d] = p->x[3 * i + d] + p->u[3 * i + d] - centre[d];
      r2 += y[d] * y[d];
    }
    if (r2 >= R * R || r2 == 0.0) continue;
    const double r = sqrt(r2), tangential = k * (R - r) * (R - r) / r, normal = -2.0 * k * (R - r);
    double K[9]; /* d b_i / d u_i: enters like a tangent block of f_i (F = -V (f + b)) */
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const double nn = y[a] * y[b] / r2;
        K[3 * a + b] = tangential * ((a == b) - nn) + normal * nn;
      }
    add(ctx, i, 1, &i, K);
  }
}

static bool indenter_active(const peri_sim *s) { return s->cond.indenter.on; }

const peri_contribution_ops peri_contribution_indenter = {
    .name = "indenter",
    .active = indenter_active,
    .add_load = apply_indenter,
    .sets_every_node = true,
    .follows_deformation = true,
    .tangent = indenter_tangent,
};
