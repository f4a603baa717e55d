/* The break test of the surface-corrected loops (docs/models.md 4.1), shared by the energy,
 * volume and position-aware corrections (surface_correction.c, position_aware.c). */
#include <math.h>
#include "bond_kernel.h"
#include "surface_correction.h"

/* The break test of the corrected loops, before the force: every intact bond beyond its
 * critical stretch (the same stretch from both ends); the LAMMPS-form s0 from the minimum
 * stretch of the bonds intact at the test. */
long peri_corrected_break(peri_sim *s, bool update_s0) {
  peri_particles *p = &s->disc.p;
  peri_bonds *b = &s->disc.bonds;
  const bool smin = s->mat.s0_node != NULL;
  if (!s->solver.breaking && !smin) return 0;
  long broken = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : broken)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double lowest = INFINITY;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double L = peri_bond_length(p->x, i, j), r = peri_deformed_bond(p->x, p->u, i, j, dy);
      const double stretch = (r - L) / L - peri_bond_thermal_stretch(s->state.thermal_strain, i, j);
      lowest = fmin(lowest, stretch);
      if (s->solver.breaking && stretch > peri_bond_s0(s, i, j)) b->broken[k] = 1, broken++;
    }
    if (smin) p->smin[i] = lowest;
  }
  if (broken) b->broken_edits++; /* (the node blocks' copies of the flags follow) */
  if (smin && update_s0) peri_update_lammps_s0(s);
  return broken;
}
