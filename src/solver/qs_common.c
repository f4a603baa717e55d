/* Pieces shared by the quasi-static solvers: deterministic reductions, the ADR density,
 * loading at a pseudo-time, forces and the out-of-balance residual. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/implicit.h"
#include "peri/quasistatic.h"

/* Fixed blocks: the partial sums and their order do not depend on the thread count. */
enum { BLOCK = 4096 };

double peri_qs_dot(const double *a, const double *b, size_t n) {
  size_t nb = (n + BLOCK - 1) / BLOCK;
  if (nb == 0) return 0.0;
  double stack[64];
  double *part = nb <= 64 ? stack : peri_malloc(sizeof(double) * nb);
#pragma omp parallel for schedule(static) if (nb > 4)
  for (size_t k = 0; k < nb; ++k) {
    size_t lo = k * BLOCK, hi = lo + BLOCK < n ? lo + BLOCK : n;
    double sum = 0.0;
    for (size_t c = lo; c < hi; ++c) sum += a[c] * b[c];
    part[k] = sum;
  }
  double total = 0.0;
  for (size_t k = 0; k < nb; ++k) total += part[k];
  if (part != stack) free(part);
  return total;
}

void peri_qs_density(const peri_sim *s, double fs, double *lambda) {
  const peri_particles *p = &s->p;
#pragma omp parallel for schedule(static) if (p->n_owned > 8192)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *mi = &s->materials[p->material[i]];
    lambda[i] = 0.25 * fs * peri_node_stiffness_bound(s, i);
    if (!(lambda[i] > 0.0)) lambda[i] = 0.25 * fs * mi->c_stable * p->volume[i] / s->geom.spacing;
  }
}

void peri_qs_apply_loading(peri_sim *s, double t) {
  peri_particles *p = &s->p;
  s->time = t;
  for (int k = 0; k < s->n_bcs; ++k) {
    const peri_bc *bc = &s->bcs[k];
    if (bc->kind != PERI_BC_DISPLACEMENT) continue;
    const peri_region *r = &s->regions[bc->region];
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
  const bool breaking = s->breaking;
  s->breaking = false;
  if (s->indenter.on) peri_apply_loads(s, s->time);
  s->model->force(s);
  s->breaking = breaking;
  s->qs.force_evaluations++;
}

double peri_qs_residual(const peri_sim *s, double *r) {
  const peri_particles *p = &s->p;
  const int dim = s->geom.dim;
  const int32_t n = p->n_owned;
  /* per-node squares, summed in node order blocks */
  double *sq = peri_malloc(sizeof(double) * 2 * (size_t)n);
#pragma omp parallel for schedule(static) if (n > 8192)
  for (int32_t i = 0; i < n; ++i) {
    double res = 0.0, ref = 0.0;
    const double V = p->volume[i];
    for (int d = 0; d < 3; ++d) {
      const size_t c = 3 * (size_t)i + d;
      if (d >= dim) {
        r[c] = 0.0;
      } else if (s->prescribed[c]) {
        r[c] = 0.0;
        ref += V * V * p->f[c] * p->f[c];
      } else {
        r[c] = p->f[c] + p->b[c];
        res += V * V * r[c] * r[c];
        ref += V * V * p->b[c] * p->b[c];
      }
    }
    sq[i] = res;
    sq[n + i] = ref;
  }
  double res = 0.0, ref = 0.0;
  /* block sums in a fixed order */
  size_t nb = ((size_t)n + BLOCK - 1) / BLOCK;
  for (size_t k = 0; k < nb; ++k) {
    size_t lo = k * BLOCK, hi = lo + BLOCK < (size_t)n ? lo + BLOCK : (size_t)n;
    double a = 0.0, b2 = 0.0;
    for (size_t i = lo; i < hi; ++i) a += sq[i], b2 += sq[n + i];
    res += a, ref += b2;
  }
  free(sq);
  peri_quasi_static *q = (peri_quasi_static *)&s->qs; /* the running reference is bookkeeping */
  q->last_reference = sqrt(ref);
  const double scale = fmax(sqrt(ref), q->reference);
  if (!(scale > 0.0)) return res > 0.0 ? 1.0 : 0.0;
  return sqrt(res) / scale;
}

peri_qs_status peri_solve_equilibrium(peri_sim *s) {
  switch (s->solver) {
  case PERI_SOLVER_ADR: return peri_solve_adr(s);
  case PERI_SOLVER_DYNAMIC_RELAXATION: return peri_solve_dynamic_relaxation(s);
  case PERI_SOLVER_NLCG: return peri_solve_nlcg(s);
  case PERI_SOLVER_IMPLICIT: return peri_solve_implicit(s);
  default: return PERI_QS_DIVERGED;
  }
}
