/* A dynamic phase of a quasi-static run (docs/solvers.md section 4): when a load step breaks
 * more bonds than solver.dynamic_switch.when_broken_exceeds, the crack is growing unstably and
 * sequentially linear re-solves would pick its path without inertia. The run continues with
 * the explicit integrator (peri_solve_explicit) at the held load, bonds breaking as in
 * dynamics, until the crack arrests; the load steps then resume from that state. */
#include <math.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/constants.h"
#include "peri/decompose.h"
#include "peri/energies.h"
#include "peri/error.h"
#include "peri/quasistatic.h"

typedef struct phase_ctx {
  const peri_qs_dynamic_switch *d;
  double clock;               /* s->state.time before each step: the step evaluates loads at clock + dt = t */
  double dt;
  long load_step;             /* the load step shown in history rows */
  peri_step_hook hook;        /* the run's hook (history rows) */
  void *hook_ctx;
  long quiet_needed;          /* steps without a broken bond that mean arrest */
  long broken, quiet;         /* broken bonds after the last step; steps since one broke */
  double ke_peak;
  bool arrested, stop;
} phase_ctx;

/* Time for a dilatational wave to cross the body twice, in steps: a crack that has not moved
 * in that time has arrested (the default of arrest_steps). */
static long wave_crossing_steps(const peri_sim *s, double dt) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i)
    for (int d = 0; d < 3; ++d) {
      lo[d] = fmin(lo[d], s->disc.p.x[3 * i + d]);
      hi[d] = fmax(hi[d], s->disc.p.x[3 * i + d]);
    }
  double diagonal2 = 0.0;
  for (int d = 0; d < s->disc.geom.dim; ++d) {
    const double extent = peri_comm_max(hi[d]) - peri_comm_min(lo[d]);
    if (isfinite(extent)) diagonal2 += extent * extent;
  }
  double speed = 0.0;
  for (int m = 0; m < s->mat.n_materials; ++m) {
    const peri_material *mat = &s->mat.materials[m];
    speed = fmax(speed, sqrt(peri_pwave_modulus(&s->disc.geom, mat->E, mat->nu, mat->K, mat->mu) / mat->density));
  }
  if (!(speed > 0.0) || !(diagonal2 > 0.0)) return 1000;
  const double steps = ceil(2.0 * sqrt(diagonal2) / (speed * dt));
  return steps < 10.0 ? 10 : steps > 1e9 ? 1000000000L : (long)steps;
}

/* The time step of the dynamic phase: given, or safety_factor x the stable estimate. */
static double phase_time_step(const peri_sim *s) {
  const peri_qs_dynamic_switch *d = &s->solver.qs.dynamic;
  return d->time_step > 0.0 ? d->time_step : d->safety_factor * peri_stable_dt(s);
}

void peri_qs_dynamic_summary(const peri_sim *s, FILE *out) {
  const peri_qs_dynamic_switch *d = &s->solver.qs.dynamic;
  if (!d->on) return;
  const double dt = phase_time_step(s);
  const long quiet = d->arrest_steps > 0 ? d->arrest_steps : wave_crossing_steps(s, dt);
  fprintf(out, "  dynamics     above %ld bonds broken in a load step: explicit, time step %g s, damping %g 1/s; "
               "arrest at kinetic energy < %g of its peak or %ld steps without a broken bond (at most %ld "
               "steps)\n", d->when_broken_exceeds, dt, d->damping, d->arrest_kinetic_energy, quiet,
          d->max_dynamic_steps);
}

/* A history row of the dynamic phase through the run's hook. */
static void report(peri_sim *s, phase_ctx *c) {
  if (!c->hook || c->stop) return;
  const double clock = s->state.time;
  const long step = s->state.step;
  s->state.time = c->clock + c->dt; /* the held load level */
  s->state.step = c->load_step;
  if (c->hook(s, c->hook_ctx)) c->stop = true;
  s->state.time = clock;
  s->state.step = step;
}

/* After every explicit step: hold the load, track the kinetic energy and breaking, decide arrest. */
static int after_step(peri_sim *s, void *vc) {
  phase_ctx *c = vc;
  const long done = s->state.step;
  s->state.time = c->clock; /* the next step evaluates the loads at t again */
  s->solver.qs.dynamic_time += c->dt;
  s->solver.qs.dynamic_steps++;
  const double ke = peri_kinetic_energy(s);
  const long broken = peri_global_broken(s);
  c->quiet = broken == c->broken ? c->quiet + 1 : 0;
  s->solver.qs.broken_in_run += broken - c->broken;
  c->broken = broken;
  c->ke_peak = fmax(c->ke_peak, ke);
  const bool settled = c->quiet > 0 && ke <= c->d->arrest_kinetic_energy * c->ke_peak;
  c->arrested = settled || c->quiet >= c->quiet_needed;
  if (s->out.progress) s->out.progress(s); /* progress lines */
  if (done % c->d->history_every == 0 && !c->arrested && done < c->d->max_dynamic_steps) report(s, c);
  return c->arrested || c->stop;
}

int peri_qs_dynamic_phase(peri_sim *s, double t, peri_step_hook hook, void *ctx, bool *stop) {
  const peri_qs_dynamic_switch *d = &s->solver.qs.dynamic;
  /* what the explicit integrator uses, restored afterwards */
  const double dt_saved = s->solver.dt, damping_saved = s->solver.damping, work_saved = s->state.external_work;
  const long step_saved = s->state.step, steps_saved = s->solver.steps;
  struct peri_thermal *thermal_saved = s->thermal;

  phase_ctx c = {.d = d, .dt = phase_time_step(s), .load_step = step_saved + 1, .hook = hook, .hook_ctx = ctx};
  c.clock = t - c.dt;
  c.quiet_needed = d->arrest_steps > 0 ? d->arrest_steps : wave_crossing_steps(s, c.dt);
  c.broken = peri_global_broken(s);
  const long broken_before = c.broken;
  s->solver.dt = c.dt;
  s->solver.damping = d->damping;
  s->solver.steps = d->max_dynamic_steps;
  s->state.step = 0;
  s->state.time = c.clock;
  s->thermal = NULL; /* the temperature field is held with the load */
  s->solver.qs.phase = PERI_QS_PHASE_DYNAMIC;
  s->solver.qs.dynamic_phases++;
  memset(s->disc.p.v, 0, sizeof(double) * 3 * (size_t)s->disc.p.n); /* from rest at the last equilibrium */

  int rc = peri_solve_explicit(s, after_step, &c);
  if (rc == PERI_OK) report(s, &c); /* the state at arrest */
  if (rc == PERI_OK && !c.arrested && !c.stop)
    peri_warning("dynamic phase at load step %ld (t = %g): the crack has not arrested after %ld steps "
                 "(kinetic energy above %g of its peak); the load steps resume (raise "
                 "solver.dynamic_switch.max_dynamic_steps or damping)",
                 step_saved + 1, t, d->max_dynamic_steps, d->arrest_kinetic_energy);
  if (!s->out.quiet && peri_comm_rank() == 0)
    printf("  dynamic      load step %ld (t = %g): %ld steps (%.3g s), %ld bonds broken, %s\n", step_saved + 1, t,
           s->state.step, (double)s->state.step * c.dt, c.broken - broken_before,
           c.arrested ? (c.quiet >= c.quiet_needed ? "arrested (no bond broke)" : "arrested (kinetic energy)")
                      : "not arrested");

  s->solver.qs.phase = PERI_QS_PHASE_STATIC;
  s->thermal = thermal_saved;
  s->solver.dt = dt_saved;
  s->solver.damping = damping_saved;
  s->state.external_work = work_saved;
  s->solver.steps = steps_saved;
  s->state.step = step_saved;
  peri_qs_apply_loading(s, t); /* exactly the held load; velocities zero */
  *stop = c.stop;
  return rc;
}
