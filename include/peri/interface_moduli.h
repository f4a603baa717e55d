/* The elastic constant of the bonds between two materials (docs/deck.md section 9,
 * docs/thin_films.md section 7): `interfaces: [{materials: [a, b], youngs_modulus: E_I}]` gives
 * the PMB bonds with one end in a and the other in b the micromodulus of a PMB material of
 * modulus E_I, in place of the mean (c_a + c_b)/2 of the half-bond rule. The bond loops keep
 * the mean; a pass over the nodes with such bonds adds the difference, so a deck without an
 * interface modulus pays nothing. */
#ifndef PERI_INTERFACE_MODULI_H
#define PERI_INTERFACE_MODULI_H
#include "peri/sim.h"

/* Sets the modulus E_I (Pa) of the bonds between materials a and b (a != b); allocates the
 * table on first use. */
void peri_interface_modulus_set(peri_sim *s, int a, int b, double E);

/* Called by the PMB model's init once the materials' micromoduli are known: the pair
 * micromoduli c_ab = c_PMB(E_I) times the influence calibration, and the stable micromodulus
 * of each material of such a pair raised to c_ab where that is larger (the time step and the
 * quasi-static solvers' scaling follow the stiffer bonds). Nothing without an interface
 * modulus. */
void peri_interface_moduli_init(peri_sim *s);

/* The micromodulus of a bond between materials a and b: c_ab when the pair has a modulus,
 * else (c_a + c_b)/2. */
double peri_pmb_bond_micromodulus(const peri_sim *s, int a, int b);

/* Adds to p->f of the owned nodes the force of the interface bonds' micromodulus difference
 * c_ab - (c_a + c_b)/2 over their intact bonds (the PMB pair force of the bond loops). */
void peri_interface_moduli_force(peri_sim *s);

/* Adds that difference's strain energy density to W[i] of every owned node. */
void peri_interface_moduli_energy(const peri_sim *s, double *W);

void peri_interface_moduli_free(peri_sim *s);

#endif
