/* Energy minimisation by nonlinear conjugate gradients (Le 2014 sec. 2.4.1 eqs. 2.46-2.49;
 * docs/model_reference.md 12.3; Shewchuk 1994 B4/B5): Polak-Ribiere directions with the PR+ reset
 * (beta = max(beta_PR, 0)), a secant line search on the directional derivative of the
 * potential energy Pi(u) = sum_i V_i W_i - sum_i V_i b_i.u_i, whose gradient is
 * -V_i (f_i + b_i) because the models' forces are the exact gradient of their energy
 * (docs/model_reference.md 3.3). Optional Jacobi preconditioner: the ADR density Lambda_i. The energy
 * itself guards the line search: a step that raises Pi is halved until it does not. */
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/quasistatic.h"

typedef struct cg_work {
  peri_sim *s;
  size_t n3;
  double *r;   /* f + b on free components */
  double *vr;  /* V r (minus the gradient) */
  double *wn;  /* per-node energy work array */
} cg_work;

/* Forces and the residual at the current u; returns the relative residual. */
static double evaluate(cg_work *w) {
  peri_qs_forces(w->s);
  double res = peri_qs_residual(w->s, w->r);
  const peri_particles *p = &w->s->disc.p;
#pragma omp parallel for schedule(static) if (p->n_owned > 8192)
  for (int32_t i = 0; i < p->n_owned; ++i)
    for (int d = 0; d < 3; ++d) w->vr[3 * (size_t)i + d] = p->volume[i] * w->r[3 * (size_t)i + d];
  return res;
}

/* Pi(u) = sum V W - sum V b.u (node order blocks via peri_qs_dot). */
static double potential(cg_work *w) {
  peri_sim *s = w->s;
  peri_particles *p = &s->disc.p;
  peri_exchange_state(s); /* ghost displacements (MPI ranks) */
  s->mat.model->energy(s, w->wn);
  const int32_t n = p->n_owned;
  double *vb = peri_malloc(sizeof(double) * w->n3);
  for (int32_t i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) vb[3 * (size_t)i + d] = p->volume[i] * p->b[3 * (size_t)i + d];
  double e = peri_qs_dot(s, w->wn, p->volume, 1) - peri_qs_dot(s, vb, p->u, 3);
  free(vb);
  return e;
}

static void axpy(double *y, double a, const double *x, size_t n) {
#pragma omp parallel for schedule(static) if (n > 24576)
  for (size_t k = 0; k < n; ++k) y[k] += a * x[k];
}

/* max |x| over the owned values of every rank */
static double max_abs(const double *x, size_t n) {
  double m = 0.0;
  for (size_t k = 0; k < n; ++k) m = fmax(m, fabs(x[k]));
  return peri_comm_max(m);
}

peri_qs_status peri_solve_nlcg(peri_sim *s) {
  peri_particles *p = &s->disc.p;
  peri_quasi_static *q = &s->solver.qs;
  const int32_t n = p->n_owned;
  const size_t n3 = 3 * (size_t)n;
  cg_work w = {.s = s, .n3 = n3};
  w.r = peri_malloc(sizeof(double) * n3);
  w.vr = peri_malloc(sizeof(double) * n3);
  w.wn = peri_malloc(sizeof(double) * (size_t)p->n);
  double *pre = peri_malloc(sizeof(double) * n3);  /* inverse preconditioner */
  double *z = peri_malloc(sizeof(double) * n3);    /* preconditioned residual */
  double *z_old = peri_malloc(sizeof(double) * n3);
  double *d = peri_malloc(sizeof(double) * n3);
  double *u_start = peri_malloc(sizeof(double) * n3);
  if (q->preconditioner) {
    double *lambda = peri_malloc(sizeof(double) * n);
    peri_qs_density(s, 1.0, lambda);
    for (int32_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) pre[3 * (size_t)i + c] = 1.0 / (lambda[i] * p->volume[i]);
    free(lambda);
  } else {
    for (size_t k = 0; k < n3; ++k) pre[k] = 1.0;
  }
  q->solves++;

  const double dx = s->disc.geom.spacing;
  const int jmax = 5;
  double res = evaluate(&w);
  peri_qs_status status = peri_qs_status_of(s, res); /* diverged: the loads or the start are not finite */
  for (size_t k = 0; k < n3; ++k) z[k] = pre[k] * w.vr[k];
  memcpy(d, z, sizeof(double) * n3);
  double delta_new = peri_qs_dot(s, w.vr, z, 3);
  double last_step = 1e-6 * dx; /* |alpha| max|d| of the previous iteration */
  long it = 0, k_restart = 0;
  for (; status == PERI_QS_NOT_CONVERGED && it < q->max_iterations; ++it) {
    /* eta(alpha) = dPi/dalpha = -(V r).d */
    double eta0 = -peri_qs_dot(s, w.vr, d, 3);
    if (!(eta0 < 0.0)) { /* not a descent direction: restart along z */
      memcpy(d, z, sizeof(double) * n3);
      eta0 = -peri_qs_dot(s, w.vr, d, 3);
      k_restart = 0;
    }
    const double dmax = max_abs(d, n3);
    if (!(dmax > 0.0)) break;
    memcpy(u_start, p->u, sizeof(double) * n3);
    /* secant line search: first point at sigma0 */
    double sigma0 = fmax(1e-2 * last_step, 1e-12 * dx) / dmax;
    axpy(p->u, sigma0, d, n3);
    res = evaluate(&w);
    double a_prev = 0.0, eta_prev = eta0, a = sigma0, eta = -peri_qs_dot(s, w.vr, d, 3);
    bool ok = true;
    for (int j = 0; j < jmax; ++j) {
      const double denom = eta - eta_prev;
      if (!(denom > 0.0) && j == 0) { /* no positive curvature along d */
        ok = false;
        break;
      }
      if (denom == 0.0) break;
      double a_new = a - eta * (a - a_prev) / denom;
      if (!isfinite(a_new)) {
        ok = false;
        break;
      }
      axpy(p->u, a_new - a, d, n3);
      a_prev = a, eta_prev = eta, a = a_new;
      res = evaluate(&w);
      eta = -peri_qs_dot(s, w.vr, d, 3);
      if (fabs(eta) <= 1e-3 * fabs(eta0)) break;
    }
    if (!ok || !isfinite(res)) {
      /* fall back to a halving search on the energy from the start of the iteration */
      double *u_try = p->u;
      memcpy(u_try, u_start, sizeof(double) * n3);
      double pi0 = potential(&w);
      double step = fmax(last_step, 1e-6 * dx) / dmax;
      bool decreased = false;
      for (int h = 0; h < 40 && !decreased; ++h, step *= 0.5) {
        memcpy(p->u, u_start, sizeof(double) * n3);
        axpy(p->u, step, d, n3);
        decreased = potential(&w) < pi0;
        a = step;
      }
      if (!decreased) {
        memcpy(p->u, u_start, sizeof(double) * n3);
        a = 0.0;
      }
      res = evaluate(&w);
      if (!decreased) {
        status = PERI_QS_NOT_CONVERGED;
        break;
      }
    }
    last_step = fabs(a) * dmax;
    peri_qs_iteration(s, it + 1, res); /* progress lines */
    if (getenv("PERI_QS_DEBUG")) fprintf(stderr, "nlcg %ld res %.3e a %.3e eta %.3e/%.3e\n", it, res, a, eta, eta0);
    if (!isfinite(res)) {
      status = PERI_QS_DIVERGED;
      break;
    }
    if (res <= q->tolerance) {
      status = PERI_QS_CONVERGED;
      ++it;
      break;
    }
    /* Polak-Ribiere+ (preconditioned): beta = (r_new.z_new - r_new.z_old) / (r_old.z_old) */
    double *swap = z_old;
    z_old = z;
    z = swap;
#pragma omp parallel for schedule(static) if (n3 > 24576)
    for (size_t k = 0; k < n3; ++k) z[k] = pre[k] * w.vr[k];
    const double delta_old = delta_new;
    const double delta_mid = peri_qs_dot(s, w.vr, z_old, 3);
    delta_new = peri_qs_dot(s, w.vr, z, 3);
    const double beta = (delta_new - delta_mid) / delta_old;
    ++k_restart;
    if (beta <= 0.0 || k_restart >= 3 * (long)peri_global_nodes(s)) {
      memcpy(d, z, sizeof(double) * n3);
      k_restart = 0;
    } else {
#pragma omp parallel for schedule(static) if (n3 > 24576)
      for (size_t k = 0; k < n3; ++k) d[k] = z[k] + beta * d[k];
    }
  }
  q->iterations += it;
  q->residual = res;
  free(w.r);
  free(w.vr);
  free(w.wn);
  free(pre);
  free(z);
  free(z_old);
  free(d);
  free(u_start);
  return status;
}
