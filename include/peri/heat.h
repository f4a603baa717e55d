/* Heat conduction in time (src/solver/heat.c, docs/heat.md): sources and conditions, the rate
 * dT/dt, Euler and RK4 steps, growing cracks, and the coupling with explicit mechanics. */
#ifndef PERI_HEAT_H
#define PERI_HEAT_H
#include "peri/sim.h"
#include "peri/thermal.h"

/* Allocates the integrator buffers and evaluates the largest row sum (after the
 * conditions are set). */
void peri_thermal_prepare(peri_sim *s);
/* dT/dt of every node into out [n] at the temperature field T and time t (prescribed and
 * algebraic nodes get 0). Uses th->cut. */
void peri_thermal_rate(const peri_sim *s, const double *T, double t, double *out);
/* Sets prescribed temperatures at time t and re-imposes the algebraic flux rule on T. */
void peri_thermal_constrain(const peri_sim *s, double *T, double t);
/* Advances the temperature by one step dt from th->time (RK4 or Euler); cuts growing-crack
 * bonds reached by then. Returns 0, or PERI_ERR_RUN if the temperature is not finite. */
int peri_thermal_step(peri_sim *s, double dt);
/* Cuts the bonds of growing cracks whose tip has passed them by time t. Returns the number. */
long peri_thermal_grow_cracks(peri_sim *s, double t);
/* Per-node thermal strain alpha_eff (T - T_ref) into s->state.thermal_strain. */
void peri_thermal_update_strain(peri_sim *s);
/* Coupled runs: advances the heat to time t (sub-cycled) when due at this mechanical step,
 * then updates the thermal strain. Called by the explicit solver before the force. */
int peri_thermal_couple(peri_sim *s, long step, double t);

#endif
