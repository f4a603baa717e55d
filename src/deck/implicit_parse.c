/* The implicit solver's keys of the `solver` section (docs/solvers.md, docs/deck.md). */
#include <ctype.h>
#include <string.h>
#include "peri/error.h"
#include "peri/implicit.h"
#include "peri/setup.h"

#define TRY(expr)                   \
  do {                              \
    int rc_ = (expr);               \
    if (rc_ != PERI_OK) return rc_; \
  } while (0)

static const char *const implicit_keys[] = {"linear_solver", "petsc_preconditioner", "newton_tolerance",
                                            "petsc_options", NULL};

/* Newton needs few iterations: more than this many means it is not converging. */
enum { DEFAULT_NEWTON_ITERATIONS = 50 };

/* PETSc options are "-name [value] -name [value] ...": the string must start with an option. */
static int check_petsc_options(const peri_node *at, const char *text) {
  const char *c = text;
  while (isspace((unsigned char)*c)) ++c;
  if (*c == '\0') return PERI_OK;
  if (c[0] != '-' || !isalpha((unsigned char)c[1]))
    return peri_deck_error(at, "key 'petsc_options': expected PETSc options such as \"-ksp_rtol 1e-10 "
                               "-snes_monitor\" (each option starts with '-'), got '%s'", text);
  return PERI_OK;
}

int peri_implicit_parse(peri_sim *s, const peri_node *it) {
  peri_quasi_static *q = &s->solver.qs;
  if (s->solver.kind != PERI_SOLVER_IMPLICIT) {
    for (int k = 0; implicit_keys[k]; ++k)
      if (peri_deck_get(it, implicit_keys[k]))
        return peri_deck_error(peri_deck_key_node(it, implicit_keys[k]), "key '%s': only for solver type implicit",
                               implicit_keys[k]);
    return PERI_OK;
  }
  if (!peri_implicit_available())
    return peri_deck_error(peri_deck_get(it, "type"),
                           "solver type 'implicit': this peri was built without PETSc (install petsc-dev, "
                           "e.g. with scripts/install-deps, and rebuild), or use type nlcg");
  static const char *const linear[] = {"cg", "gmres", "direct", NULL};
  static const char *const pcs[] = {"gamg", "jacobi", "ilu", "lu", "none", NULL};
  int choice = PERI_LINEAR_CG;
  TRY(peri_deck_choice(it, "linear_solver", false, linear, &choice));
  q->linear_solver = choice;
  choice = q->linear_solver == PERI_LINEAR_DIRECT ? PERI_PC_LU : PERI_PC_GAMG;
  TRY(peri_deck_choice(it, "petsc_preconditioner", false, pcs, &choice));
  q->petsc_preconditioner = choice;
  if (q->linear_solver == PERI_LINEAR_DIRECT && q->petsc_preconditioner != PERI_PC_LU)
    return peri_deck_error(peri_deck_get(it, "petsc_preconditioner"),
                           "key 'petsc_preconditioner': linear_solver direct is an LU factorization; "
                           "remove the preconditioner or choose linear_solver cg or gmres");
  if (peri_deck_get(it, "newton_tolerance")) {
    if (peri_deck_get(it, "tolerance"))
      return peri_deck_error(peri_deck_key_node(it, "newton_tolerance"),
                             "key 'newton_tolerance': give either 'tolerance' or 'newton_tolerance' "
                             "(the same relative residual)");
    TRY(peri_deck_double(it, "newton_tolerance", false, &q->tolerance));
    if (!(q->tolerance > 0.0 && q->tolerance < 1.0))
      return peri_deck_error(peri_deck_get(it, "newton_tolerance"),
                             "key 'newton_tolerance': must be in (0, 1) (a relative residual)");
  }
  if (!peri_deck_get(it, "max_iterations")) q->max_iterations = DEFAULT_NEWTON_ITERATIONS;
  const char *options = NULL;
  TRY(peri_deck_string(it, "petsc_options", false, &options));
  q->petsc_options[0] = '\0';
  if (options) {
    if (strlen(options) >= sizeof q->petsc_options)
      return peri_deck_error(peri_deck_get(it, "petsc_options"), "key 'petsc_options': longer than %zu characters",
                             sizeof q->petsc_options - 1);
    TRY(check_petsc_options(peri_deck_get(it, "petsc_options"), options));
    strcpy(q->petsc_options, options);
  }
  return PERI_OK;
}
