/* Global quantities: energies, momentum and reactions, summed in fixed-order blocks
 * (src/post/energies.c). */
#ifndef PERI_ENERGIES_H
#define PERI_ENERGIES_H
#include "peri/sim.h"

/* Global quantities. */
double peri_kinetic_energy(const peri_sim *s);
double peri_strain_energy(peri_sim *s);
/* The mass sum rho V of every node. */
double peri_total_mass(const peri_sim *s);
/* Total linear momentum sum rho V v. */
void peri_linear_momentum(const peri_sim *s, double out[3]);
/* Reaction on a region: -sum_i f_i V_i over its nodes (internal force density f). */
void peri_region_reaction(const peri_sim *s, int region, double out[3]);
/* PD-FEM coupling: e_r over the reactions R_r of the regions of coupling.balance_regions
 * (Ongaro 2022 eqs. 2.114, 2.116): ratio[d] = |sum_r R_rd| / sum_r |R_rd| (0 where all are 0). */
void peri_coupling_region_balance(const peri_sim *s, double ratio[3]);

#endif
