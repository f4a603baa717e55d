/* The coupling section of the deck (docs/coupling.md, docs/deck.md): which nodes are PD, the
 * micromodulus family of the PD side, and the solver settings the coupled stiffness needs. */
#include <stdbool.h>
#include <string.h>
#include "peri/coupling.h"
#include "peri/error.h"
#include "peri/implicit.h"
#include "setup_parts.h"

#define TRY(expr)                   \
  do {                              \
    int rc_ = (expr);               \
    if (rc_ != PERI_OK) return rc_; \
  } while (0)

int peri_setup_coupling(peri_sim *s, const peri_node *root) {
  const peri_node *cp = peri_deck_get(root, "coupling");
  if (!cp) return PERI_OK;
  static const char *const keys[] = {"pd_region", "micromodulus_exponent", "gamma", "partial_volume", NULL};
  TRY(peri_deck_allow(cp, "coupling", keys));
  const char *name = NULL;
  TRY(peri_deck_string(cp, "pd_region", true, &name));
  const int r = peri_setup_find_region(s, peri_deck_get(root, "regions"), peri_deck_get(cp, "pd_region"), name);
  if (r < 0) return -r;
  double alpha = s->disc.geom.dim == 1 ? 1.0 : 3.0, gamma = 1.0;
  TRY(peri_deck_double(cp, "micromodulus_exponent", false, &alpha));
  TRY(peri_deck_double(cp, "gamma", false, &gamma));
  static const char *const rules[] = {"discretization", "exact", NULL};
  int rule = 0;
  TRY(peri_deck_choice(cp, "partial_volume", false, rules, &rule));
  if (rule == 1 && s->disc.geom.dim == 3)
    return peri_deck_error(peri_deck_get(cp, "partial_volume"), "key 'partial_volume': exact is for 1D and 2D "
                                                                "(Ongaro 2022 gives no 3D rule)");
  if (!(gamma > 0.0)) return peri_deck_error(peri_deck_get(cp, "gamma"), "key 'gamma': expected a positive factor, got %g", gamma);
  const bool state_based = s->mat.model->tangent_reach == 2 && s->mat.model->tangent;
  if (strcmp(s->mat.model->name, "pmb") != 0 && !state_based)
    return peri_deck_error(cp, "coupling: the PD side is bond-based (pmb) or a state-based model with a tangent "
                               "(lps): the materials have model %s", s->mat.model->name);
  static const char *const bond_only[] = {"micromodulus_exponent", "gamma", "partial_volume"};
  for (int k = 0; state_based && k < 3; ++k)
    if (peri_deck_get(cp, bond_only[k]))
      return peri_deck_error(peri_deck_key_node(cp, bond_only[k]), "key '%s': only for the bond-based PD side (model "
                                                                  "pmb); model %s takes its rows from its tangent",
                             bond_only[k], s->mat.model->name);
  const peri_node *solver = peri_deck_get(root, "solver");
  if (s->solver.kind != PERI_SOLVER_IMPLICIT)
    return peri_deck_error(solver ? solver : cp, "coupling: needs solver type implicit (the coupled stiffness is "
                                                 "assembled and solved by PETSc)");
  if (s->solver.breaking && !peri_deck_get(solver, "breaking"))
    s->solver.breaking = false; /* the coupled model is linear elastic: nothing breaks */
  if (s->solver.breaking)
    return peri_deck_error(peri_deck_get(solver, "breaking"), "key 'breaking': the coupled model is linear elastic; "
                                                              "bonds do not break in it (set breaking: false)");
  /* the coupled stiffness is not symmetric: LU by default, GMRES on request, never CG */
  if (!peri_deck_get(solver, "linear_solver")) {
    s->solver.qs.linear_solver = PERI_LINEAR_DIRECT;
    s->solver.qs.petsc_preconditioner = PERI_PC_LU;
  } else if (s->solver.qs.linear_solver == PERI_LINEAR_CG) {
    return peri_deck_error(peri_deck_get(solver, "linear_solver"), "key 'linear_solver': the coupled stiffness is "
                                                                   "not symmetric: use direct or gmres");
  }
  const peri_region *pd = &s->cond.regions[r];
  char why[512];
  if (peri_coupling_build(s, pd->nodes, pd->count, alpha, gamma, rule == 1, why, sizeof why) != PERI_OK)
    return peri_deck_error(cp, "coupling: %s", why);
  return PERI_OK;
}
