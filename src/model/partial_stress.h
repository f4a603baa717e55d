/* The partial-stress force of the coupling region (docs/model_reference.md 15.2-15.3,
 * docs/variable_horizon.md): L0 = div nu0 with nu0_i = sum_j T_i<xi_ij> (x) xi_ij V_j. */
#ifndef PERI_PARTIAL_STRESS_H
#define PERI_PARTIAL_STRESS_H
#include "peri/sim.h"

/* Builds, for every coupled node, the weighted least-squares gradient over its bonds (the
 * weights V_j d t_i / d e of its own state) and the quadratic fit of the zero-energy mode
 * control, and for every peridynamic node of a stencil the lattice correction C_iso D_i^-1,
 * probing D_i with compute_states (the model's force states of p->u into h->state; p->u, the
 * broken flags and h->state are restored). Returns PERI_OK, or PERI_ERR_INPUT after a message
 * naming a node whose bonds do not determine them. */
int peri_partial_stress_prepare(peri_sim *s, void (*compute_states)(peri_sim *s));
/* nu0 of the coupled nodes and of their bonds' nodes from the force states in h->state,
 * then f_i = div nu0 plus the zero-energy mode control at every coupled node i. */
void peri_partial_stress_force(peri_sim *s);
/* A local node's (horizon 0) strain energy density 1/2 sigma : eps, with eps the symmetric
 * part of its least-squares displacement gradient and sigma the Cauchy stress of it. */
double peri_partial_stress_local_energy(const peri_sim *s, int32_t i);

#endif
