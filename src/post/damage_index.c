/* Damage index (docs/model_reference.md 7.3; Le 2014 eq. 1.17). */
#include <string.h>
#include "peri/damage.h"

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
