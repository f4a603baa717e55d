/* Surface correction (src/model/surface_correction.c, docs/models.md 4.1). */
#ifndef PERI_SURFACE_CORRECTION_H
#define PERI_SURFACE_CORRECTION_H
#include "peri/sim.h"

/* Computes the bond factors (s->disc.bonds.surface_G, surface_D) of the deck's correction,
 * once, in the reference configuration, after the model's init; nothing without one.
 * Returns PERI_OK or PERI_ERR_INPUT with a message (a correction the model or solver cannot
 * take). `lps`: the model is lps (else pmb). */
int peri_surface_factors(peri_sim *s, bool lps);
/* The corrected models' force passes (as peri_force_pass), energies and pair forces. */
long peri_corrected_pmb_force(peri_sim *s, bool update_s0);
void peri_corrected_pmb_energy(peri_sim *s, double *W);
double peri_corrected_pmb_pair(const peri_sim *s, int32_t i, int64_t k, double r);
long peri_corrected_lps_force(peri_sim *s, bool update_s0);
void peri_corrected_lps_energy(peri_sim *s, double *W);
double peri_corrected_lps_pair(const peri_sim *s, int32_t i, int64_t k, double r);
/* The break test of the corrected loops (before the force), shared by both corrections. */
long peri_corrected_break(peri_sim *s, bool update_s0);
/* position_aware (src/model/position_aware.c): the factors, and the LPS loops; the PMB
 * takes the corrected loops above with its symmetric bond factors. `own`: node i's half
 * t_ij of the pair force alone (stress recovery). */
int peri_position_aware_factors(peri_sim *s, bool lps);
long peri_position_aware_lps_force(peri_sim *s, bool update_s0);
void peri_position_aware_lps_dilatation(peri_sim *s);
double peri_position_aware_lps_pair(const peri_sim *s, int32_t i, int64_t k, double r);
double peri_position_aware_lps_own(const peri_sim *s, int32_t i, int64_t k, double r);

#endif
