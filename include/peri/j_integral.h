/* The J-integral of a crack tip over contours given in the deck, and the crack extension
 * (docs/plasticity.md section 6, src/post/j_integral.c). 2D: J per unit length of the crack
 * front, from the equivalent domain integral of Shih, Moran and Nakamura (1986) over the
 * square ring between each contour's inner and outer half-widths, with the PD stress, the
 * nonlocal displacement gradient and the work density of the nodes. */
#ifndef PERI_J_INTEGRAL_H
#define PERI_J_INTEGRAL_H
#include "peri/sim.h"

#define PERI_MAX_J_CONTOURS 16

typedef struct peri_j_integral {
  double tip[3];        /* crack tip (m) */
  double direction[3];  /* unit vector along which the crack grows, in the plane */
  int n_contours;
  double inner[PERI_MAX_J_CONTOURS], outer[PERI_MAX_J_CONTOURS]; /* half-widths of the rings (m) */
  double damage_threshold; /* a node at least this damaged is cracked (crack extension) */
  double band;          /* half-width of the strip along the crack line searched for cracked nodes (m) */
  double thickness;     /* 2D thickness: the length of the crack front (m) */
} peri_j_integral;

/* J of every contour (J/m^2) into J[n_contours] and the crack extension (m): the largest
 * distance ahead of the tip, along `direction`, of a node within `band` of the crack line
 * whose damage is at least damage_threshold (0 when none). Evaluates the model's forces at
 * the current displacement (no breaking). All ranks call it; the sums are in fixed order.
 * Returns PERI_OK or PERI_ERR_RUN. */
int peri_j_integral_values(peri_sim *s, const peri_j_integral *j, double *J, double *crack_extension);

#endif
