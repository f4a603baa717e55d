/* The plasticity outputs of the owned nodes (src/post/plastic_fields.c, docs/plasticity.md). */
#ifndef PERI_PLASTIC_FIELDS_H
#define PERI_PLASTIC_FIELDS_H
#include "peri/sim.h"

/* Yield index psi_i = sum_j beta V_j [s^p_1,ij != 0] / sum_j beta V_j over the family: the
 * volume fraction of bonds whose first sublayer has yielded (model reference 16.3). */
void peri_yield_index(const peri_sim *s, double *psi);
/* Largest |sum_k W_k s^p_k| over the node's intact bonds (the bond's plastic stretch). */
void peri_plastic_stretch_field(const peri_sim *s, double *out);
/* The mean yield index of the nodes (all ranks). */
double peri_mean_yield_index(const peri_sim *s);

#endif
