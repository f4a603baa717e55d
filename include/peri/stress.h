/* Stress and strain recovery (docs/model_reference.md 10): the symmetrised collapsed PD stress of paper
 * Le 2014 eq. 3.1, sigma_i = 1/2 sum_j (t_ij + t_ji) M_ij (x) xi_ij chi beta V_j, the strain
 * from the nonlocal deformation gradient F = (sum w Y (x) xi)(sum w xi (x) xi)^-1, and the
 * scalar measures (von Mises in plane stress / plane strain / 3D, principal stresses). */
#ifndef PERI_STRESS_H
#define PERI_STRESS_H
#include <stdio.h>
#include "peri/sim.h"

/* Symmetric part of the PD stress of every owned node into sigma[9n] (row-major 3x3, Pa).
 * Evaluates the model's forces at the current u first (bonds do not break). Returns
 * PERI_OK, or PERI_ERR_RUN when the model has no stress recovery. */
int peri_stress(peri_sim *s, double *sigma);
/* The same for the owned nodes i with wanted[i] != 0 (all when wanted is NULL); the others'
 * sigma is 0. (The forces are evaluated for every node as above.) */
int peri_stress_of(peri_sim *s, double *sigma, const uint8_t *wanted);
/* Small strain eps = (F + F^T)/2 - I into eps[9n]; in plane stress eps33 from the
 * material's Poisson ratio, -nu/(1-nu)(eps11+eps22). */
void peri_strain(const peri_sim *s, double *eps);
/* Displacement gradient H = F - I of node i (row-major, H[3a + c] = du_a/dx_c) from the
 * nonlocal deformation gradient over its intact bonds; false (H = 0) when the shape tensor is
 * singular (a node with too few bonds). */
bool peri_displacement_gradient(const peri_sim *s, int32_t i, double H[9]);
/* Von Mises stress of a symmetric stress (row-major) in the problem's dimension and plane:
 * plane stress sqrt(s11^2 + s22^2 - s11 s22 + 3 s12^2); plane strain with
 * s33 = nu (s11 + s22); 1D |s11|. */
double peri_von_mises(const peri_sim *s, const double sig[9], double nu);
/* Principal stresses, descending (2D: the in-plane pair and s33). */
void peri_principal_stresses(const peri_sim *s, const double sig[9], double nu, double out[3]);
/* von_mises[n] (and principal[3n] if not NULL) of every owned node from sigma[9n]. */
void peri_stress_measures(const peri_sim *s, const double *sigma, double *von_mises, double *principal);

#endif
