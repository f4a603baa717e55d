/* The interface-placement indicator D^2(u) (002_b20c318388227af9.txt eq. 2.115). The seed
 * computes the derivatives with the PD differential operator; this fits them by weighted
 * least squares over the family (MODELS.md 14.5, Default), which is exact for quadratic fields
 * at every node, near a surface too. The basis is scaled by the horizon so that the normal
 * matrix is well conditioned. */
#include <math.h>
#include <string.h>
#include "peri/indicator.h"
#include "peri/sim.h"

enum { MAX_BASIS = 9 };

/* the basis p(xi / delta) and, per term, the order of the derivative it carries (1: first,
 * 2: d^2/dx_k^2 = 2 a, 3: mixed d^2/dx_k dx_l = a) */
static int basis(int dim, const double *t, double *p, int *kind) {
  if (dim == 1) {
    p[0] = t[0], p[1] = t[0] * t[0];
    kind[0] = 1, kind[1] = 2;
    return 2;
  }
  if (dim == 2) {
    p[0] = t[0], p[1] = t[1], p[2] = t[0] * t[0], p[3] = t[0] * t[1], p[4] = t[1] * t[1];
    kind[0] = kind[1] = 1, kind[2] = 2, kind[3] = 3, kind[4] = 2;
    return 5;
  }
  p[0] = t[0], p[1] = t[1], p[2] = t[2];
  p[3] = t[0] * t[0], p[4] = t[1] * t[1], p[5] = t[2] * t[2];
  p[6] = t[0] * t[1], p[7] = t[0] * t[2], p[8] = t[1] * t[2];
  for (int k = 0; k < 3; ++k) kind[k] = 1, kind[3 + k] = 2, kind[6 + k] = 3;
  return 9;
}

/* Solves A x = b (n x n, symmetric positive definite expected) for `nrhs` right-hand sides
 * stored as columns b[k * nrhs + c], by Gaussian elimination with partial pivoting; returns
 * 0 when A is singular to working precision. */
static int solve(int n, double A[MAX_BASIS][MAX_BASIS], double b[MAX_BASIS][3], int nrhs) {
  double scale = 0.0;
  for (int r = 0; r < n; ++r) scale = fmax(scale, fabs(A[r][r]));
  for (int k = 0; k < n; ++k) {
    int piv = k;
    for (int r = k + 1; r < n; ++r)
      if (fabs(A[r][k]) > fabs(A[piv][k])) piv = r;
    if (!(fabs(A[piv][k]) > 1e-12 * scale)) return 0;
    if (piv != k) {
      for (int c = 0; c < n; ++c) {
        const double t = A[k][c];
        A[k][c] = A[piv][c], A[piv][c] = t;
      }
      for (int c = 0; c < nrhs; ++c) {
        const double t = b[k][c];
        b[k][c] = b[piv][c], b[piv][c] = t;
      }
    }
    for (int r = k + 1; r < n; ++r) {
      const double f = A[r][k] / A[k][k];
      for (int c = k; c < n; ++c) A[r][c] -= f * A[k][c];
      for (int c = 0; c < nrhs; ++c) b[r][c] -= f * b[k][c];
    }
  }
  for (int k = n - 1; k >= 0; --k)
    for (int c = 0; c < nrhs; ++c) {
      double v = b[k][c];
      for (int j = k + 1; j < n; ++j) v -= A[k][j] * b[j][c];
      b[k][c] = v / A[k][k];
    }
  return 1;
}

void peri_second_derivative_indicator(const peri_sim *s, double *D2) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int dim = s->disc.geom.dim;
  const double delta = s->disc.geom.horizon;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double A[MAX_BASIS][MAX_BASIS] = {{0}}, rhs[MAX_BASIS][3] = {{0}};
    int kind[MAX_BASIS], n = 0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double xi[3], t[3], q[MAX_BASIS];
      const double L = peri_bond_xi(p->x, i, j, xi);
      for (int d = 0; d < 3; ++d) t[d] = xi[d] / delta;
      n = basis(dim, t, q, kind);
      const double w = peri_bonds_omega(b, L) * peri_bonds_beta(b, L) * p->volume[j];
      for (int r = 0; r < n; ++r) {
        for (int c = 0; c < n; ++c) A[r][c] += w * q[r] * q[c];
        for (int c = 0; c < dim; ++c) rhs[r][c] += w * q[r] * (p->u[3 * (size_t)j + c] - p->u[3 * (size_t)i + c]);
      }
    }
    double sum = 0.0;
    if (n > 0 && solve(n, A, rhs, dim))
      for (int r = 0; r < n; ++r) {
        if (kind[r] == 1) continue;
        const double factor = (kind[r] == 2 ? 2.0 : 1.0) / (delta * delta); /* back from xi / delta */
        for (int c = 0; c < dim; ++c) sum += fabs(factor * rhs[r][c]);
      }
    D2[i] = sum;
  }
}
