/* Quantities of films on substrates and of interfaces between materials (docs/thin_films.md):
 * the interface nodes, the broken interface bonds and the interface stress sigma_int of
 * Ebrahimi 2020 section 4.2.3, the strain energy of a region, and the wrinkle amplitude and
 * wavelength from a film's deflection profile. */
#ifndef PERI_FILM_QUANTITIES_H
#define PERI_FILM_QUANTITIES_H
#include <stdint.h>
#include "peri/sim.h"

/* flag[i] = 1 for every owned node with a bond (intact or broken) to a node of another
 * material, 0 otherwise (the output field `interface`). */
void peri_interface_flags(const peri_sim *s, int32_t *flag);

/* Over all ranks: the broken directed bonds joining two materials, and sigma_int, the
 * largest tensile force of an intact such bond, pair force x beta V_i V_j (0 when none is in
 * tension: compressed bonds do not hold a film down), divided by the area of a
 * node's face (dx^2 in 3D, dx times the thickness in 2D: dx^2 for a slice one spacing
 * thick, the seed's "maximum interface force / dx^2"). Needs the forces of the present state
 * (the model's pair_force reads the last force evaluation's state). */
void peri_interface_history(const peri_sim *s, long *broken, double *max_stress);

/* Over all ranks: the strain energy sum W_i V_i of a region's nodes, with s->disc.p.energy
 * holding this state's energy densities (peri_strain_energy). */
double peri_region_strain_energy(const peri_sim *s, int region);

/* The deflection profile w(x) of a film region: for each lattice column of the region (its
 * nodes that share an x, fictitious layer nodes left out) the transverse displacement (y in
 * 2D, z in 3D) of its top node, the linear trend removed, Hann-windowed. Its discrete Fourier
 * transform gives the dominant wave number (the largest |W_k|, k >= 1, refined by a Gaussian
 * through the neighbouring bins), the wavelength (the column span over it) and the amplitude
 * (of the least-squares sine of that wave number through the detrended profile). Both 0 when the region has fewer than 4 columns or no deflection.
 * The same on every rank. */
void peri_wrinkle_profile(const peri_sim *s, int region, double *amplitude, double *wavelength);

/* The onsets along a quasi-static path of n rows (docs/thin_films.md): t_k the applied strain
 * (the pseudo-time), U_k the film's strain energy, broken_k the broken interface bonds.
 * Wrinkling: the energy criterion of Ebrahimi 2020 section 4.3, the first local maximum,
 * applied to the rate dU/dt = (U_k - U_k-1)/(t_k - t_k-1), the film's mean axial force times
 * its length, which grows linearly while the film is flat and drops when it wrinkles (on an
 * equilibrium path U itself only bends there; the seed's dynamic runs overshoot and show a
 * maximum of U). *wrinkling = the row k that ends the step of the largest rate, the last state
 * on the flat branch. Delamination: the first row with a broken interface bond. -1 where
 * there is none. */
void peri_wrinkle_onsets(const double *t, const double *energy, const double *broken, int n, int *wrinkling,
                         int *delamination);

#endif
