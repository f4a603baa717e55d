/* The implicit quasi-static solver (docs/solvers.md, "Implicit (Newton + PETSc)"): Newton's
 * method (PETSc SNES, newtonls: line search on |F|^2) on
 *   F(u) = -V_i (f_i(u) + b_i) = 0 on free components,
 * with the Jacobian dF/du = -V_i K_ij assembled from the model's tangent (model.h) into an
 * AIJ matrix of block size dim (create_matrix). On MPI ranks the matrix and vectors are
 * distributed over PETSC_COMM_WORLD: equation d of node i is dim * global_id[i] + d, so each
 * rank owns the equations of its owned nodes, in the global (Morton) order; in one process
 * the numbering is the identity. Prescribed components
 * already hold their values when the solve starts (peri_qs_apply_loading), so their Newton
 * updates are zero: their rows and columns are zeroed with a unit diagonal and F = 0 there.
 * Nodes with no intact bond are held the same way (their rows are empty). Linear solves by
 * KSP: CG + GAMG by default (the tangent of an energy is symmetric), GMRES when CG breaks
 * down (an indefinite tangent under compression) or on request, LU on request; a diagonal
 * shift when the tangent is singular (pieces set loose by fracture). Convergence uses the
 * quasi-static relative residual of every solver (peri_qs_residual). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "peri/comm.h"
#include "peri/contribution.h"
#include "peri/coupling.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/implicit.h"

static char *command_line_options; /* --petsc-options */

void peri_implicit_set_command_line_options(const char *options) {
  free(command_line_options);
  command_line_options = options ? peri_strdup(options) : NULL;
}

/* Relative residuals of the Newton iterations of the last solve (iteration 0 first). */
enum { HISTORY_MAX = 256 };
static double history[HISTORY_MAX];
static int history_count;

int peri_implicit_residual_history(double *out, int max) {
  int n = history_count < max ? history_count : max;
  for (int k = 0; k < n; ++k) out[k] = history[k];
  return history_count;
}

bool peri_implicit_available(void) {
#ifdef PERI_HAVE_PETSC
  return true;
#else
  return false;
#endif
}

#ifndef PERI_HAVE_PETSC

peri_qs_status peri_solve_implicit(peri_sim *s) {
  (void)s;
  peri_error("implicit: this peri was built without PETSc");
  return PERI_QS_DIVERGED;
}

void peri_implicit_finalize(void) { peri_implicit_set_command_line_options(NULL); }

int peri_implicit_check_ranks(const peri_sim *s, int ranks) {
  (void)s, (void)ranks; /* the deck was rejected already (peri_implicit_parse) */
  return PERI_OK;
}

#else
#include <petscsnes.h>

/* The LU factorization that runs on several ranks (linear_solver direct, petsc_preconditioner
 * lu), if this PETSc has one; PETSc's own LU is sequential. */
static const char *parallel_lu(void) {
#if defined(PETSC_HAVE_MUMPS)
  return MATSOLVERMUMPS;
#elif defined(PETSC_HAVE_SUPERLU_DIST)
  return MATSOLVERSUPERLU_DIST;
#else
  return NULL;
#endif
}

int peri_implicit_check_ranks(const peri_sim *s, int ranks) {
  const bool lu = s->solver.qs.linear_solver == PERI_LINEAR_DIRECT || s->solver.qs.petsc_preconditioner == PERI_PC_LU;
  if (ranks <= 1 || !lu || parallel_lu()) return PERI_OK;
  const char *what = s->solver.qs.linear_solver == PERI_LINEAR_DIRECT ? "linear_solver direct" : "petsc_preconditioner lu";
  peri_error("%s: the LU factorization of %s needs MUMPS or SuperLU_dist on %d ranks, and this PETSc has "
             "neither: use linear_solver cg or gmres (petsc_preconditioner gamg or jacobi), or run in one process",
             s->deck_path, what, ranks);
  return PERI_ERR_INPUT;
}

static bool petsc_initialized_here;
static pid_t petsc_pid; /* the process that started PETSc (not one forked from it: src/io/guarded_read.c) */

void peri_implicit_finalize(void) {
  peri_implicit_set_command_line_options(NULL);
  if (!petsc_initialized_here || getpid() != petsc_pid) return;
  petsc_initialized_here = false;
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) PetscFinalize(); /* MPI finalized by its owner first: nothing left to do */
}

/* PETSc starts on the first implicit solve, so other runs never pay for MPI and PETSc. */
static int start_petsc(void) {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (initialized) return PERI_OK;
  if (PetscInitializeNoArguments()) {
    peri_error("implicit: PETSc failed to initialize");
    return PERI_ERR_RUN;
  }
  /* peri's own handlers (and sanitizers, test runners) keep the signals */
  PetscPopSignalHandler();
  petsc_initialized_here = true, petsc_pid = getpid();
  atexit(peri_implicit_finalize);
  return PERI_OK;
}

typedef struct implicit_ctx {
  peri_sim *s;
  int dim;
  PetscInt n_eq;        /* dim * n_owned: this rank's equations */
  PetscInt n_eq_global; /* dim * nodes of all ranks */
  const int32_t *global_id; /* [p.n] global node of each local node; NULL in one process */
  uint8_t *held;        /* [n_eq] prescribed, or a node with no intact bond */
  PetscInt *held_rows;  /* global equations */
  PetscInt n_held;
  double *r;            /* [3n] out-of-balance force density */
  double rel;           /* relative residual of the last evaluation */
  double shift;         /* J += shift |diag J|: makes a singular tangent (a loose piece) regular */
  double fnorm_start;   /* |F| when the solve started */
  bool roundoff;        /* |F| fell to round-off: ROUNDOFF times |F| at the start */
  Mat A;                /* the matrix being assembled */
  PetscErrorCode error; /* first PETSc error inside a callback */
  /* one row at a time: columns sorted (PETSc then inserts in one pass) and values */
  struct column { PetscInt col; int32_t at; } *order;
  PetscInt *cols;
  PetscScalar *values;
  int32_t capacity;
} implicit_ctx;

/* u on free components from the Newton iterate. */
static PetscErrorCode set_displacement(implicit_ctx *c, Vec x) {
  peri_particles *p = &c->s->disc.p;
  const PetscScalar *xa;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(x, &xa));
  for (int32_t i = 0; i < p->n_owned; ++i)
    for (int d = 0; d < c->dim; ++d) {
      const PetscInt e = (PetscInt)c->dim * i + d;
      if (!c->held[e]) p->u[3 * (size_t)i + d] = xa[e];
    }
  PetscCall(VecRestoreArrayRead(x, &xa));
  PetscFunctionReturn(0);
}

static PetscErrorCode form_function(SNES snes, Vec x, Vec F, void *vctx) {
  implicit_ctx *c = vctx;
  peri_sim *s = c->s;
  PetscScalar *fa;
  (void)snes;
  PetscFunctionBeginUser;
  PetscCall(set_displacement(c, x));
  peri_qs_forces(s);
  c->rel = peri_qs_residual(s, c->r);
  PetscCall(VecGetArray(F, &fa));
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i)
    for (int d = 0; d < c->dim; ++d) {
      const PetscInt e = (PetscInt)c->dim * i + d;
      fa[e] = c->held[e] ? 0.0 : -s->disc.p.volume[i] * c->r[3 * (size_t)i + d];
    }
  PetscCall(VecRestoreArray(F, &fa));
  PetscFunctionReturn(0);
}

/* Equation dim * node + component: the global node is the Morton index on MPI ranks (rank r
 * owns the equations dim * [first[r], first[r+1])), the local index in one process. */
static inline PetscInt global_node(const implicit_ctx *c, int32_t i) {
  return c->global_id ? (PetscInt)c->global_id[i] : (PetscInt)i;
}

static int by_column(const void *a, const void *b) {
  const PetscInt x = ((const struct column *)a)->col, y = ((const struct column *)b)->col;
  return (x > y) - (x < y);
}

/* Row i of J: J_ij += -V_i K_ij (the dim x dim part of each block), columns in order, in
 * global numbering. The row of a ghost node goes to its owner at assembly. */
static void add_row(void *vctx, int32_t i, int32_t count, const int32_t *cols, const double *blocks) {
  implicit_ctx *c = vctx;
  if (c->error || count <= 0) return;
  if (count > c->capacity) {
    c->capacity = 2 * count;
    c->order = peri_realloc(c->order, sizeof *c->order * (size_t)c->capacity);
    c->cols = peri_realloc(c->cols, sizeof(PetscInt) * (size_t)c->capacity);
    c->values = peri_realloc(c->values, sizeof(PetscScalar) * 9 * (size_t)c->capacity);
  }
  for (int32_t k = 0; k < count; ++k) c->order[k] = (struct column){global_node(c, cols[k]), k};
  qsort(c->order, (size_t)count, sizeof *c->order, by_column);
  const int dim = c->dim;
  const double V = c->s->disc.p.volume[i];
  const size_t width = (size_t)count * dim; /* values row-major over the block row */
  for (int32_t k = 0; k < count; ++k) {
    c->cols[k] = c->order[k].col;
    const double *K = &blocks[9 * (size_t)c->order[k].at];
    for (int a = 0; a < dim; ++a)
      for (int b = 0; b < dim; ++b) c->values[a * width + (size_t)k * dim + b] = -V * K[3 * a + b];
  }
  const PetscInt row = global_node(c, i);
  c->error = MatSetValuesBlocked(c->A, 1, &row, count, c->cols, c->values, ADD_VALUES);
}

static PetscErrorCode form_jacobian(SNES snes, Vec x, Mat J, Mat P, void *vctx) {
  implicit_ctx *c = vctx;
  (void)snes;
  PetscFunctionBeginUser;
  PetscCall(set_displacement(c, x));
  peri_exchange_state(c->s); /* the ghosts' displacements at x (MPI ranks) */
  PetscCall(MatZeroEntries(P));
  c->A = P;
  c->error = 0;
  if (c->s->coupling) peri_coupling_rows(c->s, add_row, c); /* FEM rows and PD rows (docs/coupling.md) */
  else c->s->mat.model->tangent(c->s, add_row, c);
  peri_contributions_tangent(c->s, add_row, c); /* loads that depend on u (indenter) */
  PetscCall(c->error);
  PetscCall(MatAssemblyBegin(P, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(P, MAT_FINAL_ASSEMBLY));
  if (c->shift > 0.0) {
    Vec diag;
    PetscCall(MatCreateVecs(P, &diag, NULL));
    PetscCall(MatGetDiagonal(P, diag));
    PetscCall(VecAbs(diag));
    PetscCall(VecScale(diag, c->shift));
    PetscCall(MatDiagonalSet(P, diag, ADD_VALUES));
    PetscCall(VecDestroy(&diag));
  }
  PetscCall(MatZeroRowsColumns(P, c->n_held, c->held_rows, 1.0, NULL, NULL));
  if (J != P) {
    PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  }
  PetscFunctionReturn(0);
}

/* Newton has converged to round-off when |F| has fallen by this factor within one solve. This
 * matters only when the reference force of the relative residual vanishes (nothing loaded:
 * a piece moved rigidly by its prescribed displacements), where no relative measure works. */
#define ROUNDOFF 1e-12

/* Converged when the quasi-static relative residual reaches the tolerance, or at round-off. */
static PetscErrorCode converged_test(SNES snes, PetscInt it, PetscReal xnorm, PetscReal step, PetscReal fnorm,
                                     SNESConvergedReason *reason, void *vctx) {
  implicit_ctx *c = vctx;
  const peri_quasi_static *q = &c->s->solver.qs;
  (void)snes, (void)xnorm, (void)step;
  PetscFunctionBeginUser;
  if (history_count < HISTORY_MAX) history[history_count] = c->rel;
  history_count++;
  if (getenv("PERI_QS_DEBUG") && peri_comm_rank() == 0)
    fprintf(stderr, "implicit %ld: relative residual %.3e |F| %.3e\n", (long)it, c->rel, fnorm);
  if (c->fnorm_start == 0.0) c->fnorm_start = fnorm;
  peri_qs_iteration(c->s, (long)it, c->rel); /* progress lines */
  *reason = SNES_CONVERGED_ITERATING;
  if (!isfinite(c->rel) || !isfinite(fnorm)) *reason = SNES_DIVERGED_FNORM_NAN;
  else if (c->rel <= q->tolerance) *reason = SNES_CONVERGED_FNORM_ABS;
  else if (fnorm <= ROUNDOFF * c->fnorm_start) *reason = SNES_CONVERGED_FNORM_RELATIVE, c->roundoff = true;
  else if (it >= q->max_iterations) *reason = SNES_DIVERGED_MAX_IT;
  PetscFunctionReturn(0);
}

/* Before each Newton step: the linear solve need not go further than a hundredth of what the
 * tolerance asks of the nonlinear residual, whose scale (the reactions) changes as it goes. */
static PetscErrorCode update_linear_tolerance(SNES snes, PetscInt step) {
  implicit_ctx *c;
  KSP ksp;
  PetscReal rtol, atol, dtol;
  PetscInt maxits;
  PetscFunctionBeginUser;
  (void)step;
  PetscCall(SNESGetApplicationContext(snes, &c));
  const peri_quasi_static *q = &c->s->solver.qs;
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPGetTolerances(ksp, &rtol, &atol, &dtol, &maxits));
  PetscCall(KSPSetTolerances(ksp, rtol, 1e-2 * q->tolerance * fmax(q->last_reference, q->reference), dtol, maxits));
  PetscFunctionReturn(0);
}

/* Block nonzeros of each row: the node, its intact bonds, and for reach 2 their intact bonds;
 * with a coupling, an FEM node's row holds the corners of its elements instead. */
static PetscInt *count_blocks(const peri_sim *s, int reach) {
  const peri_bonds *b = &s->disc.bonds;
  const int32_t n = s->disc.p.n_owned;
  PetscInt *count = peri_calloc((size_t)(n > 0 ? n : 1), sizeof(PetscInt));
  int32_t *mark = peri_malloc(sizeof(int32_t) * (size_t)(s->disc.p.n > 0 ? s->disc.p.n : 1));
  for (int32_t i = 0; i < s->disc.p.n; ++i) mark[i] = -1;
  const peri_coupling *cp = s->coupling;
  for (int32_t i = 0; i < n; ++i) {
    PetscInt c = 1;
    mark[i] = i;
    if (cp && !cp->node_type[i]) { /* an FEM row: the corners of its elements (docs/coupling.md) */
      for (int64_t q = cp->node_offset[i]; q < cp->node_offset[i + 1]; ++q) {
        const int32_t e = cp->node_element[q];
        for (int64_t a = cp->element_offset[e]; a < cp->element_offset[e + 1]; ++a)
          if (mark[cp->element_nodes[a]] != i) mark[cp->element_nodes[a]] = i, ++c;
      }
      count[i] = c;
      continue;
    }
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      if (mark[j] != i) mark[j] = i, ++c;
      if (reach < 2) continue;
      for (int64_t l = b->offset[j]; l < b->offset[j + 1]; ++l) {
        const int32_t m = b->neighbor[l];
        if (!b->broken[l] && mark[m] != i) mark[m] = i, ++c;
      }
    }
    count[i] = c;
  }
  free(mark);
  return count;
}

/* Prescribed components, and every component of a node with no intact bond (with a coupling:
 * of a PD node with none, or an FEM node in no element; the coarse nodes of a graded mesh have
 * no bond, as their neighbours lie beyond the horizon). */
static void find_held(implicit_ctx *c) {
  const peri_sim *s = c->s;
  const peri_bonds *b = &s->disc.bonds;
  c->held = peri_calloc((size_t)c->n_eq + 1, 1);
  c->held_rows = peri_malloc(sizeof(PetscInt) * ((size_t)c->n_eq + 1));
  c->n_held = 0;
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i) {
    const peri_coupling *cp = s->coupling;
    bool bonded = cp && !cp->node_type[i] && cp->node_offset[i + 1] > cp->node_offset[i];
    for (int64_t k = b->offset[i]; k < b->offset[i + 1] && !bonded; ++k) bonded = !b->broken[k];
    for (int d = 0; d < c->dim; ++d) {
      const PetscInt e = (PetscInt)c->dim * i + d;
      if (s->cond.prescribed[3 * (size_t)i + d] || !bonded) {
        c->held[e] = 1;
        c->held_rows[c->n_held++] = (PetscInt)c->dim * global_node(c, i) + d;
      }
    }
  }
}

/* The Jacobian's matrix (block size dim, rows of rank r: its owned equations), preallocated:
 * in one process from the bond lists (count_blocks: 0.05 s against 4 s for the preallocator
 * on the plate with a hole at delta = 1.5 mm, m = 3, 18,736 nodes); on several ranks, where
 * the families of ghosts are not at hand, by a symbolic pass of the tangent itself into a
 * MATPREALLOCATOR (one more tangent evaluation, into a hash set, per solve). */
static PetscErrorCode create_matrix(implicit_ctx *c, Mat *A) {
  peri_sim *s = c->s;
  PetscFunctionBeginUser;
  PetscCall(MatCreate(PETSC_COMM_WORLD, A));
  PetscCall(MatSetSizes(*A, c->n_eq, c->n_eq, c->n_eq_global, c->n_eq_global));
  PetscCall(MatSetType(*A, MATAIJ));
  PetscCall(MatSetBlockSize(*A, c->dim));
  if (!c->global_id) {
    PetscInt *blocks = count_blocks(s, s->mat.model->tangent_reach);
    PetscCall(MatXAIJSetPreallocation(*A, c->dim, blocks, NULL, NULL, NULL));
    free(blocks);
    /* coupled rows: a node switched to PD since the count gets its bonds' blocks (slower)
     * rather than an error */
    if (s->coupling) PetscCall(MatSetOption(*A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
    PetscFunctionReturn(0);
  }
  Mat pattern;
  PetscCall(MatCreate(PETSC_COMM_WORLD, &pattern));
  PetscCall(MatSetType(pattern, MATPREALLOCATOR));
  PetscCall(MatSetSizes(pattern, c->n_eq, c->n_eq, c->n_eq_global, c->n_eq_global));
  PetscCall(MatSetBlockSize(pattern, c->dim));
  PetscCall(MatSetUp(pattern));
  peri_exchange_state(s); /* the tangent reads the ghosts' displacements */
  c->A = pattern;
  c->error = 0;
  if (s->coupling) peri_coupling_rows(s, add_row, c); /* FEM rows and PD rows (docs/coupling.md) */
  else s->mat.model->tangent(s, add_row, c); /* the indenter adds diagonal blocks only: present already */
  PetscCall(c->error);
  PetscCall(MatAssemblyBegin(pattern, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(pattern, MAT_FINAL_ASSEMBLY));
  PetscCall(MatPreallocatorPreallocate(pattern, PETSC_TRUE, *A));
  PetscCall(MatDestroy(&pattern));
  /* The tangents skip a bond of zero deformed length: should one open during the solve, its
   * blocks are new nonzeros, allowed (slower) rather than an error. */
  PetscCall(MatSetOption(*A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  PetscFunctionReturn(0);
}

static PetscErrorCode configure_ksp(const peri_sim *s, KSP ksp, peri_linear_solver linear, Mat A, Vec coords,
                                    double atol) {
  PC pc;
  PetscFunctionBeginUser;
  const bool distributed = peri_comm_size() > 1;
  PetscCall(KSPGetPC(ksp, &pc));
  if (linear == PERI_LINEAR_DIRECT) {
    PetscCall(KSPSetType(ksp, KSPPREONLY));
    PetscCall(PCSetType(pc, PCLU));
    if (distributed) PetscCall(PCFactorSetMatSolverType(pc, parallel_lu())); /* peri_implicit_check_ranks */
    else if (s->coupling && parallel_lu()) PetscCall(PCFactorSetMatSolverType(pc, parallel_lu())); /* MUMPS */
    PetscFunctionReturn(0);
  }
  PetscCall(KSPSetType(ksp, linear == PERI_LINEAR_CG ? KSPCG : KSPGMRES));
  /* tolerances on the true residual |K du + F|, in the units of F */
  if (linear == PERI_LINEAR_GMRES) PetscCall(KSPSetPCSide(ksp, PC_RIGHT));
  PetscCall(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED));
  /* inexact Newton: 1e-6 of the Newton residual, and no further than a hundredth of what
   * the tolerance asks of the nonlinear residual */
  PetscCall(KSPSetTolerances(ksp, 1e-6, atol, PETSC_DEFAULT, 10000));
  static const PCType types[] = {PCGAMG, PCJACOBI, PCILU, PCLU, PCNONE};
  /* PETSc's ILU is sequential: on several ranks, block Jacobi with ILU(0) on each rank's block */
  const bool ilu = s->solver.qs.petsc_preconditioner == PERI_PC_ILU;
  PetscCall(PCSetType(pc, distributed && ilu ? PCBJACOBI : types[s->solver.qs.petsc_preconditioner]));
  if (distributed && s->solver.qs.petsc_preconditioner == PERI_PC_LU) PetscCall(PCFactorSetMatSolverType(pc, parallel_lu()));
  if (s->solver.qs.petsc_preconditioner == PERI_PC_GAMG) {
    /* the rigid-body modes let aggregation coarsen elasticity well */
    MatNullSpace rigid;
    PetscCall(MatNullSpaceCreateRigidBody(coords, &rigid));
    PetscCall(MatSetNearNullSpace(A, rigid));
    PetscCall(MatNullSpaceDestroy(&rigid));
  }
  PetscFunctionReturn(0);
}

/* Options of the deck, then of the command line, in a private database for this solve. */
static PetscErrorCode push_options(const peri_sim *s, PetscOptions *opts) {
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsCreate(opts));
  if (s->solver.qs.petsc_options[0]) PetscCall(PetscOptionsInsertString(*opts, s->solver.qs.petsc_options));
  if (command_line_options) PetscCall(PetscOptionsInsertString(*opts, command_line_options));
  PetscCall(PetscOptionsPush(*opts));
  PetscFunctionReturn(0);
}

static void warn_unused_options(PetscOptions opts) {
  static bool warned = false; /* once per run, not per solve */
  PetscInt n = 0;
  char **names = NULL, **values = NULL;
  if (warned || PetscOptionsLeftGet(opts, &n, &names, &values) || n == 0) return;
  for (PetscInt k = 0; k < n; ++k)
    peri_warning("implicit: PETSc option -%s was not used (misspelt, or not for this solver)", names[k]);
  PetscOptionsLeftRestore(opts, &n, &names, &values);
  warned = true;
}

static PetscErrorCode solve(implicit_ctx *c, peri_linear_solver linear, long *newton, long *krylov,
                            SNESConvergedReason *reason) {
  peri_sim *s = c->s;
  const peri_particles *p = &s->disc.p;
  const int dim = c->dim;
  Mat A;
  Vec x, F, coords;
  SNES snes;
  KSP ksp;
  PetscOptions opts;
  PetscFunctionBeginUser;
  PetscCall(create_matrix(c, &A));
  PetscCall(MatSetOption(A, MAT_SYMMETRIC, linear != PERI_LINEAR_GMRES && !s->coupling ? PETSC_TRUE : PETSC_FALSE));
  /* vectors with the matrix's layout: this rank's equations, block size dim */
  PetscCall(MatCreateVecs(A, &x, &F));
  PetscCall(VecDuplicate(x, &coords));
  PetscScalar *xa, *ca;
  PetscCall(VecGetArray(x, &xa));
  PetscCall(VecGetArray(coords, &ca));
  for (int32_t i = 0; i < p->n_owned; ++i)
    for (int d = 0; d < dim; ++d) {
      xa[dim * i + d] = p->u[3 * (size_t)i + d];
      ca[dim * i + d] = p->x[3 * (size_t)i + d];
    }
  PetscCall(VecRestoreArray(x, &xa));
  PetscCall(VecRestoreArray(coords, &ca));

  PetscCall(SNESCreate(PETSC_COMM_WORLD, &snes));
  PetscCall(SNESSetType(snes, SNESNEWTONLS));
  PetscCall(SNESSetFunction(snes, F, form_function, c));
  PetscCall(SNESSetJacobian(snes, A, A, form_jacobian, c));
  PetscCall(SNESSetConvergenceTest(snes, converged_test, c, NULL));
  PetscCall(SNESSetApplicationContext(snes, c));
  if (linear != PERI_LINEAR_DIRECT) PetscCall(SNESSetUpdate(snes, update_linear_tolerance));
  PetscCall(SNESSetTolerances(snes, 0.0, 0.0, 0.0, (PetscInt)s->solver.qs.max_iterations, 1000000));
  PetscCall(SNESGetKSP(snes, &ksp));
  /* the scale of the residual is the reference force norm of the quasi-static measure */
  const double scale = fmax(s->solver.qs.last_reference, s->solver.qs.reference);
  PetscCall(configure_ksp(s, ksp, linear, A, coords, 1e-2 * s->solver.qs.tolerance * scale));
  PetscCall(push_options(s, &opts));
  PetscErrorCode solved = SNESSetFromOptions(snes); /* a bad option value fails here */
  if (!solved) solved = SNESSolve(snes, NULL, x);
  PetscCall(PetscOptionsPop()); /* whatever happened: the next solve starts clean */
  warn_unused_options(opts);
  PetscCall(PetscOptionsDestroy(&opts));
  PetscCall(solved);
  PetscInt its = 0, lits = 0;
  PetscCall(SNESGetIterationNumber(snes, &its));
  PetscCall(SNESGetLinearSolveIterations(snes, &lits));
  PetscCall(SNESGetConvergedReason(snes, reason));
  *newton += its;
  *krylov += lits;
  PetscCall(set_displacement(c, x)); /* the iterate SNES returned, whatever it evaluated last */
  PetscCall(SNESDestroy(&snes));
  PetscCall(MatDestroy(&A));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&F));
  PetscCall(VecDestroy(&coords));
  PetscFunctionReturn(0);
}

peri_qs_status peri_solve_implicit(peri_sim *s) {
  peri_quasi_static *q = &s->solver.qs;
  if (!s->mat.model->tangent && !s->coupling) {
    peri_error("implicit: model %s has no tangent stiffness (use solver type nlcg)", s->mat.model->name);
    return PERI_QS_DIVERGED;
  }
  if (start_petsc() != PERI_OK) return PERI_QS_DIVERGED;
  implicit_ctx c = {.s = s, .dim = s->disc.geom.dim, .global_id = s->par.dd ? s->par.dd->global_id : NULL};
  c.n_eq = (PetscInt)c.dim * s->disc.p.n_owned;
  c.n_eq_global = (PetscInt)c.dim * (s->par.dd ? (PetscInt)s->par.dd->n_global : (PetscInt)s->disc.p.n_owned);
  c.r = peri_malloc(sizeof(double) * 3 * (size_t)(s->disc.p.n > 0 ? s->disc.p.n : 1));
  find_held(&c);
  q->solves++;
  history_count = 0;
  /* the state at the start: its residual sets the scale of the linear tolerance */
  peri_qs_forces(s);
  c.rel = peri_qs_residual(s, c.r);
  long newton = 0, krylov = 0;
  SNESConvergedReason reason = SNES_CONVERGED_ITERATING;
  peri_linear_solver linear = (peri_linear_solver)q->linear_solver;
  PetscErrorCode err = 0;
  /* When a linear solve fails, Newton continues from where it stopped: CG fails on an
   * indefinite tangent (bonds in compression), so GMRES takes over; any solver fails on a
   * singular one (a piece that fracture set loose, a node left on one bond), so a diagonal
   * shift of 1e-8 |diag J|, raised 100-fold up to 1e-2, makes it regular. The shift only
   * changes the Newton steps, not the equations, so the converged state is the same. */
  static bool told_gmres = false, told_shift = false; /* once per run */
  while (c.rel > q->tolerance && !c.roundoff) {
    err = solve(&c, linear, &newton, &krylov, &reason);
    if (err || reason != SNES_DIVERGED_LINEAR_SOLVE) break;
    if (linear == PERI_LINEAR_CG && c.shift == 0.0) {
      if (!s->out.quiet && !told_gmres)
        peri_warning("implicit: CG failed on an indefinite tangent at t = %g; GMRES takes over for such "
                     "solves", s->state.time);
      told_gmres = true;
      linear = PERI_LINEAR_GMRES;
      continue;
    }
    if (c.shift >= 1e-2) break;
    c.shift = c.shift == 0.0 ? 1e-8 : 100.0 * c.shift;
    if (!s->out.quiet && !told_shift)
      peri_warning("implicit: the tangent is singular at t = %g (a loose piece?); solving with a diagonal "
                   "shift of %g |diag K| (reported once)", s->state.time, c.shift);
    told_shift = true;
  }
  /* forces and residual at the final state (the line search may have evaluated elsewhere) */
  peri_qs_forces(s);
  const double rel = peri_qs_residual(s, c.r);
  q->iterations += newton;
  q->linear_iterations += krylov;
  q->residual = rel;
  free(c.r);
  free(c.order);
  free(c.cols);
  free(c.values);
  free(c.held);
  free(c.held_rows);
  if (err) {
    peri_error("implicit: PETSc error %d during the solve at t = %g", (int)err, s->state.time);
    return PERI_QS_DIVERGED;
  }
  if (!isfinite(rel)) return PERI_QS_DIVERGED;
  return rel <= q->tolerance || c.roundoff ? PERI_QS_CONVERGED : PERI_QS_NOT_CONVERGED;
}

#endif
