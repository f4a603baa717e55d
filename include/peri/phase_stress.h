/* Stress per phase (material) of a multi-phase body (src/post/phase_stress.c,
 * docs/microstructures.md): the largest von Mises stress of each material and where, and its
 * mean stress, over the body nodes (fictitious boundary layers left out, as Le 2014 section 3.2
 * leaves out its dummy layers). */
#ifndef PERI_PHASE_STRESS_H
#define PERI_PHASE_STRESS_H
#include <stdio.h>
#include "peri/sim.h"

typedef struct peri_phase_stress {
  double max_von_mises; /* Pa; -inf when the material has no body node */
  double where[3];      /* reference position of the node of the largest value (the first such node) */
  double mean_stress;   /* Pa: the volume-weighted mean of tr(sigma)/3 (sigma_33 of the plane condition in 2D) */
  double volume;        /* m^3: the material's body volume */
} peri_phase_stress;

/* out[m] for every material m from the stress sigma[9 n_owned] of peri_stress. Collective on MPI
 * ranks; every rank gets the result, independent of the rank and thread counts. */
void peri_phase_stresses(const peri_sim *s, const double *sigma, peri_phase_stress *out);
/* The same, the stress evaluated first (peri_stress); PERI_ERR_RUN without stress recovery. */
int peri_phase_stresses_now(peri_sim *s, peri_phase_stress *out);
/* Prints "  max von Mises <material>: <value> Pa at (x, y, z), mean stress <value> Pa" for every
 * material with body nodes (rank 0 prints; collective). */
void peri_print_stress_summary(peri_sim *s, FILE *out);

#endif
