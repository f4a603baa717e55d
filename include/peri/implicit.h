/* The implicit quasi-static solver (docs/solvers.md, "Implicit (Newton + PETSc)"): Newton's
 * method on V_i (f_i + b_i) = 0 with the models' tangent stiffness, linear solves by PETSc
 * (KSP), driven by PETSc's SNES. Built only when PETSc is found (PERI_HAVE_PETSC); without
 * it, a deck asking for it is rejected with a positioned message. */
#ifndef PERI_IMPLICIT_H
#define PERI_IMPLICIT_H
#include <stdbool.h>
#include "peri/quasistatic.h"

/* solver.linear_solver */
typedef enum {
  PERI_LINEAR_CG = 0,     /* conjugate gradients (symmetric tangent; GMRES if CG breaks down) */
  PERI_LINEAR_GMRES = 1,  /* restarted GMRES (any tangent) */
  PERI_LINEAR_DIRECT = 2, /* LU factorization (PETSc's own, or -pc_factor_mat_solver_type) */
} peri_linear_solver;

/* solver.petsc_preconditioner */
typedef enum {
  PERI_PC_GAMG = 0,   /* smoothed-aggregation algebraic multigrid, rigid-body near-null space */
  PERI_PC_JACOBI = 1,
  PERI_PC_ILU = 2,
  PERI_PC_LU = 3,
  PERI_PC_NONE = 4,
} peri_petsc_preconditioner;

/* Whether this build has the implicit solver. */
bool peri_implicit_available(void);

/* PETSc options from the command line (peri run --petsc-options "..."), applied after the
 * deck's solver.petsc_options. The string is copied. */
void peri_implicit_set_command_line_options(const char *options);

/* Newton solve at the loads and prescribed displacements currently set (the contract of
 * peri_solve_adr in quasistatic.h). Initializes PETSc on the first call. */
peri_qs_status peri_solve_implicit(peri_sim *s);

/* Relative residuals of the Newton iterations of the last solve, iteration 0 first: copies
 * up to max of them into out and returns how many there were. */
int peri_implicit_residual_history(double *out, int max);

/* Before a run on `ranks` MPI ranks: PERI_OK, or PERI_ERR_INPUT with a message when the
 * deck asks for an LU factorization (linear_solver direct, petsc_preconditioner lu) and this
 * PETSc has no parallel one (MUMPS, SuperLU_dist). Its entry in the solver table (src/solver/qs_solvers.c). */
int peri_implicit_check_ranks(const peri_sim *s, int ranks);

/* Finalizes PETSc if this process initialized it (also registered with atexit; safe to
 * call more than once). */
void peri_implicit_finalize(void);

#endif
