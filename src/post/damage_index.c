/* Damage index (docs/model_reference.md 7.3; Le 2014 eq. 1.17). */
#include <stdlib.h>
#include <string.h>
#include "peri/damage.h"
#include "peri/damage_index.h"
#include "peri/comm.h"
#include "peri/decompose.h"
#include "peri/error.h"

void peri_damage_index(const peri_sim *s, double *phi) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const int64_t k0 = b->offset[i], count = b->offset[i + 1] - k0;
    if (!memchr(b->broken + k0, 1, (size_t)count)) { /* intact: 1 - all/all */
      phi[i] = 0.0;
      continue;
    }
    double all = 0.0, intact = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      const double w = peri_bonds_beta(b, peri_bond_length(p->x, i, j)) * p->volume[j];
      all += w;
      if (!b->broken[k]) intact += w;
    }
    phi[i] = all > 0.0 ? 1.0 - intact / all : 0.0;
  }
}

double peri_mean_damage(const peri_sim *s) {
  const int32_t n = s->disc.p.n_owned;
  double *phi = peri_malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  peri_damage_index(s, phi);
  /* fictitious layer nodes are out of the statistics (docs/deck.md section 10) */
  long layer_nodes = 0;
  for (int32_t i = 0; i < n; ++i)
    if (s->disc.p.flags[i] & PERI_NODE_FICTITIOUS) phi[i] = 0.0, layer_nodes++;
  double sum = 0.0;
  peri_sum_owned(s, phi, 1, &sum); /* fixed-order blocks: the same on any number of ranks */
  free(phi);
  const int64_t nodes = peri_global_nodes(s) - peri_comm_sum_long(layer_nodes);
  return nodes > 0 ? sum / (double)nodes : 0.0;
}
