/* Damped dynamic relaxation (Le 2014 sec. 2.4.1 eqs. 2.43-2.45; docs/model_reference.md 12.1): velocity-
 * Verlet with the physical density and time step and a user-set damping, run until the
 * out-of-balance force vanishes. Two damping forms:
 *   damping (1/s):     -rho gamma v                                   (mass-proportional)
 *   bond_damping:      gamma sum_j [(v_j - v_i).M_ij] M_ij / |xi| beta V_j  (pairwise, eq. 2.43;
 *                      rigid motion is not damped)
 * Both are evaluated with the half-step velocity v_(n+1/2) (docs/model_reference.md 12.1 erratum). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/quasistatic.h"

/* Pairwise damping force density with velocities vel into out (free and prescribed). */
static void bond_damping_force(const peri_sim *s, double gamma, const double *vel, double *out) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
#pragma omp parallel for schedule(dynamic, 256) if (p->n_owned > 8192)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double fi[3] = {0.0, 0.0, 0.0};
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double m[3], r2 = 0.0;
      for (int d = 0; d < 3; ++d) {
        m[d] = p->x[3 * j + d] + p->u[3 * j + d] - p->x[3 * i + d] - p->u[3 * i + d];
        r2 += m[d] * m[d];
      }
      if (!(r2 > 0.0)) continue;
      double proj = 0.0;
      for (int d = 0; d < 3; ++d) proj += (vel[3 * j + d] - vel[3 * i + d]) * m[d];
      const double r0 = peri_bond_length(p->x, i, j);
      const double scale = gamma * proj / r2 / r0 * peri_bonds_beta(b, r0) * p->volume[j];
      for (int d = 0; d < 3; ++d) fi[d] += scale * m[d];
    }
    for (int d = 0; d < 3; ++d) out[3 * i + d] = fi[d];
  }
}

peri_qs_status peri_solve_dynamic_relaxation(peri_sim *s) {
  peri_particles *p = &s->disc.p;
  peri_quasi_static *q = &s->solver.qs;
  const int32_t n = p->n_owned;
  const size_t n3 = 3 * (size_t)n;
  const double dt = s->solver.dt, gamma = s->solver.damping, gb = q->bond_damping;
  double *inv_rho = peri_malloc(sizeof(double) * n);
  for (int32_t i = 0; i < n; ++i) inv_rho[i] = 1.0 / s->mat.materials[p->material[i]].density;
  double *vel = peri_calloc(3 * (size_t)(p->n > 0 ? p->n : 1), sizeof(double)); /* ghosts: bond damping */
  double *r = peri_malloc(sizeof(double) * n3);
  double *fd = gb > 0.0 ? peri_calloc(n3, sizeof(double)) : NULL;
  q->solves++;

  double *acc = peri_calloc(n3, sizeof(double));
  peri_qs_forces(s);
  double res = peri_qs_residual(s, r);
  for (size_t k = 0; k < n3; ++k) acc[k] = r[k] * inv_rho[k / 3];
  peri_qs_status status = peri_qs_status_of(s, res); /* diverged: the loads or the start are not finite */
  long it = 0;
  const int dim = s->disc.geom.dim;
  for (; status == PERI_QS_NOT_CONVERGED && it < q->max_iterations; ++it) {
#pragma omp parallel for schedule(static) if (n > 8192)
    for (int32_t i = 0; i < n; ++i)
      for (int d = 0; d < dim; ++d) {
        const size_t k = 3 * (size_t)i + d;
        if (s->cond.prescribed[k]) continue;
        vel[k] += 0.5 * dt * acc[k]; /* v_(n+1/2) */
        p->u[k] += dt * vel[k];
      }
    peri_qs_forces(s);
    res = peri_qs_residual(s, r);
    if (fd) {
      peri_sim_exchange(s, vel, 3); /* the ghosts' velocities (MPI ranks) */
      bond_damping_force(s, gb, vel, fd);
    }
#pragma omp parallel for schedule(static) if (n > 8192)
    for (int32_t i = 0; i < n; ++i)
      for (int d = 0; d < dim; ++d) {
        const size_t k = 3 * (size_t)i + d;
        if (s->cond.prescribed[k]) continue;
        /* a_(n+1) with the damping of the half-step velocity */
        acc[k] = (r[k] + (fd ? fd[k] : 0.0)) * inv_rho[i] - gamma * vel[k];
        vel[k] += 0.5 * dt * acc[k];
      }
    status = peri_qs_status_of(s, res);
    peri_qs_iteration(s, it + 1, res); /* progress lines */
  }
  free(acc);
  q->iterations += it;
  q->residual = res;
  free(inv_rho);
  free(vel);
  free(r);
  free(fd);
  return status;
}
