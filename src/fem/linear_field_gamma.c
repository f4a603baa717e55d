/* The correction factor gamma of the coupled model's micromodulus for the family the PD rows
 * use (coupling.gamma: auto; 002_b20c318388227af9.txt eq. 2.39, Remark A.2): c is matched to E
 * over the continuous horizon, but the rows sum over lattice neighbours with partial volumes,
 * so a linear field gives a discrete stress that is not the classical one (3.3% too stiff at
 * m = 3 with the linear ramp in plane strain). gamma = classical / discrete stress of the
 * uniaxial strain u = (x, 0, 0) at a node with a full family: sigma_xx = M (the P-wave modulus
 * of the bond-based nu) against (1/2) sum_j lambda(|xi|) beta_j V_j xi_x^4, which is also the
 * nonlocal traction of that field across a lattice plane (eqs. A.15, A.34), the t2 / tau2_num of
 * Remark A.2. With the exact partial volumes it is the seed's 0.9784710341 at m = 3. */
#include <math.h>
#include <stdlib.h>
#include "peri/bonds.h"
#include "peri/coupling.h"
#include "peri/sim.h"

/* sum over the lattice offsets of the family of lambda beta V xi_x^4 (1D: xi^2), with E = 1 */
static double discrete_stiffness(const peri_sim *s, const peri_coupling *c) {
  const peri_geometry *g = &s->disc.geom;
  const peri_bonds *b = &s->disc.bonds;
  const int dim = g->dim;
  const double dx = g->spacing, delta = g->horizon;
  const double c1 = peri_coupling_micromodulus(dim, g->plane, 1.0, c->alpha, delta, g->thickness, g->cross_section);
  const double V = dim == 1 ? dx * g->cross_section : dim == 2 ? dx * dx * g->thickness : dx * dx * dx;
  double sum = 0.0;
  if (c->exact_volumes) { /* the lattice cells that meet the horizon (coupling.c) */
    for (int32_t q = 0; q < c->n_offsets; ++q) {
      const double x = c->offset[3 * (size_t)q] * dx, y = c->offset[3 * (size_t)q + 1] * dx;
      const double L = hypot(x, y), term = dim == 1 ? x * x : x * x * x * x;
      sum += c1 * pow(L, -c->alpha) * c->offset_beta[q] * V * term;
    }
    return 0.5 * sum;
  }
  const int R = (int)ceil(delta / dx) + 1;
  for (int k = dim > 2 ? -R : 0; k <= (dim > 2 ? R : 0); ++k)
    for (int j = dim > 1 ? -R : 0; j <= (dim > 1 ? R : 0); ++j)
      for (int i = -R; i <= R; ++i) {
        if (!i && !j && !k) continue;
        const double x = i * dx, L = sqrt((double)(i * i + j * j + k * k)) * dx;
        if (!(peri_partial_volume_factor(b->family.rule, L, delta, dx) > 0.0)) continue; /* not a neighbour */
        const double term = dim == 1 ? x * x : x * x * x * x;
        sum += c1 * pow(L, -c->alpha) * peri_bonds_beta(b, L) * V * term;
      }
  return 0.5 * sum;
}

double peri_coupling_linear_field_gamma(const peri_sim *s) {
  const peri_geometry *g = &s->disc.geom;
  /* the P-wave modulus over E of the bond-based Poisson ratio: 1 (1D), 1/(1 - nu^2) at nu = 1/3
   * (plane stress), (1 - nu)/((1 + nu)(1 - 2 nu)) at nu = 1/4 (plane strain, 3D) */
  const double M = g->dim == 1 ? 1.0 : g->dim == 2 && g->plane != PERI_PLANE_STRAIN ? 9.0 / 8.0 : 6.0 / 5.0;
  return M / discrete_stiffness(s, s->coupling);
}

void peri_coupling_set_gamma(peri_sim *s, double gamma) {
  peri_coupling *c = s->coupling;
  for (int m = 0; m < s->mat.n_materials; ++m) c->c[m] *= gamma / c->gamma;
  c->gamma = gamma;
}
