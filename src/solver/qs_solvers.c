/* The table of quasi-static solvers, as the model table is for models: each entry solves for
 * equilibrium at the loads and prescribed displacements currently set (the contract of
 * peri_solve_equilibrium) and may reject a number of MPI ranks it cannot run on. The load
 * stepping (quasi_static.c) and the dynamic switch reach a solver only through this table,
 * so the solvers and their shared helpers (qs_common.c) never call each other in a loop.
 * A new solver is one file, one line here and its name under solver.type in the deck. */
#include <stddef.h>
#include "peri/coupling.h"
#include "peri/error.h"
#include "peri/implicit.h"
#include "peri/quasistatic.h"

static const peri_qs_solver_ops solvers[] = {
    {PERI_SOLVER_ADR, "adr", peri_solve_adr, NULL},
    {PERI_SOLVER_DYNAMIC_RELAXATION, "dynamic_relaxation", peri_solve_dynamic_relaxation, NULL},
    {PERI_SOLVER_NLCG, "nlcg", peri_solve_nlcg, NULL},
    {PERI_SOLVER_IMPLICIT, "implicit", peri_solve_implicit, peri_implicit_check_ranks}, /* a parallel LU */
};

const peri_qs_solver_ops *peri_qs_solver(peri_solver_kind kind) {
  for (size_t k = 0; k < sizeof solvers / sizeof solvers[0]; ++k)
    if (solvers[k].kind == kind) return &solvers[k];
  return NULL;
}

peri_qs_status peri_solve_equilibrium(peri_sim *s) {
  const peri_qs_solver_ops *solver = peri_qs_solver(s->solver.kind);
  /* with load-controlled tools, the solver's solve inside the search for their offsets */
  return solver ? peri_tools_load_equilibrium(s, solver->solve) : PERI_QS_DIVERGED;
}

int peri_solver_check_ranks(const peri_sim *s, int ranks) {
  const peri_qs_solver_ops *solver = peri_qs_solver(s->solver.kind);
  if (ranks <= 1 || !solver || !solver->check_ranks) return PERI_OK;
  return solver->check_ranks(s, ranks);
}
