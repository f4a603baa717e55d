/* Helpers shared by the bond loops of the mechanical models. */
#ifndef PERI_BOND_KERNEL_H
#define PERI_BOND_KERNEL_H
#include <math.h>
#include "peri/sim.h"

/* Deformed bond vector y_j - y_i and its length. Computed identically from both ends up
 * to sign, so the stretch (and so every breaking decision) is symmetric in i and j. */
static inline double peri_deformed_bond(const double *x, const double *u, int32_t i, int32_t j,
                                        double dy[3]) {
  for (int c = 0; c < 3; ++c) dy[c] = (x[3 * j + c] + u[3 * j + c]) - (x[3 * i + c] + u[3 * i + c]);
  return sqrt(dy[0] * dy[0] + dy[1] * dy[1] + dy[2] * dy[2]);
}

/* Critical stretch of bond i-j: LAMMPS form min(s0_i, s0_j), else the pair table.
 * INFINITY when either end is a no-fail node. */
static inline double peri_bond_s0(const peri_sim *s, int32_t i, int32_t j) {
  const peri_particles *p = &s->p;
  if ((p->flags[i] | p->flags[j]) & PERI_NODE_NO_FAIL) return INFINITY;
  if (s->s0_node) return fmin(s->s0_node[i], s->s0_node[j]);
  return s->pair_s0[p->material[i] * s->n_materials + p->material[j]];
}

/* Thermal stretch of bond i-j, 1/2 (alpha_i dT_i + alpha_j dT_j) (docs/model_reference.md 9): subtracted
 * from the stretch by the bond-based model and by every breaking test; 0 without
 * thermomechanics. */
static inline double peri_bond_thermal_stretch(const double *eth, int32_t i, int32_t j) {
  return eth ? 0.5 * (eth[i] + eth[j]) : 0.0;
}

/* Publishes the LAMMPS-form critical stretches for the next step, s0_i = s00 - alpha *
 * (min stretch of i's bonds this step), computed in p->smin by the force pass. */
void peri_update_lammps_s0(peri_sim *s);

#endif
