/* Boundary and initial conditions on regions, and external loads. */
#include <math.h>
#include <stdlib.h>
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/solver.h"

static void eval_at(peri_expr *e, const double *x, double t, double *out) {
  if (e) *out = peri_expr_eval(e, x[0], x[1], x[2], t);
}

void peri_apply_initial_conditions(peri_sim *s) {
  peri_particles *p = &s->p;
  for (int k = 0; k < s->n_bcs; ++k) {
    const peri_bc *bc = &s->bcs[k];
    const peri_region *r = &s->regions[bc->region];
    for (int32_t a = 0; a < r->count; ++a) {
      int32_t i = r->nodes[a];
      for (int d = 0; d < 3; ++d) {
        if (!bc->value[d]) continue;
        if (bc->kind == PERI_BC_INITIAL_DISPLACEMENT) eval_at(bc->value[d], &p->x[3 * i], 0.0, &p->u[3 * i + d]);
        if (bc->kind == PERI_BC_INITIAL_VELOCITY) eval_at(bc->value[d], &p->x[3 * i], 0.0, &p->v[3 * i + d]);
        if (bc->kind == PERI_BC_DISPLACEMENT || bc->kind == PERI_BC_VELOCITY)
          s->prescribed[3 * i + d] = 1;
      }
    }
  }
  /* Prescribed displacements hold from t = 0. */
  for (int k = 0; k < s->n_bcs; ++k) {
    const peri_bc *bc = &s->bcs[k];
    if (bc->kind != PERI_BC_DISPLACEMENT) continue;
    const peri_region *r = &s->regions[bc->region];
    for (int32_t a = 0; a < r->count; ++a) {
      int32_t i = r->nodes[a];
      for (int d = 0; d < 3; ++d) eval_at(bc->value[d], &p->x[3 * i], 0.0, &p->u[3 * i + d]);
    }
  }
}

void peri_apply_prescribed_motion(peri_sim *s, double t, double dt) {
  peri_particles *p = &s->p;
  for (int k = 0; k < s->n_bcs; ++k) {
    const peri_bc *bc = &s->bcs[k];
    if (bc->kind != PERI_BC_DISPLACEMENT && bc->kind != PERI_BC_VELOCITY) continue;
    const peri_region *r = &s->regions[bc->region];
    for (int32_t a = 0; a < r->count; ++a) {
      int32_t i = r->nodes[a];
      const double *x = &p->x[3 * i];
      for (int d = 0; d < 3; ++d) {
        peri_expr *e = bc->value[d];
        if (!e) continue;
        if (bc->kind == PERI_BC_DISPLACEMENT) {
          double u_new = peri_expr_eval(e, x[0], x[1], x[2], t);
          p->v[3 * i + d] = (u_new - p->u[3 * i + d]) / dt;
          p->u[3 * i + d] = u_new;
        } else {
          double v_old = peri_expr_eval(e, x[0], x[1], x[2], t - dt);
          double v_new = peri_expr_eval(e, x[0], x[1], x[2], t);
          p->u[3 * i + d] += 0.5 * (v_old + v_new) * dt;
          p->v[3 * i + d] = v_new;
        }
      }
    }
  }
}

/* LAMMPS fix indent: force k (R - r)^2 along the outward radius for r < R, added to the
 * force density as LAMMPS peri does (its per-atom "force" is a force density). With
 * `overwrite` the pass sets b of the owned nodes instead of adding to it (no other load). */
static void apply_indenter(peri_sim *s, double t, bool overwrite) {
  peri_indenter *ind = &s->indenter;
  peri_particles *p = &s->p;
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
      if (overwrite) b[0] = b[1] = b[2] = 0.0;
      if (r2 >= R * R) continue;
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

void peri_apply_loads(peri_sim *s, double t) {
  peri_particles *p = &s->p;
  bool loads = false;
  for (int k = 0; k < s->n_bcs; ++k)
    loads = loads || s->bcs[k].kind == PERI_BC_BODY_FORCE || s->bcs[k].kind == PERI_BC_TRACTION;
  /* the indenter alone sets b of the owned nodes in its own pass; else b starts from zero */
  const bool indenter_sets = s->indenter.on && !loads;
  const size_t zero_from = indenter_sets ? 3 * (size_t)p->n_owned : 0, zero_to = 3 * (size_t)p->n;
#pragma omp parallel for schedule(static) if (zero_to - zero_from > 65536)
  for (size_t c = zero_from; c < zero_to; ++c) p->b[c] = 0.0;
  for (int k = 0; k < s->n_bcs; ++k) {
    const peri_bc *bc = &s->bcs[k];
    if (bc->kind != PERI_BC_BODY_FORCE && bc->kind != PERI_BC_TRACTION) continue;
    const double scale = bc->kind == PERI_BC_TRACTION ? 1.0 / bc->layer : 1.0;
    const peri_region *r = &s->regions[bc->region];
    for (int32_t a = 0; a < r->count; ++a) {
      int32_t i = r->nodes[a];
      const double *x = &p->x[3 * i];
      for (int d = 0; d < 3; ++d)
        if (bc->value[d]) p->b[3 * i + d] += scale * peri_expr_eval(bc->value[d], x[0], x[1], x[2], t);
    }
  }
  if (s->indenter.on) apply_indenter(s, t, indenter_sets);
}
