/* Tangent stiffness of the PMB model, analytic, in the current configuration.
 * The pair force of bond i-j on i is g(y) = a s(r) y/r with y = y_j - y_i, r = |y|,
 * s = (r - L)/L - s_thermal and a = c_ij omega beta V_j (src/model/pmb.c; c_ij that of an
 * interface modulus where the pair has one, include/peri/interface_moduli.h). Its derivative,
 *   dg/dy = a [ (1/L) n n^T + (s/r) (I - n n^T) ],  n = y/r,
 * is the block K_ij = d f_i / d u_j, and K_ii = -sum_j K_ij. The second (geometric) term
 * keeps Newton quadratic under large rotations and stretches; it vanishes at s = 0. */
#include <math.h>
#include <stdlib.h>
#include "peri/error.h"
#include "peri/interface_moduli.h"
#include "peri/sim.h"
#include "bond_kernel.h"

void peri_pmb_tangent(const peri_sim *s, peri_tangent_add_fn add, void *ctx) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain;
  const int64_t longest = peri_bonds_longest_family(b, p->n_owned);
  /* rows in parallel; add() sees one row at a time, each block once, so the sums do not
   * depend on the threads */
#pragma omp parallel
  {
    int32_t *cols = peri_malloc(sizeof(int32_t) * (size_t)(longest + 1));
    double *blocks = peri_malloc(sizeof(double) * 9 * (size_t)(longest + 1));
#pragma omp for schedule(dynamic, 256)
    for (int32_t i = 0; i < p->n_owned; ++i) {
      double *diag = blocks;
      for (int e = 0; e < 9; ++e) diag[e] = 0.0;
      cols[0] = i;
      int32_t count = 1;
      for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
        if (b->broken[k]) continue;
        const int32_t j = b->neighbor[k];
        double dy[3];
        const double r = peri_deformed_bond(p->x, p->u, i, j, dy);
        if (r <= 0.0) continue; /* the force skips it too */
        const double L = peri_bond_length(p->x, i, j);
        const double stretch = (r - L) / L - peri_bond_thermal_stretch(eth, i, j);
        const double c = peri_pmb_bond_micromodulus(s, p->material[i], p->material[j]);
        const double a = c * peri_bonds_omega(b, L) * peri_bonds_beta(b, L) * p->volume[j];
        const double axial = a / L, geometric = a * stretch / r;
        double *K = &blocks[9 * (size_t)count];
        for (int r1 = 0; r1 < 3; ++r1)
          for (int c1 = 0; c1 < 3; ++c1) {
            const double nn = dy[r1] * dy[c1] / (r * r);
            K[3 * r1 + c1] = axial * nn + geometric * ((r1 == c1) - nn);
            diag[3 * r1 + c1] -= K[3 * r1 + c1];
          }
        cols[count++] = j;
      }
#pragma omp critical(peri_pmb_tangent_add)
      add(ctx, i, count, cols, blocks);
    }
    free(cols);
    free(blocks);
  }
}
