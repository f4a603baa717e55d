/* Isotropic elastic constants from any two of E, nu, K, mu. */
#include <math.h>
#include <stdio.h>
#include "peri/error.h"
#include "peri/material.h"

double peri_pmb_poisson(const peri_geometry *g) {
  return (g->dim == 2 && g->plane == PERI_PLANE_STRESS) ? 1.0 / 3.0 : 0.25;
}

int peri_elastic_resolve(double E, double nu, double K, double mu, double fixed_nu,
                         double *E_out, double *nu_out, double *K_out, double *mu_out,
                         char *why, int n) {
  int given = !isnan(E) + !isnan(nu) + !isnan(K) + !isnan(mu);
  if (given == 1 && !isnan(fixed_nu) && isnan(nu)) {
    nu = fixed_nu;
    given = 2;
  }
  if (given != 2) {
    snprintf(why, n, "give exactly two of youngs_modulus, poisson_ratio, bulk_modulus, "
                     "shear_modulus (got %d)", given);
    return PERI_ERR_INPUT;
  }
  if (!isnan(E) && !isnan(nu)) {
    K = E / (3.0 * (1.0 - 2.0 * nu));
    mu = E / (2.0 * (1.0 + nu));
  } else if (!isnan(K) && !isnan(mu)) {
    E = 9.0 * K * mu / (3.0 * K + mu);
    nu = (3.0 * K - 2.0 * mu) / (2.0 * (3.0 * K + mu));
  } else if (!isnan(E) && !isnan(K)) {
    nu = (3.0 * K - E) / (6.0 * K);
    mu = 3.0 * K * E / (9.0 * K - E);
  } else if (!isnan(E) && !isnan(mu)) {
    nu = E / (2.0 * mu) - 1.0;
    K = E * mu / (3.0 * (3.0 * mu - E));
  } else if (!isnan(K) && !isnan(nu)) {
    E = 3.0 * K * (1.0 - 2.0 * nu);
    mu = E / (2.0 * (1.0 + nu));
  } else { /* mu and nu */
    E = 2.0 * mu * (1.0 + nu);
    K = E / (3.0 * (1.0 - 2.0 * nu));
  }
  if (!(E > 0.0) || !(mu > 0.0) || !(K > 0.0) || !(nu > -1.0) || !(nu < 0.5)) {
    snprintf(why, n, "elastic constants are not admissible (E = %g, nu = %g, K = %g, mu = %g; "
                     "need E, K, mu > 0 and -1 < nu < 1/2)", E, nu, K, mu);
    return PERI_ERR_INPUT;
  }
  *E_out = E;
  *nu_out = nu;
  *K_out = K;
  *mu_out = mu;
  return PERI_OK;
}
