/* Initial conditions and prescribed motion on regions (the loads are contributions:
 * src/solver/contributions/). */
#include <math.h>
#include <stdlib.h>
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/solver.h"

static void eval_at(peri_expr *e, const double *x, double t, double *out) {
  if (e) *out = peri_expr_eval(e, x[0], x[1], x[2], t);
}

void peri_apply_initial_conditions(peri_sim *s) {
  peri_particles *p = &s->disc.p;
  for (int k = 0; k < s->cond.n_bcs; ++k) {
    const peri_bc *bc = &s->cond.bcs[k];
    const peri_region *r = &s->cond.regions[bc->region];
    for (int32_t a = 0; a < r->count; ++a) {
      int32_t i = r->nodes[a];
      for (int d = 0; d < 3; ++d) {
        if (!bc->value[d]) continue;
        if (bc->kind == PERI_BC_INITIAL_DISPLACEMENT) eval_at(bc->value[d], &p->x[3 * i], 0.0, &p->u[3 * i + d]);
        if (bc->kind == PERI_BC_INITIAL_VELOCITY) eval_at(bc->value[d], &p->x[3 * i], 0.0, &p->v[3 * i + d]);
        if (bc->kind == PERI_BC_DISPLACEMENT || bc->kind == PERI_BC_VELOCITY)
          s->cond.prescribed[3 * i + d] = 1;
      }
    }
  }
  /* Prescribed displacements hold from t = 0. */
  for (int k = 0; k < s->cond.n_bcs; ++k) {
    const peri_bc *bc = &s->cond.bcs[k];
    if (bc->kind != PERI_BC_DISPLACEMENT) continue;
    const peri_region *r = &s->cond.regions[bc->region];
    for (int32_t a = 0; a < r->count; ++a) {
      int32_t i = r->nodes[a];
      for (int d = 0; d < 3; ++d) eval_at(bc->value[d], &p->x[3 * i], 0.0, &p->u[3 * i + d]);
    }
  }
}

void peri_apply_prescribed_motion(peri_sim *s, double t, double dt) {
  peri_particles *p = &s->disc.p;
  for (int k = 0; k < s->cond.n_bcs; ++k) {
    const peri_bc *bc = &s->cond.bcs[k];
    if (bc->kind != PERI_BC_DISPLACEMENT && bc->kind != PERI_BC_VELOCITY) continue;
    const peri_region *r = &s->cond.regions[bc->region];
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
