/* The partial-stress force of the coupling region (docs/model_reference.md 15.2-15.3,
 * docs/variable_horizon.md): L0 = div nu0 with nu0_i = sum_j T_i<xi_ij> (x) xi_ij V_j. */
#ifndef PERI_PARTIAL_STRESS_H
#define PERI_PARTIAL_STRESS_H
#include "peri/sim.h"

/* Builds the least-squares gradient stencil of every coupled node: its neighbours within
 * 1.5 spacings (in 1D the two nearest, so the gradient is the central difference). Returns
 * PERI_OK, or PERI_ERR_INPUT after a message naming a node whose stencil does not span the
 * dimensions. */
int peri_partial_stress_prepare(peri_sim *s);
/* nu0 of the coupled nodes and of their stencils' nodes from the force states in
 * h->state, then f_i = div nu0 at every coupled node i. */
void peri_partial_stress_force(peri_sim *s);

#endif
