/* Explicit dynamics: velocity-Verlet (docs/model_reference.md 13.1; Ongaro 2022 sec. 1.3.2), with optional
 * viscous damping, prescribed motion and external loads. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/solver.h"
#include "peri/thermal.h"

/* External force density on each component: applied loads on free components, and on
 * prescribed ones the reaction rho a - f that enforces the motion. */
static void external_load(const peri_sim *s, const double *v_old, double dt, double *load) {
  const peri_particles *p = &s->p;
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double rho = s->materials[p->material[i]].density;
    for (int d = 0; d < 3; ++d) {
      size_t c = 3 * (size_t)i + d;
      load[c] = s->prescribed[c] ? rho * (p->v[c] - v_old[c]) / dt - p->f[c] : p->b[c];
    }
  }
}

int peri_solve_explicit(peri_sim *s, peri_step_hook hook, void *ctx) {
  peri_particles *p = &s->p;
  const double dt = s->dt;
  const int32_t n = p->n_owned;
  const size_t n3 = 3 * (size_t)n;
  double *inv_rho = peri_malloc(sizeof(double) * n);
  for (int32_t i = 0; i < n; ++i) inv_rho[i] = 1.0 / s->materials[p->material[i]].density;
  double *u_old = peri_malloc(sizeof(double) * n3);
  double *v_old = peri_malloc(sizeof(double) * n3);
  /* the last step's load stays in the sim: a checkpoint carries it (docs/restart.md) */
  if (!s->step_load) s->step_load = peri_calloc(n3 > 0 ? n3 : 1, sizeof(double));
  double *load_old = s->step_load;
  const double damping = s->damping;
  const uint8_t *fixed = s->prescribed;
  double *node_work = peri_malloc(sizeof(double) * (n > 0 ? n : 1));

  peri_apply_loads(s, s->time);
  peri_exchange_state(s); /* ghost displacements (MPI ranks, docs/parallel.md) */
  if (s->step == 0) { /* a restart resumes with the checkpoint's forces and load */
    if (!s->forces_current) s->model->force(s);
    external_load(s, p->v, dt, load_old);
  }
  s->forces_current = false;
  /* accelerations at t = 0 live in f + b */
  int status = PERI_OK;
  for (long step = s->step; step < s->steps; ++step) {
#pragma omp parallel for schedule(static)
    for (int32_t i = 0; i < n; ++i) {
      for (int d = 0; d < 3; ++d) {
        size_t c = 3 * (size_t)i + d;
        u_old[c] = p->u[c];
        v_old[c] = p->v[c];
        if (fixed[c]) continue;
        double a = (p->f[c] + p->b[c]) * inv_rho[i] - damping * p->v[c];
        p->v[c] += 0.5 * dt * a;
        p->u[c] += dt * p->v[c];
      }
    }
    s->time += dt;
    s->step = step + 1;
    peri_apply_prescribed_motion(s, s->time, dt);
    peri_apply_loads(s, s->time);
    /* thermomechanics: heat advanced to t (sub-cycled), then the thermal strain (docs/heat.md) */
    if (s->thermal && peri_thermal_couple(s, s->step, s->time) != PERI_OK) {
      status = PERI_ERR_RUN;
      break;
    }
    peri_exchange_state(s);
    s->model->force(s);
    /* one pass over the nodes: second half-step of the velocity, the external load of the
     * step (applied loads, or the reaction rho a - f of prescribed motion), its work by the
     * trapezoid rule, and the finiteness check */
    bool finite = true;
#pragma omp parallel for schedule(static) reduction(&& : finite)
    for (int32_t i = 0; i < n; ++i) {
      const double rho = s->materials[p->material[i]].density;
      double work = 0.0;
      for (int d = 0; d < 3; ++d) {
        size_t c = 3 * (size_t)i + d;
        if (!fixed[c]) {
          double a = (p->f[c] + p->b[c]) * inv_rho[i];
          /* damping is implicit in the half-step velocity (docs/model_reference.md 12.1 erratum) */
          p->v[c] = (p->v[c] + 0.5 * dt * a) / (1.0 + 0.5 * dt * damping);
        }
        const double load = fixed[c] ? rho * (p->v[c] - v_old[c]) / dt - p->f[c] : p->b[c];
        work += 0.5 * (load_old[c] + load) * (p->u[c] - u_old[c]) * p->volume[i];
        load_old[c] = load;
        finite = finite && fabs(p->u[c]) < 1e100 && fabs(p->v[c]) < 1e100;
      }
      node_work[i] = work;
    }
    double step_total = 0.0; /* in fixed-order blocks: the same on any number of ranks */
    peri_sum_owned(s, node_work, 1, &step_total);
    s->external_work += step_total;
    finite = peri_comm_all(finite); /* every rank stops together */
    /* NaN fails the comparison; the bound catches a blow-up before energies overflow */
    if (!finite || !isfinite(s->external_work)) {
      peri_error("the solution diverged at step %ld (t = %g): displacement or velocity is not "
                 "finite; reduce the time step or check the loads", s->step, s->time);
      status = PERI_ERR_RUN;
    }
    if (status != PERI_OK) break;
    if (hook && hook(s, ctx)) break;
  }
  free(inv_rho);
  free(node_work);
  free(u_old);
  free(v_old);
  return status;
}
