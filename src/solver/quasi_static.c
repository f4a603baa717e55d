/* Load stepping with sequentially linear fracture (docs/model_reference.md 12.4; Ongaro 2022 sec. 2.7): at each
 * load step solve for equilibrium, break every bond beyond its critical stretch, re-solve
 * at the same load until no bond breaks. A step that breaks more than max_broken_per_step
 * bonds is undone and taken in halves (up to max_cutbacks times). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/contribution.h"
#include "peri/coupling.h"
#include "peri/damage.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/interface_strength.h"
#include "peri/model.h"
#include "peri/plasticity.h"
#include "peri/quasistatic.h"

static const char *solver_name(peri_solver_kind k) {
  switch (k) {
  case PERI_SOLVER_ADR: return "adr";
  case PERI_SOLVER_DYNAMIC_RELAXATION: return "dynamic_relaxation";
  case PERI_SOLVER_NLCG: return "nlcg";
  case PERI_SOLVER_IMPLICIT: return "implicit";
  default: return "explicit";
  }
}

void peri_print_quasi_static_summary(const peri_sim *s, FILE *out) {
  const peri_quasi_static *q = &s->solver.qs;
  fprintf(out, "  solver       %s (quasi-static), %ld load step%s to t = %g, tolerance %g, at most %ld "
               "iterations per solve\n", solver_name(s->solver.kind), q->load_steps, q->load_steps == 1 ? "" : "s",
          s->solver.end_time, q->tolerance, q->max_iterations);
  if (s->solver.kind == PERI_SOLVER_IMPLICIT && s->disc.geom.dim == 3)
    /* measured on examples/dayone_bar3d.yaml (docs/solvers.md, "Which solver"): in 3D a
     * tangent row holds the nodes within 2 horizons (LPS), so the matrix is nearly dense on a
     * body a few horizons across */
    fprintf(out, "  note         implicit in 3D: each matrix row couples the nodes within %s; nlcg was 7 to 26 "
                 "times faster on a 960-node bar (docs/solvers.md, \"Which solver\")\n",
            s->mat.model && !strcmp(s->mat.model->name, "pmb") ? "one horizon" : "two horizons");
  if (s->solver.kind == PERI_SOLVER_DYNAMIC_RELAXATION)
    fprintf(out, "  relaxation   time step %g s, damping %g 1/s, bond damping %g\n", s->solver.dt, s->solver.damping,
            q->bond_damping);
  if (s->solver.breaking)
    fprintf(out, "  fracture     re-solve until no bond breaks%s\n",
            q->max_broken_per_step > 0 ? ", cut back above max_broken_per_step" : "");
  peri_qs_dynamic_summary(s, out); /* solver.dynamic_switch */
}

/* Breaks every intact bond beyond its critical stretch at the current u (and refreshes the
 * forces); returns the number of directed bonds broken. */
static long break_bonds(peri_sim *s) {
  if (!s->solver.breaking) return 0;
  if (peri_loads_follow_deformation(s)) peri_apply_loads(s, s->state.time);
  peri_exchange_state(s); /* ghost displacements (MPI ranks) */
  /* PD-FEM coupling: bonds with a PD end, then FEM->PD switching (docs/coupling.md) */
  long nb = s->coupling ? peri_coupling_break(s) : s->mat.model->force(s);
  s->solver.qs.force_evaluations++;
  if (s->par.dd) nb = peri_comm_sum_long(nb); /* every rank takes the same branch */
  /* interfaces with a normal strength (docs/thin_films.md section 6): the columns whose
   * traction reaches it, at the forces just evaluated; the re-solve follows as for any break */
  nb += peri_break_interfaces_by_traction(s);
  s->solver.qs.broken_in_run += nb;
  return nb;
}

/* After a converged solve: the reference force norm of later solves is at least this one. */
static void converged(peri_sim *s) { s->solver.qs.reference = fmax(s->solver.qs.reference, s->solver.qs.last_reference); }

/* The message of a solve that failed with no cut-back left. */
static int not_converged(peri_sim *s, peri_qs_status st, double t, int cuts) {
  char halved[64] = "";
  if (cuts > 0) snprintf(halved, sizeof halved, ", the increment halved %d time%s", cuts, cuts == 1 ? "" : "s");
  if (st == PERI_QS_DIVERGED)
    peri_error("%s: the solution diverged at load step %ld (t = %g%s): the displacements, forces or "
               "residual are not finite (check the loads; take more load_steps or raise solver.max_cutbacks)",
               solver_name(s->solver.kind), s->state.step + 1, t, halved);
  else
    peri_error("%s: not converged at load step %ld (t = %g%s) after %ld iterations: relative residual "
               "%.3g > tolerance %g (raise solver.max_iterations, loosen solver.tolerance or take "
               "more load_steps)", solver_name(s->solver.kind), s->state.step + 1, t, halved,
               s->solver.qs.max_iterations, s->solver.qs.residual, s->solver.qs.tolerance);
  return PERI_ERR_RUN;
}

/* Back to the state at the start of the load step (displacements and bonds), with half the
 * increment: after too many broken bonds, or a solve that failed. */
static void undo_step(peri_sim *s, const double *u_save, const uint8_t *broken_save, double *inc, int *cut) {
  memcpy(s->disc.p.u, u_save, sizeof(double) * 3 * (size_t)s->disc.p.n_owned);
  memcpy(s->disc.bonds.broken, broken_save, (size_t)s->disc.bonds.n_bonds);
  ++s->disc.bonds.broken_edits;
  *inc *= 0.5;
  ++*cut;
  ++s->solver.qs.cutbacks;
}

/* The compression-dependent s0 of every node follows the last force evaluation; a failed
 * solve may have left it not finite, so its retry starts from the s0 of the step's start.
 * (A cut-back after too many broken bonds keeps the last s0, as it always has.) */
static void restore_s0(peri_sim *s, const double *s0_save) {
  if (s0_save) memcpy(s->mat.s0_node, s0_save, sizeof(double) * (size_t)s->disc.p.n);
}

int peri_solve_quasi_static(peri_sim *s, peri_step_hook hook, void *ctx) {
  peri_particles *p = &s->disc.p;
  peri_quasi_static *q = &s->solver.qs;
  const size_t n3 = 3 * (size_t)p->n_owned;
  const size_t nbonds = (size_t)s->disc.bonds.n_bonds;
  double *u_save = peri_malloc(sizeof(double) * n3);
  uint8_t *broken_save = peri_malloc(nbonds ? nbonds : 1);
  double *s0_save = s->mat.s0_node ? peri_malloc(sizeof(double) * (size_t)(p->n > 0 ? p->n : 1)) : NULL;
  const double T = s->solver.end_time;
  const long N = q->load_steps;
  double t_done = s->state.time;
  int rc = PERI_OK;
  bool stop = false; /* the hook asked to stop (during a dynamic phase) */
  peri_qs_work work; /* external work over the accepted states (history column external_work) */
  peri_qs_work_begin(&work, s);
  /* from the load step reached: 0, or a checkpoint's (docs/restart.md) */
  for (long n = s->state.step; n < N && rc == PERI_OK; ++n) {
    const double t_target = T * (double)(n + 1) / (double)N;
    double inc = t_target - t_done;
    int cut = 0;
    while (t_done < t_target && rc == PERI_OK && !stop) {
      const double t = fmin(t_done + inc, t_target);
      memcpy(u_save, p->u, sizeof(double) * n3);
      memcpy(broken_save, s->disc.bonds.broken, nbonds);
      if (s0_save) memcpy(s0_save, s->mat.s0_node, sizeof(double) * (size_t)p->n);
      peri_qs_apply_loading(s, t);
      peri_qs_status st = peri_solve_equilibrium(s);
      bool retry = false, went_dynamic = false;
      if (st != PERI_QS_CONVERGED) {
        /* not converged, or not finite: undo and take half the increment while cut-backs are left */
        if (cut < q->max_cutbacks) {
          undo_step(s, u_save, broken_save, &inc, &cut);
          restore_s0(s, s0_save);
          continue;
        }
        rc = not_converged(s, st, t, cut);
        break;
      }
      converged(s);
      long broken = 0, rounds = 0, since_dynamic = 0;
      for (;;) {
        long nb = break_bonds(s);
        if (nb < 0) { /* the coupled model could not switch a node (message given) */
          rc = PERI_ERR_RUN;
          break;
        }
        broken += nb;
        since_dynamic += nb;
        if (nb == 0) break;
        if (q->max_broken_per_step > 0 && broken > q->max_broken_per_step && cut < q->max_cutbacks &&
            !went_dynamic) {
          /* too many at once: undo and take half the increment */
          undo_step(s, u_save, broken_save, &inc, &cut);
          retry = true;
          break;
        }
        if (q->dynamic.on && since_dynamic > q->dynamic.when_broken_exceeds) {
          /* unstable growth: explicit dynamics at this load until the crack arrests, then
           * equilibrium again from where it stopped (docs/solvers.md section 4) */
          rc = peri_qs_dynamic_phase(s, t, hook, ctx, &stop);
          if (rc != PERI_OK || stop) break;
          went_dynamic = true;
          since_dynamic = 0;
        }
        if (++rounds > q->max_fracture_iterations) {
          peri_error("%s: bonds still break after %ld re-solves at load step %ld (t = %g); raise "
                     "solver.max_fracture_iterations", solver_name(s->solver.kind), rounds - 1, n + 1, t);
          rc = PERI_ERR_RUN;
          break;
        }
        st = peri_solve_equilibrium(s);
        if (st != PERI_QS_CONVERGED) {
          /* as for the first solve; after a dynamic phase (its history rows are written) the
           * step is not undone */
          if (cut < q->max_cutbacks && !went_dynamic) {
            undo_step(s, u_save, broken_save, &inc, &cut);
            restore_s0(s, s0_save);
            retry = true;
            break;
          }
          rc = not_converged(s, st, t, cut);
          break;
        }
        converged(s);
      }
      if (retry) continue;
      if (!stop && rc == PERI_OK) peri_qs_work_step(&work, s);
      if (!stop) t_done = t, peri_plastic_commit(s); /* the accepted plastic state (docs/plasticity.md) */
    }
    s->state.time = t_done;
    if (rc != PERI_OK || stop) break;
    s->state.step = n + 1;
    if (hook && hook(s, ctx)) break;
  }
  /* the run is static: no velocity to report */
  memset(p->v, 0, sizeof(double) * 3 * (size_t)p->n);
  free(u_save);
  free(broken_save);
  free(s0_save);
  peri_qs_work_free(&work);
  return rc;
}
