/* The damage index of every node (src/post/damage_index.c). */
#ifndef PERI_DAMAGE_INDEX_H
#define PERI_DAMAGE_INDEX_H
#include "peri/sim.h"

/* Volume-weighted damage index phi_i = 1 - sum chi beta V / sum beta V (docs/model_reference.md 7.3). */
void peri_damage_index(const peri_sim *s, double *phi);
/* The mean of the damage index over the nodes of every rank (the history column mean_damage):
 * the plain mean, sum phi_i / N, that the damage field of a frame gives. */
double peri_mean_damage(const peri_sim *s);

#endif
