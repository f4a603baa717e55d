/* Derived quantities of heat conduction (src/post/heat_quantities.c, docs/heat.md). */
#ifndef PERI_HEAT_QUANTITIES_H
#define PERI_HEAT_QUANTITIES_H
#include "peri/sim.h"
#include "peri/thermal.h"

/* Total heat sum_i rho_i c_i T_i A_i g (J, g = h in 2D, A in 1D). */
double peri_thermal_total_heat(const peri_sim *s);
/* Net heat flow (W) into the nodes of a region from the other nodes. */
double peri_thermal_region_inflow(const peri_sim *s, int region);
/* Heat flux per node into th->flux [3n]: the into-flux of Bobaru & Duangpanya 2012 eq. 7, discrete form
 * q_i = sum_{p: T_p > T_i} chi H_ip (T_p - T_i) (x_p - x_i) (points towards hotter nodes;
 * equals kappa grad T = -q_Fourier for a linear field). */
void peri_thermal_flux(const peri_sim *s);
/* Extra history columns of coupled runs. */
int peri_thermal_history_count(const peri_sim *s);
void peri_thermal_history_names(const peri_sim *s, char **names);
void peri_thermal_history_values(const peri_sim *s, double *values);

#endif
