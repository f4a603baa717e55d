/* The elastic constant of the bonds between two materials (include/peri/interface_moduli.h,
 * docs/thin_films.md section 7). */
#include <math.h>
#include <stdlib.h>
#include "peri/bonds.h"
#include "peri/constants.h"
#include "peri/error.h"
#include "peri/interface_moduli.h"
#include "bond_kernel.h"

struct peri_interface_moduli {
  double *E;      /* [n^2] interface modulus (Pa, 0: none) */
  double *delta_c; /* [n^2] c_ab - (c_a + c_b)/2, from init (0: none) */
  uint8_t *has_pair; /* [n] the material has a pair with a modulus */
};

void peri_interface_modulus_set(peri_sim *s, int a, int b, double E) {
  const int nm = s->mat.n_materials;
  if (!s->mat.interface_moduli) {
    struct peri_interface_moduli *t = peri_calloc(1, sizeof(*t));
    t->E = peri_calloc((size_t)nm * (size_t)nm, sizeof(double));
    t->delta_c = peri_calloc((size_t)nm * (size_t)nm, sizeof(double));
    t->has_pair = peri_calloc((size_t)nm, 1);
    s->mat.interface_moduli = t;
  }
  struct peri_interface_moduli *t = s->mat.interface_moduli;
  t->E[a * nm + b] = t->E[b * nm + a] = E;
  t->has_pair[a] = t->has_pair[b] = 1;
}

void peri_interface_moduli_init(peri_sim *s) {
  struct peri_interface_moduli *t = s->mat.interface_moduli;
  if (!t) return;
  const int nm = s->mat.n_materials;
  const double calibration =
      peri_influence_calibration(s->disc.family.influence, s->disc.geom.dim, s->disc.geom.horizon);
  for (int a = 0; a < nm; ++a)
    for (int b = 0; b < nm; ++b) {
      const double E = t->E[a * nm + b];
      if (!(E > 0.0)) continue;
      /* the PMB material of modulus E: K = E/(3(1 - 2 nu)) at PMB's nu = 1/4 (used in 3D) */
      const double c = peri_pmb_micromodulus(&s->disc.geom, E, 2.0 * E / 3.0) * calibration;
      peri_material *ma = &s->mat.materials[a], *mb = &s->mat.materials[b];
      t->delta_c[a * nm + b] = c - 0.5 * (ma->micromodulus + mb->micromodulus);
      ma->c_stable = fmax(ma->c_stable, c);
      mb->c_stable = fmax(mb->c_stable, c);
    }
}

double peri_pmb_bond_micromodulus(const peri_sim *s, int a, int b) {
  const double mean = 0.5 * (s->mat.materials[a].micromodulus + s->mat.materials[b].micromodulus);
  const struct peri_interface_moduli *t = s->mat.interface_moduli;
  return t ? mean + t->delta_c[a * s->mat.n_materials + b] : mean;
}

/* Node i's sum over its intact bonds to the other material of a pair with a modulus:
 * the force density (f) or the energy density (W), with the bond loops' stretch (thermal
 * stretch subtracted), influence and partial volume. */
static void node_difference(const peri_sim *s, int32_t i, double f[3], double *W) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const struct peri_interface_moduli *t = s->mat.interface_moduli;
  const int nm = s->mat.n_materials;
  const double *row = t->delta_c + p->material[i] * nm;
  const double *eth = s->state.thermal_strain;
  for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
    const int32_t j = b->neighbor[k];
    const double dc = row[p->material[j]];
    if (dc == 0.0 || b->broken[k]) continue;
    double dy[3];
    const double r = peri_deformed_bond(p->x, p->u, i, j, dy);
    if (!(r > 0.0)) continue; /* the bond loops skip it too */
    const double r0 = peri_bond_length(p->x, i, j);
    const double stretch = (r - r0) / r0 - peri_bond_thermal_stretch(eth, i, j);
    const double weight = dc * peri_bonds_omega(b, r0) * peri_bonds_beta(b, r0) * p->volume[j];
    if (f) {
      const double g = weight * stretch / r;
      for (int d = 0; d < 3; ++d) f[d] += g * dy[d];
    }
    if (W) *W += 0.25 * weight * stretch * stretch * r0; /* w = c omega s^2 |xi| / 2, half to each end */
  }
}

void peri_interface_moduli_force(peri_sim *s) {
  const struct peri_interface_moduli *t = s->mat.interface_moduli;
  if (!t) return;
  peri_particles *p = &s->disc.p;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (!t->has_pair[p->material[i]]) continue;
    node_difference(s, i, &p->f[3 * i], NULL);
  }
}

void peri_interface_moduli_energy(const peri_sim *s, double *W) {
  const struct peri_interface_moduli *t = s->mat.interface_moduli;
  if (!t) return;
  const peri_particles *p = &s->disc.p;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (!t->has_pair[p->material[i]]) continue;
    node_difference(s, i, NULL, &W[i]);
  }
}

void peri_interface_moduli_free(peri_sim *s) {
  struct peri_interface_moduli *t = s->mat.interface_moduli;
  if (!t) return;
  free(t->E);
  free(t->delta_c);
  free(t->has_pair);
  free(t);
  s->mat.interface_moduli = NULL;
}
