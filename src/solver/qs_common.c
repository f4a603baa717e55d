/* Pieces shared by the quasi-static solvers: deterministic reductions (fixed-order blocks of
 * the global node order, the same on any number of threads and MPI ranks), the ADR density,
 * loading at a pseudo-time, forces and the out-of-balance residual. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/contribution.h"
#include "peri/coupling.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/horizon_field.h"
#include "peri/implicit.h"
#include "peri/quasistatic.h"

double peri_qs_dot(const peri_sim *s, const double *a, const double *b, int ncomp) {
  const int32_t n = s->disc.p.n_owned;
  double *terms = peri_malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
#pragma omp parallel for schedule(static) if (n > 8192)
  for (int32_t i = 0; i < n; ++i) {
    double sum = 0.0;
    for (int c = 0; c < ncomp; ++c) sum += a[(size_t)ncomp * i + c] * b[(size_t)ncomp * i + c];
    terms[i] = sum;
  }
  double total;
  peri_sum_owned(s, terms, 1, &total); /* fixed-order blocks of the global node order */
  free(terms);
  return total;
}

/* A horizon that varies (docs/variable_horizon.md): the bond stiffness of a PMB pair is its own
 * (c_i + c_j)/2 and so varies as delta^-(d+1) across the levels of a graded grid, where the bound
 * above takes the stiffest node's c for every node; the sum of the pairs' own stiffnesses is the
 * trace of the node's diagonal block. */
static double pair_stiffness(const peri_sim *s, int32_t i) {
  const peri_bonds *b = &s->disc.bonds;
  const double *pair = s->disc.horizon_field->bond_pair;
  double sum = 0.0;
  for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) sum += pair[k];
  return sum;
}

void peri_qs_density(const peri_sim *s, double fs, double *lambda) {
  const peri_particles *p = &s->disc.p;
  const bool pair = s->disc.horizon_field && s->disc.horizon_field->bond_pair;
  /* A local node (horizon 0, docs/variable_horizon.md) is stiffer than the bond bound of its
   * stencil: its elastic force reads the stencils of its stencil's nodes, and the zero-energy
   * mode control adds kappa times the bond stiffness at most twice over; the stable time step's
   * factor 1 + 2 kappa (src/solver/stable_dt.c) keeps the pseudo-dynamics stable there (in 2D
   * the largest eigenvalue of Lambda^-1 K was 4.7 without it, above the 4 of a unit step). */
  const uint8_t *local = s->disc.horizon_field ? s->disc.horizon_field->local : NULL;
  const double local_factor = local ? peri_horizon_control_factor(s->disc.horizon_field) : 1.0;
#pragma omp parallel for schedule(static) if (p->n_owned > 8192)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *mi = &s->mat.materials[p->material[i]];
    lambda[i] = 0.25 * fs * (pair ? pair_stiffness(s, i) : peri_node_stiffness_bound(s, i));
    if (!(lambda[i] > 0.0)) lambda[i] = 0.25 * fs * mi->c_stable * p->volume[i] / s->disc.geom.spacing;
    if (local && local[i]) lambda[i] *= local_factor;
  }
}

void peri_qs_apply_loading(peri_sim *s, double t) {
  peri_particles *p = &s->disc.p;
  s->state.time = t;
  for (int k = 0; k < s->cond.n_bcs; ++k) {
    const peri_bc *bc = &s->cond.bcs[k];
    if (bc->kind != PERI_BC_DISPLACEMENT) continue;
    const peri_region *r = &s->cond.regions[bc->region];
    for (int32_t a = 0; a < r->count; ++a) {
      const int32_t i = r->nodes[a];
      const double *x = &p->x[3 * i];
      for (int d = 0; d < 3; ++d)
        if (bc->value[d]) p->u[3 * i + d] = peri_expr_eval(bc->value[d], x[0], x[1], x[2], t);
    }
  }
  memset(p->v, 0, sizeof(double) * 3 * (size_t)p->n);
  peri_apply_loads(s, t);
}

void peri_qs_forces(peri_sim *s) {
  const bool breaking = s->solver.breaking;
  s->solver.breaking = false;
  peri_exchange_state(s); /* ghost displacements (MPI ranks) */
  if (peri_loads_follow_deformation(s)) peri_apply_loads(s, s->state.time);
  if (s->coupling) peri_coupling_force(s); /* PD-FEM coupling: K u row by row (docs/coupling.md) */
  else s->mat.model->force(s);
  s->solver.breaking = breaking;
  s->solver.qs.force_evaluations++;
}

double peri_qs_residual(const peri_sim *s, double *r) {
  const peri_particles *p = &s->disc.p;
  const int dim = s->disc.geom.dim;
  const int32_t n = p->n_owned;
  /* per-node squares, summed in node order blocks */
  double *sq = peri_malloc(sizeof(double) * 2 * (size_t)(n > 0 ? n : 1));
#pragma omp parallel for schedule(static) if (n > 8192)
  for (int32_t i = 0; i < n; ++i) {
    double res = 0.0, ref = 0.0;
    const double V = p->volume[i];
    for (int d = 0; d < 3; ++d) {
      const size_t c = 3 * (size_t)i + d;
      if (d < dim && !isfinite(p->u[c])) res = NAN; /* a displacement that is not finite fails the state */
      if (d >= dim) {
        r[c] = 0.0;
      } else if (s->cond.prescribed[c]) {
        r[c] = 0.0;
        ref += V * V * p->f[c] * p->f[c];
      } else {
        r[c] = p->f[c] + p->b[c];
        res += V * V * r[c] * r[c];
        ref += V * V * p->b[c] * p->b[c];
      }
    }
    sq[2 * (size_t)i] = res;
    sq[2 * (size_t)i + 1] = ref;
  }
  double sums[2];
  peri_sum_owned(s, sq, 2, sums); /* fixed-order blocks: any number of threads and ranks */
  const double res = sums[0], ref = sums[1];
  free(sq);
  peri_quasi_static *q = (peri_quasi_static *)&s->solver.qs; /* the running reference is bookkeeping */
  q->last_reference = sqrt(ref);
  /* A state that is not finite (displacements, forces, loads), or whose norms overflow, has
   * no meaningful residual: infinite, so that no comparison with the tolerance passes (a NaN
   * would, below, where the scale ignores it) and the solvers report it as diverged. */
  if (!isfinite(res) || !isfinite(ref)) return INFINITY;
  const double scale = fmax(sqrt(ref), q->reference);
  if (!(scale > 0.0)) return res > 0.0 ? 1.0 : 0.0;
  return sqrt(res) / scale;
}

peri_qs_status peri_qs_status_of(const peri_sim *s, double residual) {
  if (!isfinite(residual)) return PERI_QS_DIVERGED;
  return residual <= s->solver.qs.tolerance ? PERI_QS_CONVERGED : PERI_QS_NOT_CONVERGED;
}

void peri_qs_iteration(peri_sim *s, long iteration, double residual) {
  s->solver.qs.solve_iterations = iteration;
  s->solver.qs.residual = residual;
  if (s->out.progress) s->out.progress(s);
}
