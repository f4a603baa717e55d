/* Published constants. Equations cited from the model reference (docs/model_reference.md) and papers:
 * 000 = Le 2014, 002 = Ongaro 2022, 004 = Ebrahimi 2020. */
#include <math.h>
#include "peri/constants.h"

/* docs/model_reference.md 2.3: Le 2014 eqs. 1.6, 1.15; Ongaro 2022 eqs. 1.38-1.42. */
double peri_pmb_micromodulus(const peri_geometry *g, double E, double K) {
  const double d = g->horizon;
  switch (g->dim) {
  case 3: return 18.0 * K / (M_PI * pow(d, 4));
  case 2:
    if (g->plane == PERI_PLANE_STRAIN) return 48.0 * E / (5.0 * M_PI * g->thickness * pow(d, 3));
    return 9.0 * E / (M_PI * g->thickness * pow(d, 3));
  default: return 2.0 * E / (g->cross_section * d * d);
  }
}

/* Simpson's rule on [0, d] with an even number of panels; the integrands are smooth
 * once multiplied by r^power (power >= 1). */
double peri_influence_moment(peri_influence w, int dim, double d) {
  const int panels = 2000;
  const double h = d / panels;
  double sum = 0.0;
  for (int k = 0; k <= panels; ++k) {
    double r = k * h;
    /* at r = 0 the integrand is its limit: 1 for omega = 1/r with power 1, else 0 */
    double f = r > 0.0 ? peri_influence_value(w, r, d) * pow(r, dim)
                       : (w == PERI_INFLUENCE_INVERSE && dim == 1 ? 1.0 : 0.0);
    double weight = (k == 0 || k == panels) ? 1.0 : (k % 2 ? 4.0 : 2.0);
    sum += weight * f;
  }
  return sum * h / 3.0;
}

/* docs/model_reference.md 2.2: the energy-matching calibration holds for any profile c(xi). */
double peri_influence_calibration(peri_influence w, int dim, double delta) {
  if (w == PERI_INFLUENCE_CONSTANT) return 1.0;
  double constant = pow(delta, dim + 1) / (dim + 1);
  return constant / peri_influence_moment(w, dim, delta);
}

/* docs/model_reference.md 4: m = S_d int_0^d omega r^2 r^(d-1) dr, S_3 = 4 pi, S_2 = 2 pi h, S_1 = 2 A. */
double peri_weighted_volume_analytic(const peri_geometry *g, peri_influence w) {
  double radial = peri_influence_moment(w, g->dim + 1, g->horizon);
  if (g->dim == 3) return 4.0 * M_PI * radial;
  if (g->dim == 2) return 2.0 * M_PI * g->thickness * radial;
  return 2.0 * g->cross_section * radial;
}

/* docs/model_reference.md 2.3 (Ongaro 2022 eqs. 1.45-1.48; 1D derived with 2.2). */
double peri_critical_stretch_pmb(const peri_geometry *g, double G0, double E, double K) {
  const double d = g->horizon;
  switch (g->dim) {
  case 3: return sqrt(5.0 * G0 / (9.0 * K * d));
  case 2:
    if (g->plane == PERI_PLANE_STRAIN) return sqrt(5.0 * M_PI * G0 / (12.0 * E * d));
    return sqrt(4.0 * M_PI * G0 / (9.0 * E * d));
  default: return sqrt(3.0 * G0 / (E * d));
  }
}

/* docs/model_reference.md 7.2 (Ongaro 2022 eqs. 1.95-1.97). */
double peri_critical_stretch_lps(const peri_geometry *g, double G0, double E) {
  if (g->dim == 3) return sqrt(5.0 * G0 / (6.0 * E * g->horizon));
  return peri_critical_stretch_pmb(g, G0, E, 0.0);
}

/* docs/model_reference.md 2.3 notes (Ongaro 2022 eqs. 1.49-1.50). */
double peri_fracture_energy_from_toughness(const peri_geometry *g, double KIc, double E, double nu) {
  bool plane_strain = g->dim == 3 || (g->dim == 2 && g->plane == PERI_PLANE_STRAIN);
  double E_eff = plane_strain ? E / (1.0 - nu * nu) : E;
  return KIc * KIc / E_eff;
}

/* docs/model_reference.md 3.3 table (Le 2014 eqs. 2.24-2.42; Silling 2007 for 3D). In 1D the state-based
 * bar has no dilatation term (Madenci-Oterkus 1D row, a1 = 0): W = (alpha/2)(w e).e, and
 * matching W = E eps^2/2 under uniform strain gives alpha*m = E. */
void peri_lps_constants(const peri_geometry *g, double K, double mu, double *n_theta,
                        double *K_theta, double *alpha_m) {
  double nu = (3.0 * K - 2.0 * mu) / (2.0 * (3.0 * K + mu));
  switch (g->dim) {
  case 3:
    *n_theta = 3.0;
    *K_theta = K;
    *alpha_m = 15.0 * mu;
    break;
  case 2:
    *alpha_m = 8.0 * mu;
    if (g->plane == PERI_PLANE_STRAIN) {
      *n_theta = 2.0;
      *K_theta = K + mu / 9.0;
    } else {
      double r = (1.0 + nu) / (1.0 - 2.0 * nu);
      *n_theta = 2.0 * (1.0 - 2.0 * nu) / (1.0 - nu);
      *K_theta = K + (mu / 9.0) * r * r;
    }
    break;
  default:
    *n_theta = 0.0;
    *K_theta = 0.0;
    *alpha_m = 9.0 * K * mu / (3.0 * K + mu); /* E */
    break;
  }
}

/* Madenci-Oterkus (Ebrahimi 2020 Table 2.1; MODELS.md 3.5-3.6) in the LPS fields: n the
 * dimension of the dilatation (theta = n times the horizon-average stretch), K_theta = 2 a1
 * (W = K_theta theta^2/2 + ...), alpha*m = 2 b m with m the weighted volume of omega =
 * delta/|xi| (pi delta^5 in 3D, 2 pi h delta^4/3 in 2D, A delta^3 in 1D):
 *   3D  a1 = (K - 5 mu/3)/2,   b = 15 mu/(2 pi delta^5):    alpha*m = 15 mu
 *   2D  a1 = (K2D - 2 mu)/2,   b = 6 mu/(pi h delta^4):     alpha*m = 8 mu
 *   1D  a1 = 0,                b = E/(2 A delta^3):         alpha*m = E
 * K2D = K + mu/3 (plane strain), E/(2(1 - nu)) = 9 K mu/(3K + 4 mu) (plane stress): the
 * modulus of W = 2 K2D eps^2 under isotropic in-plane strain (MODELS.md 3.5, Derived). */
void peri_mo_constants(const peri_geometry *g, double K, double mu, double *n_theta, double *K_theta,
                       double *alpha_m) {
  switch (g->dim) {
  case 3:
    *n_theta = 3.0;
    *K_theta = K - 5.0 * mu / 3.0;
    *alpha_m = 15.0 * mu;
    break;
  case 2: {
    const double K2D = g->plane == PERI_PLANE_STRAIN ? K + mu / 3.0 : 9.0 * K * mu / (3.0 * K + 4.0 * mu);
    *n_theta = 2.0;
    *K_theta = K2D - 2.0 * mu;
    *alpha_m = 8.0 * mu;
    break;
  }
  default:
    *n_theta = 1.0;
    *K_theta = 0.0;
    *alpha_m = 9.0 * K * mu / (3.0 * K + mu); /* E */
    break;
  }
}

/* docs/model_reference.md 13.2: M = K + 4mu/3 (3D, plane strain), E/(1-nu^2) (plane stress), E (1D). */
double peri_pwave_modulus(const peri_geometry *g, double E, double nu, double K, double mu) {
  if (g->dim == 1) return E;
  if (g->dim == 2 && g->plane == PERI_PLANE_STRESS) return E / (1.0 - nu * nu);
  return K + 4.0 * mu / 3.0;
}

/* docs/model_reference.md 13.2: c_eq = 10M/(pi d^4) (3D), 8M/(pi h d^3) (2D), 2M/(A d^2) (1D). */
double peri_stable_micromodulus(const peri_geometry *g, double M) {
  const double d = g->horizon;
  if (g->dim == 3) return 10.0 * M / (M_PI * pow(d, 4));
  if (g->dim == 2) return 8.0 * M / (M_PI * g->thickness * pow(d, 3));
  return 2.0 * M / (g->cross_section * d * d);
}
