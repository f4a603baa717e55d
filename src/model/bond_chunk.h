/* A chunk of one node's bonds with their lengths, for the loops that walk a family bond by bond
 * (the position-aware LPS force, the bond rule's energies): the lengths, omega and beta by a
 * vector loop, then the node's sums bond by bond in family order. The numbers are those of
 * peri_bond_length, peri_deformed_bond, peri_bonds_omega and peri_bonds_beta for one bond
 * (the same operations), whose square roots and divisions, one bond at a time, were most of
 * those loops' time. */
#ifndef PERI_BOND_CHUNK_H
#define PERI_BOND_CHUNK_H
#include <math.h>
#include <stdbool.h>
#include "peri/bonds.h"
#include "peri/sim.h"

/* bonds per chunk (a family is one or more chunks) */
enum { PERI_BOND_CHUNK = 256 };

typedef struct peri_bond_chunk {
  /* |xi|, |y| and y = (x_j + u_j) - (x_i + u_i), omega(|xi|), beta(|xi|) */
  double L[PERI_BOND_CHUNK], r[PERI_BOND_CHUNK], y0[PERI_BOND_CHUNK], y1[PERI_BOND_CHUNK], y2[PERI_BOND_CHUNK],
      omega[PERI_BOND_CHUNK], beta[PERI_BOND_CHUNK];
} peri_bond_chunk;

/* The bonds of node i's chunk starting at bond k0. */
static inline int peri_bond_chunk_size(const peri_bonds *b, int32_t i, int64_t k0) {
  return (int)(b->offset[i + 1] - k0 < PERI_BOND_CHUNK ? b->offset[i + 1] - k0 : PERI_BOND_CHUNK);
}

static inline __attribute__((always_inline)) void peri_bond_chunk_of(const peri_sim *s, int32_t i, int64_t k0, int n,
                                                                     peri_bond_chunk *restrict c, const bool inverse,
                                                                     const bool ramp) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int32_t *restrict nbr = b->neighbor + k0;
  const double *restrict x = p->x, *restrict u = p->u;
  const double horizon = b->family.horizon, spacing = b->family.spacing;
#pragma omp simd
  for (int a = 0; a < n; ++a) {
    const int32_t j = nbr[a];
    const double xi0 = x[3 * j] - x[3 * i], xi1 = x[3 * j + 1] - x[3 * i + 1], xi2 = x[3 * j + 2] - x[3 * i + 2];
    const double y0 = (x[3 * j] + u[3 * j]) - (x[3 * i] + u[3 * i]),
                 y1 = (x[3 * j + 1] + u[3 * j + 1]) - (x[3 * i + 1] + u[3 * i + 1]),
                 y2 = (x[3 * j + 2] + u[3 * j + 2]) - (x[3 * i + 2] + u[3 * i + 2]);
    const double L = sqrt(xi0 * xi0 + xi1 * xi1 + xi2 * xi2);
    c->L[a] = L, c->r[a] = sqrt(y0 * y0 + y1 * y1 + y2 * y2), c->y0[a] = y0, c->y1[a] = y1, c->y2[a] = y2;
    c->omega[a] = inverse ? 1.0 / L : 1.0;
    const double beta = 0.5 + (horizon - L) / spacing;
    c->beta[a] = ramp ? (beta < 1.0 ? (beta > 0.0 ? beta : 0.0) : 1.0) : 1.0;
  }
}

/* Fills c with bonds k0 .. k0+n-1 of node i (n <= PERI_BOND_CHUNK). */
static inline void peri_bond_chunk_fill(const peri_sim *s, int32_t i, int64_t k0, int n, peri_bond_chunk *c) {
  const peri_bonds *b = &s->disc.bonds;
  const bool ramp = b->family.rule != PERI_PV_NONE && b->family.spacing > 0;
  if (b->family.influence == PERI_INFLUENCE_INVERSE) {
    if (ramp) peri_bond_chunk_of(s, i, k0, n, c, true, true);
    else peri_bond_chunk_of(s, i, k0, n, c, true, false);
  } else {
    if (ramp) peri_bond_chunk_of(s, i, k0, n, c, false, true);
    else peri_bond_chunk_of(s, i, k0, n, c, false, false);
  }
  if (b->family.influence == PERI_INFLUENCE_GAUSSIAN) /* (exp: the scalar function's value) */
    for (int a = 0; a < n; ++a) c->omega[a] = peri_bonds_omega(b, c->L[a]);
}

#endif
