/* Solvers and the pieces they share: the stable time step, initial conditions and
 * prescribed motion, and the explicit integrator. The loads and everything else a step adds
 * to the model's force are contributions (peri/contribution.h). */
#ifndef PERI_SOLVER_H
#define PERI_SOLVER_H
#include "peri/contribution.h"
#include "peri/sim.h"

/* Stable time step estimate (docs/model_reference.md 13.2) without the safety factor:
 * min( min_i sqrt(2 rho_i / sum_j beta V_j c_eq omega / |xi|), dx / c_p ). */
double peri_stable_dt(const peri_sim *s);
/* The stiffness bound sum_j beta V_j c_eq (omega) / |xi| of node i's family (all bonds), used
 * by the stable step and the ADR fictitious density. */
double peri_node_stiffness_bound(const peri_sim *s, int32_t i);

/* Applies initial displacements and velocities (t = 0) and marks prescribed components. */
void peri_apply_initial_conditions(peri_sim *s);
/* Prescribed displacement/velocity at time t for the step t - dt -> t: sets u and v of
 * prescribed components. */
void peri_apply_prescribed_motion(peri_sim *s, double t, double dt);
/* Per-step callback for output; return nonzero to stop. */
typedef int (*peri_step_hook)(peri_sim *s, void *ctx);

/* Whether the hook after step `step` (the step just completed) reads nothing of the state
 * but its step and time, writes nothing and does not stop the run. */
typedef bool (*peri_step_quiet)(const peri_sim *s, long step, void *ctx);

/* Explicit dynamics with velocity-Verlet (docs/model_reference.md 13.1). Calls hook after every step. */
int peri_solve_explicit(peri_sim *s, peri_step_hook hook, void *ctx);
/* The same; after a step whose hook `quiet` says is quiet, the pass that finishes the step
 * also begins the next one (the first half kick and the drift): the same arithmetic in one
 * pass over the nodes instead of two. */
int peri_solve_explicit_hooked(peri_sim *s, peri_step_hook hook, peri_step_quiet quiet, void *ctx);
/* The energy an explicit run starts with (kinetic, and strain when displaced), the first term
 * of the energy put into the body that the runaway check bounds (docs/solvers.md section 10). */
double peri_explicit_energy_in(peri_sim *s);
/* The checks after an explicit step (every rank alike): the state finite, and with
 * check_runaway the kinetic energy within RUNAWAY_FACTOR of energy_in; PERI_OK, or the reason
 * written and PERI_ERR_RUN. */
int peri_explicit_check_step(const peri_sim *s, bool finite, double kinetic, double energy_in, bool check_runaway);

#endif
