/* Heat conduction in time: sources and boundary conditions, the rate dT/dt, the algebraic
 * flux rule, forward Euler and RK4, growing cracks, and the staggered
 * coupling with the explicit mechanics (docs/model_reference.md 9, 11). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/conduction.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/sim.h"
#include "peri/thermal.h"

static double eval(peri_expr *e, const double *x, double t) { return peri_expr_eval(e, x[0], x[1], x[2], t); }

/* Ghost temperatures from their owners before a pass reads T of neighbours (MPI ranks,
 * docs/parallel.md; a no-op in one process). */
static void exchange(const peri_sim *s, double *T) { peri_sim_exchange((peri_sim *)s, T, 1); }

/* Volumetric sources w_i and linear sinks (convection) at time t (serial: expressions). */
static void eval_sources(const peri_sim *s, double t) {
  peri_thermal *th = s->thermal;
  const int32_t n = th->n;
  memset(th->source, 0, sizeof(double) * (size_t)n);
  memset(th->sink, 0, sizeof(double) * (size_t)n);
  for (int c = 0; c < th->n_bcs; ++c) {
    const peri_thermal_bc *bc = &th->bcs[c];
    if (bc->kind == PERI_TBC_TEMPERATURE || bc->kind == PERI_TBC_INITIAL) continue;
    if (bc->kind == PERI_TBC_HEAT_FLUX && th->insulation == PERI_TINSULATION_ALGEBRAIC) continue;
    const peri_region *r = &s->cond.regions[bc->region];
    const bool cv = peri_expr_is_constant(bc->value);
    const double v0 = cv ? eval(bc->value, s->disc.p.x, t) : 0.0;
    for (int32_t a = 0; a < r->count; ++a) {
      const int32_t i = r->nodes[a];
      const double *x = &s->disc.p.x[3 * i];
      const double v = cv ? v0 : eval(bc->value, x, t);
      if (bc->kind == PERI_TBC_HEAT_SOURCE) th->source[i] += v;
      else if (bc->kind == PERI_TBC_HEAT_FLUX) th->source[i] += v / bc->layer;
      else if (bc->kind == PERI_TBC_CONVECTION) {
        th->sink[i] += v / bc->layer;
        th->source[i] += v / bc->layer * eval(bc->ambient, x, t);
      }
    }
  }
}

void peri_thermal_prepare(peri_sim *s) {
  peri_thermal *th = s->thermal;
  const peri_bonds *b = &s->disc.bonds;
  const size_t n = (size_t)(th->n > 0 ? th->n : 1);
  if (!th->source) th->source = peri_calloc(n, sizeof(double));
  if (!th->sink) th->sink = peri_calloc(n, sizeof(double));
  if (!th->flux) th->flux = peri_calloc(3 * n, sizeof(double));
  for (int k = 0; k < 6; ++k)
    if (!th->work[k]) th->work[k] = peri_calloc(n, sizeof(double));
  eval_sources(s, 0.0);
  /* Gershgorin: |lambda| <= 2 sum_p w_ip + sink_i / (rho c)_i (docs/model_reference.md 11.6) */
  double worst = 0.0;
  for (int32_t i = 0; i < th->n; ++i) {
    double row = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) row += th->H[k];
    row = (row + 0.5 * th->sink[i]) / th->rhoc[i];
    if (row > worst) worst = row;
  }
  th->max_row_sum = worst;
}

void peri_thermal_rate(const peri_sim *s, const double *T, double t, double *out) {
  const peri_thermal *th = s->thermal;
  const peri_bonds *b = &s->disc.bonds;
  eval_sources(s, t);
  const double cc = th->crack_conductance;
  const uint8_t *cut = th->cut;
#pragma omp parallel for schedule(dynamic, 512)
  for (int32_t i = 0; i < th->n; ++i) {
    if (th->fixed[i]) {
      out[i] = 0.0;
      continue;
    }
    const double Ti = T[i];
    double sum = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const double w = cut[k] ? cc * th->H[k] : th->H[k];
      sum += w * (T[b->neighbor[k]] - Ti);
    }
    out[i] = (sum + th->source[i] - th->sink[i] * Ti) / th->rhoc[i];
  }
}

void peri_thermal_constrain(const peri_sim *s, double *T, double t) {
  peri_thermal *th = s->thermal;
  const peri_bonds *b = &s->disc.bonds;
  const peri_particles *p = &s->disc.p;
  for (int c = 0; c < th->n_bcs; ++c) {
    const peri_thermal_bc *bc = &th->bcs[c];
    if (bc->kind != PERI_TBC_TEMPERATURE) continue;
    const peri_region *r = &s->cond.regions[bc->region];
    for (int32_t a = 0; a < r->count; ++a) T[r->nodes[a]] = eval(bc->value, &p->x[3 * r->nodes[a]], t);
  }
  if (!th->alg_bc) return;
  exchange(s, T);
  /* algebraic flux nodes (Bobaru & Duangpanya 2012 sec. 3.2), Jacobi: every node from the same field */
  double *q = th->work[5];
  for (int32_t i = 0; i < th->n; ++i) {
    q[i] = 0.0;
    if (th->fixed[i] != 2 || th->alg_bc[i] < 0) continue;
    const peri_thermal_bc *bc = &th->bcs[th->alg_bc[i]];
    /* value = heat flux into the body; the rule imposes kappa dT/dx_axis = sign * value */
    q[i] = (th->alg_axis[i] > 0 ? 1.0 : -1.0) * eval(bc->value, &p->x[3 * i], t);
  }
  const double cc = th->crack_conductance;
  double *newT = th->flux; /* scratch: [3n] >= n */
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < th->n; ++i) {
    newT[i] = T[i];
    if (th->fixed[i] != 2) continue;
    const int axis = abs(th->alg_axis[i]) - 1;
    double num = 0.0, den = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      const double L = p->x[3 * j + axis] - p->x[3 * i + axis];
      const double hf = th->H[k] - th->Hs[k];
      const double w = (th->cut[k] ? cc : 1.0) * hf * L;
      num += w * T[j];
      den += w;
    }
    if (den != 0.0) newT[i] = (num - q[i]) / den;
  }
  for (int32_t i = 0; i < th->n; ++i)
    if (th->fixed[i] == 2) T[i] = newT[i];
}

long peri_thermal_grow_cracks(peri_sim *s, double t) {
  peri_thermal *th = s->thermal;
  long n = 0;
  while (th->growing_next < th->n_growing_bonds && th->growing_time[th->growing_next] <= t) {
    const int64_t k = th->growing_bond[th->growing_next++];
    if (!th->cut[k]) ++n;
    th->cut[k] = 1;
    s->disc.bonds.broken[k] = 1;
  }
  if (n > 0) ++s->disc.bonds.broken_edits;
  return n;
}

int peri_thermal_step(peri_sim *s, double dt) {
  peri_thermal *th = s->thermal;
  const int32_t n = th->n;
  const double t0 = th->time;
  peri_thermal_grow_cracks(s, t0);
  double *T = th->T;
  if (th->integrator == PERI_TINT_EULER) {
    double *k1 = th->work[0];
    exchange(s, T);
    peri_thermal_rate(s, T, t0, k1);
    for (int32_t i = 0; i < n; ++i) T[i] += dt * k1[i];
  } else {
    double *k1 = th->work[0], *k2 = th->work[1], *k3 = th->work[2], *k4 = th->work[3], *Y = th->work[4];
    exchange(s, T);
    peri_thermal_rate(s, T, t0, k1);
    for (int32_t i = 0; i < n; ++i) Y[i] = T[i] + 0.5 * dt * k1[i];
    peri_thermal_constrain(s, Y, t0 + 0.5 * dt);
    exchange(s, Y);
    peri_thermal_rate(s, Y, t0 + 0.5 * dt, k2);
    for (int32_t i = 0; i < n; ++i) Y[i] = T[i] + 0.5 * dt * k2[i];
    peri_thermal_constrain(s, Y, t0 + 0.5 * dt);
    exchange(s, Y);
    peri_thermal_rate(s, Y, t0 + 0.5 * dt, k3);
    for (int32_t i = 0; i < n; ++i) Y[i] = T[i] + dt * k3[i];
    peri_thermal_constrain(s, Y, t0 + dt);
    exchange(s, Y);
    peri_thermal_rate(s, Y, t0 + dt, k4);
    for (int32_t i = 0; i < n; ++i) T[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  }
  th->time = t0 + dt;
  peri_thermal_constrain(s, T, th->time);
  bool finite = true;
  for (int32_t i = 0; i < n; ++i) finite = finite && fabs(T[i]) < 1e100;
  if (!peri_comm_all(finite)) { /* every rank stops together */
    peri_error("the temperature diverged at t = %g: reduce the heat time step (stable estimate %g s)",
               th->time, peri_thermal_stable_dt(th));
    return PERI_ERR_RUN;
  }
  return PERI_OK;
}

void peri_thermal_update_strain(peri_sim *s) {
  const peri_thermal *th = s->thermal;
  if (!s->state.thermal_strain) return;
  const bool plane_strain = s->disc.geom.dim == 2 && s->disc.geom.plane == PERI_PLANE_STRAIN;
  for (int32_t i = 0; i < th->n; ++i) {
    const peri_material *m = &s->mat.materials[s->disc.p.material[i]];
    const double alpha = plane_strain ? (1.0 + m->nu) * m->thermal_expansion : m->thermal_expansion;
    s->state.thermal_strain[i] = alpha * (th->T[i] - th->T_ref[i]);
  }
  peri_sim_exchange(s, s->state.thermal_strain, 1); /* the bond stretch reads both ends */
}

int peri_thermal_couple(peri_sim *s, long step, double t) {
  peri_thermal *th = s->thermal;
  if (th->every == 0) {
    /* heat advanced every `every` mechanical steps when its step is the longer one */
    double ratio = floor(th->dt / s->solver.dt * (1.0 + 1e-12));
    th->every = ratio >= 1.0 ? (long)fmin(ratio, 1e9) : 1;
    th->substeps = ratio >= 1.0 ? 1 : (long)ceil(s->solver.dt / th->dt * (1.0 - 1e-12));
  }
  if (step % th->every != 0 && step != s->solver.steps) return PERI_OK;
  const double span = t - th->time;
  if (!(span > 0.0)) return PERI_OK;
  /* sub-steps no longer than the heat time step */
  long sub = (long)ceil(span / th->dt * (1.0 - 1e-12));
  if (sub < 1) sub = 1;
  const double h = span / (double)sub;
  for (long k = 0; k < sub; ++k) {
    int rc = peri_thermal_step(s, h);
    if (rc != PERI_OK) return rc;
  }
  th->time = t;
  peri_thermal_update_strain(s);
  return PERI_OK;
}
