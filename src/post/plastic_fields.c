/* The plasticity outputs (docs/plasticity.md, model reference 16.3): yield index and plastic
 * stretch per node, their mean for the history. */
#include <math.h>
#include <stdlib.h>
#include "peri/comm.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/plastic_fields.h"
#include "peri/plasticity.h"
#include "peri/sim.h"
#include "peri/tensor_plasticity.h"

void peri_yield_index(const peri_sim *s, double *psi) {
  if (s->state.plastic_tensor) { /* the tensor rule: a node's bonds yield together */
    peri_tensor_yield_index(s, psi);
    return;
  }
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const bool plastic = s->state.plastic_stretch != NULL;
  const uint8_t *flags = s->state.plastic_nodes; /* (NULL until the first plastic pass builds them) */
  /* beta of each bond from its length where partial volumes apply (else 1, whatever the length) */
  const bool partial = b->family.rule != PERI_PV_NONE && b->family.spacing > 0;
  const int64_t most = peri_bonds_longest_family(b, p->n_owned), longest = most > 0 ? most : 1;
#pragma omp parallel
  {
    uint8_t *yielded_bond = peri_malloc((size_t)longest);
    double *weight = peri_malloc(sizeof(double) * (size_t)longest);
#pragma omp for schedule(static)
    for (int32_t i = 0; i < p->n_owned; ++i) {
      double all = 0.0, yielded = 0.0;
      /* a node flagged without a plastic state (s->state.plastic_nodes, written from its own
       * bonds' state) has no yielded bond: 0 without reading its bonds */
      const bool none = !plastic || (flags && !flags[i]);
      const int64_t k0 = b->offset[i], n = none ? 0 : b->offset[i + 1] - k0;
      if (!none) peri_plastic_first_layer_flags(s, i, yielded_bond);
      /* the bonds' weights beta V_j by a vector loop (peri_bonds_beta's and peri_bond_length's
       * operations), their sums bond by bond */
      const int32_t *restrict nbr = b->neighbor + k0;
      const double *restrict x = p->x, *restrict volume = p->volume;
      if (partial) {
        const double horizon = b->family.horizon, spacing = b->family.spacing;
#pragma omp simd
        for (int64_t a = 0; a < n; ++a) {
          const int32_t j = nbr[a];
          const double x0 = x[3 * j] - x[3 * i], x1 = x[3 * j + 1] - x[3 * i + 1], x2 = x[3 * j + 2] - x[3 * i + 2];
          const double beta = 0.5 + (horizon - sqrt(x0 * x0 + x1 * x1 + x2 * x2)) / spacing;
          weight[a] = (beta < 1.0 ? (beta > 0.0 ? beta : 0.0) : 1.0) * volume[j];
        }
      } else {
        for (int64_t a = 0; a < n; ++a) weight[a] = volume[nbr[a]];
      }
      for (int64_t a = 0; a < n; ++a) {
        all += weight[a];
        if (yielded_bond[a]) yielded += weight[a];
      }
      psi[i] = all > 0.0 ? yielded / all : 0.0;
    }
    free(yielded_bond);
    free(weight);
  }
}

void peri_plastic_stretch_field(const peri_sim *s, double *out) {
  if (s->state.plastic_tensor) {
    peri_tensor_plastic_stretch(s, out);
    return;
  }
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double largest = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k)
      if (!b->broken[k]) largest = fmax(largest, fabs(peri_plastic_bond_stretch(s, i, k)));
    out[i] = largest;
  }
}

double peri_mean_yield_index(const peri_sim *s) {
  const int32_t n = s->disc.p.n_owned;
  double *psi = peri_malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  peri_yield_index(s, psi);
  double sum = 0.0;
  peri_sum_owned(s, psi, 1, &sum); /* fixed-order blocks: the same on any number of ranks */
  free(psi);
  const int64_t nodes = peri_global_nodes(s);
  return nodes > 0 ? sum / (double)nodes : 0.0;
}
