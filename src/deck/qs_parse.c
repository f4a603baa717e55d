/* The quasi-static keys of the `solver` section (docs/solvers.md). */
#include <math.h>
#include <string.h>
#include "peri/error.h"
#include "peri/implicit.h"
#include "peri/quasistatic.h"
#include "peri/setup.h"

static const char *const qs_keys[] = {PERI_QUASI_STATIC_KEYS, NULL};

/* A key given for a solver type that does not use it. */
static int only_for(const peri_node *it, const char *key, const char *types) {
  if (!peri_deck_get(it, key)) return PERI_OK;
  return peri_deck_error(peri_deck_key_node(it, key), "key '%s': only for solver type %s", key, types);
}

#define TRY(expr)                   \
  do {                              \
    int rc_ = (expr);               \
    if (rc_ != PERI_OK) return rc_; \
  } while (0)

static int positive_long(const peri_node *it, const char *key, long min, long *out) {
  TRY(peri_deck_int(it, key, false, out));
  if (peri_deck_get(it, key) && *out < min)
    return peri_deck_error(peri_deck_get(it, key), "key '%s': must be >= %ld", key, min);
  return PERI_OK;
}

int peri_quasi_static_parse(peri_sim *s, const peri_node *it) {
  peri_quasi_static *q = &s->solver.qs;
  memset(q, 0, sizeof *q);
  if (!peri_is_quasi_static(s)) {
    TRY(peri_implicit_parse(s, it)); /* its keys: "only for solver type implicit" */
    for (int k = 0; qs_keys[k]; ++k)
      TRY(only_for(it, qs_keys[k], "adr, dynamic_relaxation or nlcg (quasi-static; also implicit)"));
    return PERI_OK;
  }
  const bool adr = s->solver.kind == PERI_SOLVER_ADR, dr = s->solver.kind == PERI_SOLVER_DYNAMIC_RELAXATION,
             cg = s->solver.kind == PERI_SOLVER_NLCG;
  if (peri_deck_get(it, "steps"))
    return peri_deck_error(peri_deck_key_node(it, "steps"), "key 'steps': quasi-static solvers take "
                           "'load_steps' (the number of load increments)");
  if (!dr) {
    TRY(only_for(it, "time_step", "dynamic_relaxation or explicit"));
    TRY(only_for(it, "safety_factor", "dynamic_relaxation or explicit"));
    TRY(only_for(it, "damping", "dynamic_relaxation or explicit"));
    TRY(only_for(it, "bond_damping", "dynamic_relaxation"));
  }
  if (!adr) TRY(only_for(it, "stiffness_factor", "adr"));
  if (!cg) TRY(only_for(it, "preconditioner", "nlcg"));

  q->load_steps = 1;
  q->tolerance = 1e-8;
  q->max_iterations = 200000;
  q->stiffness_factor = 5.0;
  q->preconditioner = true;
  q->max_cutbacks = 6;
  q->max_fracture_iterations = 10000;
  TRY(positive_long(it, "load_steps", 1, &q->load_steps));
  TRY(positive_long(it, "max_iterations", 1, &q->max_iterations));
  TRY(positive_long(it, "max_broken_per_step", 0, &q->max_broken_per_step));
  TRY(positive_long(it, "max_fracture_iterations", 1, &q->max_fracture_iterations));
  long cutbacks = q->max_cutbacks;
  TRY(positive_long(it, "max_cutbacks", 0, &cutbacks));
  if (cutbacks > 30) return peri_deck_error(peri_deck_get(it, "max_cutbacks"), "key 'max_cutbacks': must be <= 30");
  q->max_cutbacks = (int)cutbacks;
  TRY(peri_deck_double(it, "tolerance", false, &q->tolerance));
  if (!(q->tolerance > 0.0 && q->tolerance < 1.0))
    return peri_deck_error(peri_deck_get(it, "tolerance"), "key 'tolerance': must be in (0, 1) (a relative residual)");
  TRY(peri_deck_double(it, "stiffness_factor", false, &q->stiffness_factor));
  if (!(q->stiffness_factor > 0.0))
    return peri_deck_error(peri_deck_get(it, "stiffness_factor"), "key 'stiffness_factor': must be positive");
  static const char *const preconditioners[] = {"none", "jacobi", NULL};
  int pc = 1;
  TRY(peri_deck_choice(it, "preconditioner", false, preconditioners, &pc));
  q->preconditioner = pc == 1;
  TRY(peri_implicit_parse(s, it)); /* linear_solver, petsc_* and newton_tolerance (implicit_parse.c) */

  /* pseudo-time of the last load step */
  s->solver.end_time = 1.0;
  TRY(peri_deck_double(it, "end_time", false, &s->solver.end_time));
  if (!(s->solver.end_time > 0.0)) return peri_deck_error(peri_deck_get(it, "end_time"), "key 'end_time': must be positive");
  s->solver.steps = q->load_steps;
  s->solver.dt_given = 0.0;
  s->solver.safety_factor = 0.8;
  TRY(peri_deck_double(it, "time_step", false, &s->solver.dt_given));
  TRY(peri_deck_double(it, "safety_factor", false, &s->solver.safety_factor));
  TRY(peri_deck_double(it, "damping", false, &s->solver.damping));
  TRY(peri_deck_double(it, "bond_damping", false, &q->bond_damping));
  if (peri_deck_get(it, "time_step") && !(s->solver.dt_given > 0.0))
    return peri_deck_error(peri_deck_get(it, "time_step"), "key 'time_step': must be positive");
  if (!(s->solver.safety_factor > 0.0 && s->solver.safety_factor <= 1.0))
    return peri_deck_error(peri_deck_get(it, "safety_factor"), "key 'safety_factor': must be in (0, 1]");
  if (s->solver.damping < 0.0) return peri_deck_error(peri_deck_get(it, "damping"), "key 'damping': must be >= 0");
  if (q->bond_damping < 0.0)
    return peri_deck_error(peri_deck_get(it, "bond_damping"), "key 'bond_damping': must be >= 0");
  if (dr && !(s->solver.damping > 0.0) && !(q->bond_damping > 0.0))
    return peri_deck_error(it, "solver: dynamic_relaxation needs 'damping' (1/s, on the velocity) or "
                               "'bond_damping' (pairwise, Le 2014 eq. 2.43); near critical is fastest");
  s->solver.breaking = true;
  TRY(peri_deck_bool(it, "breaking", false, &s->solver.breaking));
  TRY(peri_qs_dynamic_parse(s, it)); /* dynamic_switch (src/deck/qs_dynamic_parse.c) */
  for (int k = 0; k < s->cond.n_bcs; ++k) {
    peri_bc_kind kind = s->cond.bcs[k].kind;
    if (kind == PERI_BC_VELOCITY || kind == PERI_BC_INITIAL_VELOCITY || kind == PERI_BC_INITIAL_DISPLACEMENT)
      return peri_deck_error(peri_deck_get(it, "type"),
                             "solver type '%s': boundary condition %d is of type %s, which needs explicit "
                             "dynamics; use type displacement (a function of the pseudo-time t)",
                             peri_deck_get(it, "type")->scalar, k + 1,
                             kind == PERI_BC_VELOCITY           ? "velocity"
                             : kind == PERI_BC_INITIAL_VELOCITY ? "initial_velocity"
                                                                : "initial_displacement");
  }
  return PERI_OK;
}
