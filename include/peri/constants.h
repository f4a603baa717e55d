/* Published constants: bond-based micromoduli, critical stretches, LPS constants.
 * Each function names the equation it implements (model reference = docs/model_reference.md). */
#ifndef PERI_CONSTANTS_H
#define PERI_CONSTANTS_H
#include "peri/material.h"
#include "peri/bonds.h"

/* PMB micromodulus for a constant influence function:
 * 3D 18K/(pi d^4); plane stress 9E/(pi h d^3); plane strain 48E/(5 pi h d^3); 1D 2E/(A d^2). */
double peri_pmb_micromodulus(const peri_geometry *g, double E, double K);
/* Factor that rescales the constant-influence micromodulus so that the influence-weighted
 * PMB (f = c omega s) stores the same energy under isotropic stretch:
 * int_0^d r^dim dr / int_0^d omega(r) r^dim dr. */
double peri_influence_calibration(peri_influence w, int dim, double delta);
/* int_0^delta omega(r) r^power dr (Simpson's rule). */
double peri_influence_moment(peri_influence w, int power, double delta);
/* Analytic weighted volume m = int_H omega |xi|^2 dV of a full horizon (docs/model_reference.md 4). */
double peri_weighted_volume_analytic(const peri_geometry *g, peri_influence w);
/* Critical stretch from the fracture energy G0 (bond-based energy to break all bonds
 * across a unit crack): 3D sqrt(5G0/(9K d)); plane stress sqrt(4 pi G0/(9E d));
 * plane strain sqrt(5 pi G0/(12 E d)); 1D sqrt(3 G0/(E d)). */
double peri_critical_stretch_pmb(const peri_geometry *g, double G0, double E, double K);
/* The state-based default (Ongaro eqs. 1.95-1.97): as above but 3D sqrt(5G0/(6E d)). */
double peri_critical_stretch_lps(const peri_geometry *g, double G0, double E);
/* G0 = K_Ic^2 / E', E' = E in plane stress and 1D, E/(1-nu^2) in plane strain and 3D. */
double peri_fracture_energy_from_toughness(const peri_geometry *g, double KIc, double E, double nu);
/* LPS constants n_theta, K_theta, alpha*m (model reference section 3.3). */
void peri_lps_constants(const peri_geometry *g, double K, double mu, double *n_theta,
                        double *K_theta, double *alpha_m);
/* Madenci-Oterkus constants in the same three numbers (src/model/constants.c): n, K_theta = 2 a1,
 * alpha*m = 2 b m (Ebrahimi 2020 Table 2.1 with the weighted volume of omega = delta/|xi|). */
void peri_mo_constants(const peri_geometry *g, double K, double mu, double *n_theta, double *K_theta,
                       double *alpha_m);
/* P-wave modulus M and its PMB-equivalent micromodulus c_eq (section 13.2). */
double peri_pwave_modulus(const peri_geometry *g, double E, double nu, double K, double mu);
double peri_stable_micromodulus(const peri_geometry *g, double M);

#endif
