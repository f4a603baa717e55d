/* Quasi-static solvers (docs/solvers.md; docs/model_reference.md 12): adaptive dynamic relaxation,
 * damped dynamic relaxation and nonlinear conjugate gradients, driven through load steps
 * with sequentially linear fracture (break, re-solve at the same load, cut back). */
#ifndef PERI_QUASISTATIC_H
#define PERI_QUASISTATIC_H
#include <stdio.h>
#include "peri/sim.h"
#include "peri/solver.h"

/* The solver keys that only quasi-static solvers take (for the deck's key list). */
#define PERI_QUASI_STATIC_KEYS                                                                   \
  "load_steps", "tolerance", "max_iterations", "stiffness_factor", "bond_damping",               \
      "preconditioner", "max_broken_per_step", "max_cutbacks", "max_fracture_iterations",          \
      "linear_solver", "petsc_preconditioner", "newton_tolerance", "petsc_options", "dynamic_switch"

/* Result of one solve at fixed loads. */
typedef enum { PERI_QS_CONVERGED = 0, PERI_QS_NOT_CONVERGED = 1, PERI_QS_DIVERGED = 2 } peri_qs_status;

/* Solves for equilibrium at the loads and prescribed displacements currently set (p->b,
 * prescribed components of p->u); bonds do not break during the solve. On return p->f
 * holds the internal force density at the final state and s->solver.qs.residual the relative
 * residual. Counts iterations in s->solver.qs. */
peri_qs_status peri_solve_adr(peri_sim *s);
peri_qs_status peri_solve_dynamic_relaxation(peri_sim *s);
peri_qs_status peri_solve_nlcg(peri_sim *s);
/* A quasi-static solver in the table of src/solver/qs_solvers.c. */
typedef struct peri_qs_solver_ops {
  peri_solver_kind kind;
  const char *name;                               /* solver.type in the deck */
  peri_qs_status (*solve)(peri_sim *s);           /* equilibrium at the present loads */
  int (*check_ranks)(const peri_sim *s, int ranks); /* PERI_ERR_INPUT with a message when it cannot
                                                     run on this many MPI ranks; NULL: any number */
} peri_qs_solver_ops;
/* The table entry of a solver kind, NULL for explicit and heat. */
const peri_qs_solver_ops *peri_qs_solver(peri_solver_kind kind);
/* The solver of s->solver. */
peri_qs_status peri_solve_equilibrium(peri_sim *s);
/* Whether the solver of s runs on `ranks` MPI ranks (a message and PERI_ERR_INPUT if not);
 * checked before the decomposition. */
int peri_solver_check_ranks(const peri_sim *s, int ranks);

/* Load steps with fracture (docs/model_reference.md 12.4): for n = 1..load_steps sets the loads at
 * t_n, solves, breaks every bond beyond its critical stretch and re-solves until none
 * breaks; cuts the increment back when more than max_broken_per_step break. Calls hook
 * after every load step (history, frames). Returns PERI_OK, or PERI_ERR_RUN with a
 * message when a solve does not converge (the state reached is kept). */
int peri_solve_quasi_static(peri_sim *s, peri_step_hook hook, void *ctx);

/* Summary line of the dynamic switch (time step, damping, arrest criteria). */
void peri_qs_dynamic_summary(const peri_sim *s, FILE *out);
/* A dynamic phase (src/solver/qs_dynamic.c): from the current state, explicit dynamics with
 * the loads held at pseudo-time t and bonds breaking, until the crack arrests or
 * max_dynamic_steps; then the velocities are zeroed and the loads set again at t. Calls
 * hook with s->solver.qs.phase = dynamic every history_every steps and at the end (history rows).
 * *stop is set when the hook asks to stop. Returns PERI_OK or PERI_ERR_RUN (diverged). */
int peri_qs_dynamic_phase(peri_sim *s, double t, peri_step_hook hook, void *ctx, bool *stop);

/* Summary line(s) for the solver settings. */
void peri_print_quasi_static_summary(const peri_sim *s, FILE *out);

/* Helpers shared by the solvers (src/solver/qs_common.c). */
/* Dot product of two arrays of ncomp values per node over the owned nodes of every rank,
 * summed in fixed-order blocks: independent of the numbers of threads and ranks. */
double peri_qs_dot(const peri_sim *s, const double *a, const double *b, int ncomp);
/* ADR fictitious density per node, Lambda_i = f_s/4 sum_j beta V_j c_eq (omega) / |xi|
 * (docs/model_reference.md 12.2), into lambda[n]. */
void peri_qs_density(const peri_sim *s, double fs, double *lambda);
/* Sets prescribed displacement components at pseudo-time t (velocity zero) and the loads. */
/* solve(s), and with tools under load control (docs/contact.md "Load control") the search
 * for their offsets at which the contact forces equal the loads at s->state.time, each point
 * an equilibrium by solve (src/solver/tool_load_static.c). */
peri_qs_status peri_tools_load_equilibrium(peri_sim *s, peri_qs_status (*solve)(peri_sim *));
void peri_qs_apply_loading(peri_sim *s, double t);
/* Internal forces at the current u (no breaking; loads re-evaluated with an indenter). */
void peri_qs_forces(peri_sim *s);
/* The status a residual gives: diverged when it is not finite (peri_qs_residual makes any
 * state that is not finite infinite), converged at or below the tolerance. */
peri_qs_status peri_qs_status_of(const peri_sim *s, double residual);
/* The external work of the load steps (src/solver/qs_work.c): the trapezoid rule over
 * accepted equilibrium states of the loads' and the supports' reactions' work. */
typedef struct peri_qs_work {
  double *u_old, *load_old; /* per owned component at the last accepted state */
} peri_qs_work;
/* Records the current state (displacements, external forces) as the last accepted one. */
void peri_qs_work_begin(peri_qs_work *w, const peri_sim *s);
/* Adds the work from the last accepted state to the current one to s->state.external_work. */
void peri_qs_work_step(peri_qs_work *w, peri_sim *s);
void peri_qs_work_free(peri_qs_work *w);
/* Called by the solvers after each iteration of a solve: records the iteration count and
 * residual of the solve under way and lets the run driver print progress (s->out.progress). */
void peri_qs_iteration(peri_sim *s, long iteration, double residual);
/* Out-of-balance force r = f + b on free components (0 on prescribed ones and on unused
 * dimensions) into r[3n]; returns |V r| / |reference| where the reference is the larger of
 * the applied load |V b| and the reaction |V f| on prescribed components. */
double peri_qs_residual(const peri_sim *s, double *r);

#endif
