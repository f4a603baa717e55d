/* The peridynamic heat conduction operator (src/model/thermal.c, docs/model_reference.md 11):
 * micro-conductivities, the bond conductances and the stable time step of conduction. */
#ifndef PERI_CONDUCTION_H
#define PERI_CONDUCTION_H
#include "peri/model.h"
#include "peri/sim.h"
#include "peri/thermal.h"

/* Micro-conductivity constant of the kernel (docs/model_reference.md 11.2), from the flux of a linear
 * field: constant k0 = kappa/delta (1D), 4 kappa/(pi delta^2) (2D), 9 kappa/(2 pi delta^3) (3D);
 * conical k1 = 2 kappa/delta, 12 kappa/(pi delta^2), 18 kappa/(pi delta^3). */
double peri_thermal_k_constant(peri_thermal_kernel kernel, int dim, double kappa, double delta);
/* k(r) = k0 (constant) or k1 (1 - r/delta) (conical, 0 beyond delta). */
double peri_thermal_k(peri_thermal_kernel kernel, int dim, double kappa, double delta, double r);
/* The continuum flux into a point of the linear field T = g.x (Bobaru & Duangpanya 2012 eq. 7) over the
 * half horizon H+, by Gauss-Legendre quadrature that is exact for the kernels (polynomial
 * in r, trigonometric in angle): q_into = kappa g. */
void peri_thermal_flux_integral(peri_thermal_kernel kernel, int dim, double kappa, double delta,
                                const double g[3], double q[3]);
/* Bond conductivity of two materials: min (lower) or harmonic mean. */
double peri_thermal_bond_kappa(peri_thermal_bond_rule rule, double ka, double kb);
/* Builds the conduction operator (H, area, rho c) from the sim's bonds and materials.
 * Returns 0 or PERI_ERR_INPUT with a message. */
int peri_thermal_build(peri_sim *s);
/* Stability bound of the integrator, from the largest row sum (docs/model_reference.md 11.6):
 * Euler 1/max_row, RK4 1.3926/max_row (1.3926 = 2.7853/2, RK4's real-axis limit / 2). */
double peri_thermal_stable_dt(const peri_thermal *th);
void peri_thermal_free(peri_thermal *th);

/* The "model" of conduction-only runs (no mechanics: no forces, no energy). */
extern const peri_model_ops peri_model_heat_only;

#endif
