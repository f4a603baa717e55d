/* Explicit dynamics: velocity-Verlet (docs/model_reference.md 13.1; Ongaro 2022 sec. 1.3.2), with optional
 * viscous damping, prescribed motion and external loads. */
#include <math.h>
#include <stdlib.h>
#include "peri/comm.h"
#include "peri/contribution.h"
#include "peri/coupling.h"
#include "peri/decompose.h"
#include "peri/energies.h"
#include "peri/error.h"
#include "peri/solver.h"

/* Runaway growth (docs/solvers.md section 10). Without a heat source the energy of the body
 * is bounded by what was put into it: KE + SE = KE_0 + SE_0 + W - (damping and broken bonds,
 * both >= 0), with W the work of the loads and of the prescribed motion, |W| <= the sum of the
 * steps' |work|. The kinetic energy checked is that of the half-step velocities (the current
 * velocity on prescribed components): the last half kick of a full-step velocity is paid by
 * work the next step counts, so a body struck from rest would otherwise show kinetic energy
 * before any work. A stable velocity-Verlet run keeps the balance up to its discretization
 * error (a few per cent; at most a factor 1/(1 - (w dt/2)^2) for a mode of frequency w, a
 * large one only within a hair of the stability limit), far below RUNAWAY_FACTOR, while an
 * unstable one multiplies its kinetic energy at every step and passes it within a few steps.
 * The sum rides on the pass and the collective that already sum the step's work, in the same
 * fixed-order blocks, so every rank takes the same decision. Heating (the thermal strain of
 * thermomechanics) adds energy that no load accounts for: no check there. */
#define RUNAWAY_FACTOR 1000.0

/* The strain energy of the state a run starts from. A body that no rank has displaced holds
 * none (every bond stretch is 0 without thermal strain), which spares the bond pass of the
 * energy in the usual start from rest; a displaced one (initial displacement, a restart)
 * pays it once. */
static double initial_strain_energy(peri_sim *s) {
  const double *u = s->disc.p.u;
  bool at_rest = true;
  for (size_t c = 0; c < 3 * (size_t)s->disc.p.n_owned && at_rest; ++c) at_rest = u[c] == 0.0;
  return peri_comm_all(at_rest) ? 0.0 : peri_strain_energy(s);
}

double peri_explicit_energy_in(peri_sim *s) { return peri_kinetic_energy(s) + initial_strain_energy(s); }

int peri_explicit_check_step(const peri_sim *s, bool finite, double kinetic, double energy_in, bool check_runaway) {
  /* NaN fails the comparison; the bound catches a blow-up before energies overflow */
  if (!finite || !isfinite(s->state.external_work)) {
    peri_error("the solution diverged at step %ld (t = %g): displacement or velocity is not "
               "finite; reduce the time step or check the loads", s->state.step, s->state.time);
    return PERI_ERR_RUN;
  }
  if (check_runaway && kinetic > RUNAWAY_FACTOR * energy_in) {
    peri_error("the solution diverged at step %ld (t = %g): the kinetic energy %.3g J exceeds %g times "
               "the energy put into the body (%.3g J: the initial energy and the work of the loads); "
               "the time step %g s is too large for stability: reduce solver.time_step or "
               "solver.safety_factor", s->state.step, s->state.time, kinetic, RUNAWAY_FACTOR, energy_in,
               s->solver.dt);
    return PERI_ERR_RUN;
  }
  return PERI_OK;
}

/* External force density on each component: applied loads on free components, and on
 * prescribed ones the reaction rho a - f that enforces the motion. */
static void external_load(const peri_sim *s, const double *v_old, double dt, double *load) {
  const peri_particles *p = &s->disc.p;
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double rho = s->mat.materials[p->material[i]].density;
    for (int d = 0; d < 3; ++d) {
      size_t c = 3 * (size_t)i + d;
      load[c] = s->cond.prescribed[c] ? rho * (p->v[c] - v_old[c]) / dt - p->f[c] : p->b[c];
    }
  }
}

/* The nodes with a prescribed component: their per-node mask (bit d for component d) and,
 * for those nodes only, a slot of the state at the start of the step (u then v), which the
 * reaction and the work of the prescribed motion need. Free components need no copy: their
 * displacement increment is dt times the half-step velocity. */
typedef struct {
  uint8_t *mask;    /* [n] */
  int32_t *slot;    /* [n], valid where mask != 0 */
  int32_t *node;    /* [count] */
  double *old;      /* [count][6] */
  int32_t count;
} held_nodes;

static held_nodes held_nodes_of(const peri_sim *s) {
  const int32_t n = s->disc.p.n_owned;
  held_nodes h = {peri_calloc(n > 0 ? (size_t)n : 1, 1), peri_malloc(sizeof(int32_t) * (n > 0 ? (size_t)n : 1)),
                  NULL, NULL, 0};
  for (int32_t i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d)
      if (s->cond.prescribed[3 * (size_t)i + d]) h.mask[i] |= (uint8_t)(1u << d);
    if (h.mask[i]) h.slot[i] = h.count++;
  }
  h.node = peri_malloc(sizeof(int32_t) * (h.count > 0 ? (size_t)h.count : 1));
  h.old = peri_malloc(sizeof(double) * 6 * (h.count > 0 ? (size_t)h.count : 1));
  for (int32_t i = 0; i < n; ++i)
    if (h.mask[i]) h.node[h.slot[i]] = i;
  return h;
}

static void held_nodes_free(held_nodes *h) {
  free(h->mask);
  free(h->slot);
  free(h->node);
  free(h->old);
}

/* The internal force density: the model's, or with a PD-FEM coupling the rows of the coupled
 * stiffness times u (docs/coupling.md, "Explicit dynamics"); a coupled run with breaking first
 * breaks the bonds past their critical stretch and switches the FEM nodes about them to PD
 * ("Switching during explicit dynamics"). */
static int internal_force(peri_sim *s) {
  if (!s->coupling) s->mat.model->force(s);
  else if (!s->solver.breaking) peri_coupling_force(s);
  else if (peri_coupling_break(s) < 0) return PERI_ERR_RUN; /* a node that may not switch, named */
  return PERI_OK;
}

/* The first half of a step on node i's free components: the half kick with the force of the
 * step's start, then the drift. One function for both passes that do it, so that a step
 * begun by the previous step's last pass is the same to the bit. */
static inline void kick_and_drift(peri_particles *p, int32_t i, uint8_t held, double inv_rho, double dt, double damping) {
  for (int d = 0; d < 3; ++d) {
    const size_t c = 3 * (size_t)i + d;
    if (held & (1u << d)) continue;
    const double a = (p->f[c] + p->b[c]) * inv_rho - damping * p->v[c];
    p->v[c] += 0.5 * dt * a;
    p->u[c] += dt * p->v[c];
  }
}

/* Keeps node i's displacement and velocity where it has prescribed components, before the
 * step moves them: the step's reaction and work read them. */
static inline void keep_held(const peri_particles *p, const held_nodes *held, int32_t i) {
  double *old = &held->old[6 * (size_t)held->slot[i]];
  for (int d = 0; d < 3; ++d) {
    old[d] = p->u[3 * (size_t)i + d];
    old[3 + d] = p->v[3 * (size_t)i + d];
  }
}

int peri_solve_explicit(peri_sim *s, peri_step_hook hook, void *ctx) {
  return peri_solve_explicit_hooked(s, hook, NULL, ctx);
}

int peri_solve_explicit_hooked(peri_sim *s, peri_step_hook hook, peri_step_quiet quiet, void *ctx) {
  peri_particles *p = &s->disc.p;
  const double dt = s->solver.dt;
  const int32_t n = p->n_owned;
  const size_t n3 = 3 * (size_t)n;
  double *inv_rho = peri_malloc(sizeof(double) * (n > 0 ? (size_t)n : 1));
  for (int32_t i = 0; i < n; ++i) inv_rho[i] = 1.0 / s->mat.materials[p->material[i]].density;
  /* half the node's mass, 0.5 V / (1/rho) as the kinetic energy below takes it (the volumes do
   * not change during the run): one division per node at the start, not per step */
  double *half_mass = peri_malloc(sizeof(double) * (n > 0 ? (size_t)n : 1));
  for (int32_t i = 0; i < n; ++i) half_mass[i] = 0.5 * p->volume[i] / inv_rho[i];
  /* the damped half kick divides by this; undamped (1 exactly) the division is skipped, which
   * gives the same number */
  const double damping_divisor = 1.0 + 0.5 * dt * s->solver.damping;
  held_nodes held = held_nodes_of(s);
  /* the last step's load stays in the sim: a checkpoint carries it (docs/restart.md) */
  if (!s->state.step_load) s->state.step_load = peri_calloc(n3 > 0 ? n3 : 1, sizeof(double));
  double *load_old = s->state.step_load;
  const double damping = s->solver.damping;
  /* the step's external work summed per block of nodes as the pass goes (peri_sum_blocks) */
  const int64_t n_blocks = peri_sum_blocks_owned(s);
  /* per block: the step's work, then the kinetic energy (the runaway check) */
  double *block_sums = peri_malloc(sizeof(double) * 2 * (n_blocks > 0 ? (size_t)n_blocks : 1));

  peri_apply_loads(s, s->state.time);
  peri_exchange_state(s); /* ghost displacements (MPI ranks, docs/parallel.md) */
  if (s->state.step == 0) { /* a restart resumes with the checkpoint's forces and load */
    if (!s->state.forces_current && internal_force(s) != PERI_OK) {
      free(inv_rho);
      free(half_mass);
      free(block_sums);
      held_nodes_free(&held);
      return PERI_ERR_RUN;
    }
    external_load(s, p->v, dt, load_old);
  }
  s->state.forces_current = false;
  /* the energy put into the body so far: the initial energy, then the steps' |work| */
  const bool check_runaway = !s->thermal;
  double energy_in = check_runaway ? peri_explicit_energy_in(s) : 0.0;
  /* accelerations at t = 0 live in f + b */
  int status = PERI_OK;
  bool begun = false; /* whether the previous step's last pass began this step */
  for (long step = s->state.step; step < s->solver.steps; ++step) {
    if (!begun) {
#pragma omp parallel for schedule(static) if (held.count > 4096)
      for (int32_t k = 0; k < held.count; ++k) keep_held(p, &held, held.node[k]);
#pragma omp parallel for schedule(static)
      for (int32_t i = 0; i < n; ++i) kick_and_drift(p, i, held.mask[i], inv_rho[i], dt, damping);
    }
    s->state.time += dt;
    s->state.step = step + 1;
    peri_apply_prescribed_motion(s, s->state.time, dt);
    /* what the force and the loads depend on besides u: the thermal strain of thermomechanics
     * (docs/heat.md), the offset of a load-controlled tool from the contact force of the step
     * before; then the loads, so that a tool's force is that of its position at t (a restart,
     * which evaluates the loads at the checkpoint's state, gets the same) */
    if (peri_contributions_before_force(s, s->state.step, s->state.time) != PERI_OK) {
      status = PERI_ERR_RUN;
      break;
    }
    peri_apply_loads(s, s->state.time);
    peri_exchange_state(s);
    if (internal_force(s) != PERI_OK) {
      status = PERI_ERR_RUN;
      break;
    }
    /* one pass over the nodes: second half-step of the velocity, the external load of the
     * step (applied loads, or the reaction rho a - f of prescribed motion), its work by the
     * trapezoid rule, and the finiteness check; when the hook after this step reads nothing
     * and another step follows, also the next step's first half, node by node */
    /* (a run stopped below for divergence has then begun its next step: it reports, not resumes) */
    const bool begin_next = quiet && step + 1 < s->solver.steps && quiet(s, s->state.step, ctx);
    bool finite = true;
#pragma omp parallel for schedule(static) reduction(&& : finite)
    for (int64_t k = 0; k < n_blocks; ++k) {
      const int32_t i0 = (int32_t)(k * PERI_SUM_BLOCK), i1 = i0 + PERI_SUM_BLOCK < n ? i0 + PERI_SUM_BLOCK : n;
      double work_sum = 0.0, ke_sum = 0.0;
      for (int32_t i = i0; i < i1; ++i) {
        const double *old = held.mask[i] ? &held.old[6 * (size_t)held.slot[i]] : NULL;
        double work = 0.0, v2 = 0.0;
        for (int d = 0; d < 3; ++d) {
          size_t c = 3 * (size_t)i + d;
          double load, du;
          if (!(held.mask[i] & (1u << d))) {
            const double v_half = p->v[c], a = (p->f[c] + p->b[c]) * inv_rho[i];
            /* damping is implicit in the half-step velocity (docs/model_reference.md 12.1 erratum) */
            p->v[c] = damping_divisor == 1.0 ? v_half + 0.5 * dt * a : (v_half + 0.5 * dt * a) / damping_divisor;
            load = p->b[c];
            du = dt * v_half;
            v2 += v_half * v_half;
          } else {
            v2 += p->v[c] * p->v[c];
            load = s->mat.materials[p->material[i]].density * (p->v[c] - old[3 + d]) / dt - p->f[c];
            du = p->u[c] - old[d];
          }
          work += 0.5 * (load_old[c] + load) * du * p->volume[i];
          load_old[c] = load;
          finite = finite && fabs(p->u[c]) < 1e100 && fabs(p->v[c]) < 1e100;
        }
        work_sum += work;
        ke_sum += half_mass[i] * v2;
        if (begin_next) {
          if (held.mask[i]) keep_held(p, &held, i);
          kick_and_drift(p, i, held.mask[i], inv_rho[i], dt, damping);
        }
      }
      block_sums[2 * k] = work_sum;
      block_sums[2 * k + 1] = ke_sum;
    }
    double totals[2] = {0.0, 0.0}; /* in fixed-order blocks: the same on any number of ranks */
    peri_sum_blocks(s, block_sums, 2, totals);
    const double step_total = totals[0], kinetic = totals[1];
    s->state.external_work += step_total;
    energy_in += fabs(step_total);
    finite = peri_comm_all(finite); /* every rank stops together */
    status = peri_explicit_check_step(s, finite, kinetic, energy_in, check_runaway);
    if (status != PERI_OK) break;
    begun = begin_next;
    if (hook && hook(s, ctx)) break;
  }
  free(inv_rho);
  free(half_mass);
  free(block_sums);
  held_nodes_free(&held);
  return status;
}
