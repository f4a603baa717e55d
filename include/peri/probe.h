/* Named scalar quantities of a solved simulation, for sweeps (peri sweep --quantity):
 *   max_von_mises, max_displacement, strain_energy, nodes, iterations
 *   FIELD@X,Y[,Z]      value at the node nearest to the point
 *   mean:FIELD@x=X     mean over the nodes of the grid column nearest to x = X (also y=, z=)
 *   max:FIELD@x=X      largest value on that column
 *   reaction_REGION_x  total reaction force on a region (also _y, _z)
 *   max_von_mises:MATERIAL, mean_stress:MATERIAL   per phase, layers left out (phase_stress.h)
 * with FIELD one of von_mises, stress_IJ, strain_IJ (I, J in x, y, z), displacement_I. */
#ifndef PERI_PROBE_H
#define PERI_PROBE_H
#include <stddef.h>
#include "peri/sim.h"

/* Checks the syntax of a quantity name; on error writes a reason into why. */
int peri_probe_check(const char *name, char *why, size_t n);
/* Evaluates it (computes stress/strain as needed). Returns PERI_OK or PERI_ERR_RUN. */
int peri_probe(peri_sim *s, const char *name, double *value);

#endif
