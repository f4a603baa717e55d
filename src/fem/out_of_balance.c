/* The out-of-balance of the coupled model (002_b20c318388227af9.txt eqs. 2.38, 2.40;
 * MODELS.md 14.2): with F_i = (K u)_i = -V_i f_i the nodal forces (reactions where u is
 * imposed), e_r = |sum_i F_i| / sum_i |F_i|, per axis and for the vector sum. A balanced
 * model (all FEM, all PD, or a coupling under fields it reproduces) gives round-off. The same
 * ratio over the reactions of chosen regions is peri_coupling_region_balance (post/energies.c). */
#include <math.h>
#include <stdlib.h>
#include "peri/coupling.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/sim.h"

void peri_coupling_balance(const peri_sim *s, double net[3], double ratio[4]) {
  const peri_particles *p = &s->disc.p;
  const int32_t n = p->n_owned;
  /* per node: F (3), |F_d| (3), |F| (1) */
  double *terms = peri_calloc(7 * (size_t)(n > 0 ? n : 1), sizeof(double));
  for (int32_t i = 0; i < n; ++i) {
    double *t = &terms[7 * (size_t)i], sq = 0.0;
    for (int d = 0; d < 3; ++d) {
      const double F = -p->volume[i] * p->f[3 * (size_t)i + d];
      t[d] = F, t[3 + d] = fabs(F), sq += F * F;
    }
    t[6] = sqrt(sq);
  }
  double sum[7];
  peri_sum_owned(s, terms, 7, sum); /* fixed-order blocks: any number of threads and ranks */
  free(terms);
  for (int d = 0; d < 3; ++d) {
    net[d] = sum[d];
    ratio[d] = sum[3 + d] > 0.0 ? fabs(sum[d]) / sum[3 + d] : 0.0;
  }
  const double norm = sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
  ratio[3] = sum[6] > 0.0 ? norm / sum[6] : 0.0;
}
