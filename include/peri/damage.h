/* Damage: pre-cracks that remove bonds, and the damage index. */
#ifndef PERI_DAMAGE_H
#define PERI_DAMAGE_H
#include "peri/sim.h"

/* Whether the reference bond x_i -> x_j crosses the pre-crack. The crack is shifted by
 * 1e-6 dx along its normal first, so nodes exactly on the crack line fall on one side
 * (docs/model_reference.md 7.4). 2D: segment-segment test with two cross products; 3D: segment against
 * the planar rectangle a + s e1 + t e2, 0 <= s, t <= 1. */
bool peri_precrack_cuts(const peri_precrack *c, double dx, const double xi[3], const double xj[3]);
/* Marks every bond crossing any pre-crack broken, in both directions. Returns the number
 * of directed bonds cut. */
long peri_precracks_apply(peri_sim *s);

#endif
