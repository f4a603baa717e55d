/* The normal traction across interfaces between materials and the interface strength that
 * breaks them (docs/thin_films.md section 6: delamination against Mei's Eq. 4.7 of Ebrahimi
 * 2020). The interface is taken normal to the transverse axis (y in 2D, z in 3D), as a film
 * on a substrate: the traction at a lattice column (the nodes that share x in 2D, x and y in
 * 3D) is the normal force that the nodes of the other material exert on the column's nodes
 * of one material, per area of a node's face (dx times the thickness in 2D, dx^2 in 3D),
 * positive when it pulls them towards the other material (peeling). */
#ifndef PERI_INTERFACE_STRENGTH_H
#define PERI_INTERFACE_STRENGTH_H
#include "peri/sim.h"

/* Over all ranks: the largest tensile normal traction across an interface, over the columns
 * and both materials of every pair (0 when none is in tension), at the forces of the last
 * force evaluation. */
double peri_interface_max_traction(const peri_sim *s);

/* The interface strength (s->mat.pair_strength; nothing when NULL): every column whose
 * traction across a pair with a strength reaches it loses that pair's bonds there (both
 * directions). Returns the directed bonds broken over all ranks, the same on every rank. */
long peri_break_interfaces_by_traction(peri_sim *s);

#endif
