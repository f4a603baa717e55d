/* The plastic bond loops of the PMB and LPS models (src/model/plastic_bonds.c,
 * docs/plasticity.md). The models call them instead of their elastic loops when a material
 * has sublayers (s->state.plastic_stretch set), so the elastic loops carry no plasticity. */
#ifndef PERI_PLASTIC_BONDS_H
#define PERI_PLASTIC_BONDS_H
#include "peri/plasticity.h"
#include "peri/sim.h"

/* Allocates the plastic state when a material has sublayers (nothing otherwise). Returns
 * PERI_OK or PERI_ERR_INPUT with a message (a combination plasticity does not take). */
int peri_plastic_init(peri_sim *s);
/* Force passes (as peri_force_pass): the return mapping of every intact bond of the owned
 * nodes at the current stretch, then the force at the elastic stretch. */
long peri_plastic_pmb_force(peri_sim *s, bool update_s0);
long peri_plastic_lps_force(peri_sim *s, bool update_s0);
/* Elastic strain energy densities at the current plastic state. */
void peri_plastic_pmb_energy(peri_sim *s, double *W);
void peri_plastic_lps_energy(peri_sim *s, double *W);
/* (peri_plastic_bond_stretch: include/peri/plasticity.h) */

#endif
