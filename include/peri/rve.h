/* Homogenized moduli of a nanocomposite RVE (002_b20c318388227af9.txt §3.3.1, eqs. 3.3-3.9) and
 * their Monte-Carlo over realizations of peri/rve_geometry.h. docs/microstructures.md section 7. */
#ifndef PERI_RVE_H
#define PERI_RVE_H
#include "peri/rve_geometry.h"

/* The homogenized constants of one realization (eqs. 3.8, 3.9). */
typedef struct peri_rve_moduli {
  double E11, E22, nu12, nu21;
  int platelets;
  double filler_fraction; /* filler nodes / n^2 */
  int iterations;         /* conjugate-gradient iterations, both load cases */
} peri_rve_moduli;

/* Solves the two load cases of g; returns 0, or -1 (out of memory, or the solver did not
 * converge: peri_error says which). */
int peri_rve_homogenize(const peri_rve_params *p, const peri_rve_geometry *g, peri_rve_moduli *out);

/* Monte-Carlo: realizations 0..count-1 in parallel (OpenMP threads, one realization each);
 * each[k] receives realization k, so the results do not depend on the number of threads.
 * Returns 0 or -1. */
int peri_rve_monte_carlo(const peri_rve_params *p, int count, peri_rve_moduli *each);

/* Mean and sample standard deviation (n - 1) of count values, summed in index order. */
void peri_rve_mean_std(const double *v, int count, double *mean, double *std);

#endif
