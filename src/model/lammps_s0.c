/* Compression-dependent critical stretch (Silling-Askari 2005, LAMMPS peri):
 * s0_i = s00 - alpha * min_j s_ij of the previous step (docs/model_reference.md 7.1). */
#include <math.h>
#include "bond_kernel.h"

void peri_update_lammps_s0(peri_sim *s) {
  peri_particles *p = &s->disc.p;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *m = &s->mat.materials[p->material[i]];
    if (isfinite(p->smin[i])) s->mat.s0_node[i] = m->s00 - m->alpha_s * p->smin[i];
  }
}
