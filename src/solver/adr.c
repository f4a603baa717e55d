/* Adaptive dynamic relaxation (Kilic & Madenci 2010; docs/model_reference.md 12.2): the static problem
 * as the steady state of Lambda U'' + c Lambda U' = F(U) with a fictitious diagonal
 * density Lambda from the stiffness bound, unit pseudo time step, and the damping c from
 * the local Rayleigh quotient of each iteration. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/quasistatic.h"

peri_qs_status peri_solve_adr(peri_sim *s) {
  peri_particles *p = &s->disc.p;
  peri_quasi_static *q = &s->solver.qs;
  const int32_t n = p->n_owned;
  const size_t n3 = 3 * (size_t)n;
  double *lambda = peri_malloc(sizeof(double) * n);
  double *vel = peri_calloc(n3, sizeof(double));   /* U' at the half step */
  double *r = peri_malloc(sizeof(double) * n3);     /* F^n on free components */
  double *r_old = peri_malloc(sizeof(double) * n3); /* F^(n-1) */
  double *ku = peri_malloc(sizeof(double) * n3);    /* diag(1K) u, for the Rayleigh quotient */
  double *uf = peri_malloc(sizeof(double) * n3);    /* u on the components that move */
  peri_qs_density(s, q->stiffness_factor, lambda);
  q->solves++;

  peri_qs_forces(s);
  double res = peri_qs_residual(s, r);
  peri_qs_status status = peri_qs_status_of(s, res); /* diverged: the loads or the start are not finite */
  long it = 0;
  /* first half step: U'^(1/2) = Lambda^-1 F^0 / 2 */
  for (; status == PERI_QS_NOT_CONVERGED && it < q->max_iterations; ++it) {
    double c = 0.0;
    if (it > 0) {
      /* c^n = 2 sqrt(u^T 1K u / u^T u), 1K_ii = -(F^n_i - F^(n-1)_i) / (Lambda_ii U'^(n-1/2)_i) */
#pragma omp parallel for schedule(static) if (n > 8192)
      for (int32_t i = 0; i < n; ++i)
        for (int d = 0; d < 3; ++d) {
          const size_t k = 3 * (size_t)i + d;
          const double v = vel[k];
          if (v != 0.0) {
            ku[k] = -(r[k] - r_old[k]) / (lambda[i] * v) * p->u[k];
            uf[k] = p->u[k];
          } else {
            ku[k] = uf[k] = 0.0;
          }
        }
      const double num = peri_qs_dot(s, uf, ku, 3), den = peri_qs_dot(s, uf, uf, 3);
      if (num > 0.0 && den > 0.0) c = fmin(2.0 * sqrt(num / den), 1.9);
    }
#pragma omp parallel for schedule(static) if (n > 8192)
    for (int32_t i = 0; i < n; ++i)
      for (int d = 0; d < 3; ++d) {
        const size_t k = 3 * (size_t)i + d;
        const double a = r[k] / lambda[i];
        vel[k] = it == 0 ? 0.5 * a : ((2.0 - c) * vel[k] + 2.0 * a) / (2.0 + c);
        p->u[k] += vel[k];
      }
    double *swap = r_old;
    r_old = r;
    r = swap;
    peri_qs_forces(s);
    res = peri_qs_residual(s, r);
    status = peri_qs_status_of(s, res);
    peri_qs_iteration(s, it + 1, res); /* progress lines */
  }
  q->iterations += it;
  q->residual = res;
  free(lambda);
  free(vel);
  free(r);
  free(r_old);
  free(ku);
  free(uf);
  return status;
}
