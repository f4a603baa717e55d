/* Stress per phase (include/peri/phase_stress.h). */
#include <math.h>
#include <stdlib.h>
#include "peri/comm.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/phase_stress.h"
#include "peri/stress.h"

void peri_phase_stresses(const peri_sim *s, const double *sigma, peri_phase_stress *out) {
  const peri_particles *p = &s->disc.p;
  const int32_t n = p->n_owned;
  const int nm = s->mat.n_materials, size = peri_comm_size();
  double *terms = peri_malloc(sizeof(double) * 2 * (size_t)(n > 0 ? n : 1));
  int64_t *counts = peri_malloc(sizeof(int64_t) * (size_t)size);
  for (int r = 0; r < size; ++r) counts[r] = 4;
  double *every = peri_malloc(sizeof(double) * 4 * (size_t)size);
  for (int m = 0; m < nm; ++m) {
    int32_t best = -1;
    double best_vm = -INFINITY;
    for (int32_t i = 0; i < n; ++i) {
      terms[2 * (size_t)i] = terms[2 * (size_t)i + 1] = 0.0;
      if (p->material[i] != m || (p->flags[i] & PERI_NODE_FICTITIOUS)) continue;
      const double nu = s->mat.materials[m].nu, *sg = &sigma[9 * (size_t)i];
      const double vm = peri_von_mises(s, sg, nu);
      if (best < 0 || vm > best_vm) best = i, best_vm = vm; /* the first node of the largest value */
      double principal[3];
      peri_principal_stresses(s, sg, nu, principal); /* in 2D the third is sigma_33 */
      terms[2 * (size_t)i] = p->volume[i] * (principal[0] + principal[1] + principal[2]) / 3.0;
      terms[2 * (size_t)i + 1] = p->volume[i];
    }
    double sums[2];
    peri_sum_owned(s, terms, 2, sums); /* fixed-order blocks: independent of ranks and threads */
    double mine[4] = {best_vm, 0.0, 0.0, 0.0};
    for (int d = 0; best >= 0 && d < 3; ++d) mine[1 + d] = p->x[3 * (size_t)best + d];
    /* ranks own consecutive runs of the global node order: the first rank with the largest
     * value holds the first such node, as in one process */
    peri_comm_allgather_doubles(mine, 4, counts, every);
    int won = 0;
    for (int r = 1; r < size; ++r)
      if (every[4 * r] > every[4 * won]) won = r;
    out[m] = (peri_phase_stress){every[4 * won], {every[4 * won + 1], every[4 * won + 2], every[4 * won + 3]},
                                 sums[1] > 0.0 ? sums[0] / sums[1] : 0.0, sums[1]};
  }
  free(every);
  free(counts);
  free(terms);
}

int peri_phase_stresses_now(peri_sim *s, peri_phase_stress *out) {
  const int32_t n = s->disc.p.n_owned;
  double *sigma = peri_malloc(sizeof(double) * 9 * (size_t)(n > 0 ? n : 1));
  const int rc = peri_stress(s, sigma); /* collective on MPI ranks (ghost dilatations) */
  if (rc == PERI_OK) peri_phase_stresses(s, sigma, out);
  free(sigma);
  return rc;
}

void peri_print_stress_summary(peri_sim *s, FILE *out) {
  peri_phase_stress *phases = peri_malloc(sizeof *phases * (size_t)s->mat.n_materials);
  if (peri_phase_stresses_now(s, phases) == PERI_OK && peri_comm_rank() == 0)
    for (int m = 0; m < s->mat.n_materials; ++m) {
      const peri_phase_stress *ph = &phases[m];
      if (ph->max_von_mises > -INFINITY)
        fprintf(out, "  max von Mises %s: %.4g Pa at (%g, %g, %g), mean stress %.4g Pa\n", s->mat.materials[m].name,
                ph->max_von_mises, ph->where[0], ph->where[1], ph->where[2], ph->mean_stress);
    }
  free(phases);
}
