/* Construction and checks of the mechanical sublayers of a bond (model reference 16.1,
 * Ebrahimi 2020 §5.1.1 eqs. 5.1-5.2; docs/plasticity.md). */
#include <math.h>
#include <stdio.h>
#include "peri/plasticity.h"

int peri_sublayers_from_curve(double E, int n, const double *strain, const double *stress, peri_sublayers *out,
                              int *bad, char *why, size_t why_size) {
  *bad = -1;
  if (n < 1 || n > PERI_MAX_SUBLAYERS) {
    snprintf(why, why_size, "give 1 to %d points (got %d)", PERI_MAX_SUBLAYERS, n);
    return -1;
  }
  if (!(strain[0] > 0.0) || fabs(stress[0] - E * strain[0]) > 1e-3 * fabs(E * strain[0])) {
    *bad = 0;
    snprintf(why, why_size,
             "the first point (%g, %g) must lie on the elastic line stress = E strain (E strain = %g): it is "
             "the first yield point",
             strain[0], stress[0], E * strain[0]);
    return -1;
  }
  /* slopes e_1 = E, e_k = (sigma_k - sigma_{k-1})/(eps_k - eps_{k-1}) */
  double slope[PERI_MAX_SUBLAYERS + 1];
  slope[0] = E;
  for (int k = 1; k < n; ++k) {
    const double de = strain[k] - strain[k - 1];
    if (!(de > 0.0)) {
      *bad = k;
      snprintf(why, why_size, "point %d: strain %g does not increase (previous %g)", k + 1, strain[k], strain[k - 1]);
      return -1;
    }
    slope[k] = (stress[k] - stress[k - 1]) / de;
    if (slope[k] < 0.0) {
      *bad = k;
      snprintf(why, why_size, "point %d: the curve has a negative slope (%g) after strain %g: softening is not "
               "a sublayer curve", k + 1, slope[k], strain[k - 1]);
      return -1;
    }
    if (slope[k] > slope[k - 1]) {
      *bad = k;
      snprintf(why, why_size, "point %d: the slope increases (%g after %g): a sublayer would have a negative weight",
               k + 1, slope[k], slope[k - 1]);
      return -1;
    }
  }
  slope[n] = 0.0; /* flat beyond the last point */
  out->n = n;
  for (int k = 0; k < n; ++k) {
    out->weight[k] = (slope[k] - slope[k + 1]) / E;
    out->yield[k] = strain[k];
  }
  return 0;
}

void peri_deviatoric_curve(double K, int n, const double *strain, const double *stress, double *dev_strain,
                           double *dev_stress) {
  for (int k = 0; k < n; ++k) {
    dev_strain[k] = strain[k] - stress[k] / (9.0 * K); /* eps minus the mean strain sigma / (9K) */
    dev_stress[k] = 2.0 * stress[k] / 3.0;             /* sigma minus the mean stress sigma / 3 */
  }
}

void peri_power_law_stresses(double sigma0, double eps0, double exponent, int n, const double *strain,
                             double *stress) {
  for (int k = 0; k < n; ++k) stress[k] = sigma0 * pow(strain[k] / eps0, exponent);
}

void peri_power_law_strains(double sigma0, double eps0, double exponent, int n, const double *stress,
                            double *strain) {
  for (int k = 0; k < n; ++k) strain[k] = eps0 * pow(stress[k] / sigma0, 1.0 / exponent);
}

int peri_sublayers_check(const peri_sublayers *sl, int *bad, char *why, size_t why_size) {
  *bad = -1;
  if (sl->n < 1 || sl->n > PERI_MAX_SUBLAYERS) {
    snprintf(why, why_size, "give 1 to %d sublayers (got %d)", PERI_MAX_SUBLAYERS, sl->n);
    return -1;
  }
  double sum = 0.0;
  for (int k = 0; k < sl->n; ++k) {
    if (!(sl->weight[k] > 0.0)) {
      *bad = k;
      snprintf(why, why_size, "weight %d (%g) must be positive", k + 1, sl->weight[k]);
      return -1;
    }
    if (!(sl->yield[k] > 0.0) || (k > 0 && !(sl->yield[k] > sl->yield[k - 1]))) {
      *bad = k;
      snprintf(why, why_size, "yield stretch %d (%g) must be positive and larger than the one before", k + 1,
               sl->yield[k]);
      return -1;
    }
    sum += sl->weight[k];
  }
  if (!(fabs(sum - 1.0) <= PERI_SUBLAYER_WEIGHT_TOLERANCE)) {
    snprintf(why, why_size, "the weights sum to %.6g, not 1 (within %g)", sum, PERI_SUBLAYER_WEIGHT_TOLERANCE);
    return -1;
  }
  return 0;
}

double peri_sublayers_monotonic(const peri_sublayers *sl, double eps) {
  double s = 0.0;
  for (int k = 0; k < sl->n; ++k) s += sl->weight[k] * fmin(eps, sl->yield[k]);
  return s;
}

double peri_critical_bond_work(int dim, double G0, double delta, double thickness, double cross_section) {
  if (dim == 3) return 4.0 * G0 / (M_PI * pow(delta, 4));
  if (dim == 2) return 3.0 * G0 / (2.0 * thickness * pow(delta, 3));
  return 2.0 * G0 / (cross_section * delta * delta);
}
