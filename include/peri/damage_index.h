/* The damage index of every node (src/post/damage_index.c). */
#ifndef PERI_DAMAGE_INDEX_H
#define PERI_DAMAGE_INDEX_H
#include "peri/sim.h"

/* Volume-weighted damage index phi_i = 1 - sum chi beta V / sum beta V (docs/model_reference.md 7.3). */
void peri_damage_index(const peri_sim *s, double *phi);

#endif
