/* Global quantities for the history: energies and reactions. Per-node values are summed in
 * fixed-order blocks of the global node order (peri_sum_owned), so that the totals do not
 * depend on the thread count or on the number of MPI ranks. */
#include <math.h>
#include <stdlib.h>
#include "peri/coupling.h"
#include "peri/decompose.h"
#include "peri/error.h"

static double *node_terms(const peri_sim *s, int ncomp) {
  return peri_calloc((size_t)(s->disc.p.n_owned > 0 ? s->disc.p.n_owned : 1) * (size_t)ncomp, sizeof(double));
}

double peri_kinetic_energy(const peri_sim *s) {
  const peri_particles *p = &s->disc.p;
  double *terms = node_terms(s, 1), sum = 0.0;
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (p->flags[i] & PERI_NODE_FICTITIOUS) continue; /* out of the history (docs/deck.md section 10) */
    const double *v = &p->v[3 * i];
    double rho = s->mat.materials[p->material[i]].density;
    terms[i] = 0.5 * rho * p->volume[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  peri_sum_owned(s, terms, 1, &sum);
  free(terms);
  return sum;
}

double peri_total_mass(const peri_sim *s) {
  const peri_particles *p = &s->disc.p;
  double *terms = node_terms(s, 1), sum = 0.0;
  for (int32_t i = 0; i < p->n_owned; ++i) terms[i] = s->mat.materials[p->material[i]].density * p->volume[i];
  peri_sum_owned(s, terms, 1, &sum);
  free(terms);
  return sum;
}

void peri_linear_momentum(const peri_sim *s, double out[3]) {
  const peri_particles *p = &s->disc.p;
  double *terms = node_terms(s, 3);
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double m = s->mat.materials[p->material[i]].density * p->volume[i];
    for (int d = 0; d < 3; ++d) terms[3 * i + d] = m * p->v[3 * i + d];
  }
  peri_sum_owned(s, terms, 3, out);
  free(terms);
}

double peri_strain_energy(peri_sim *s) {
  peri_particles *p = &s->disc.p;
  if (!p->energy) p->energy = peri_calloc(p->n, sizeof(double));
  if (s->coupling) { /* PD-FEM coupling: the work of the nodal forces, 1/2 u . K u (docs/coupling.md) */
    for (int32_t i = 0; i < p->n_owned; ++i) {
      const double *u = &p->u[3 * (size_t)i], *f = &p->f[3 * (size_t)i];
      p->energy[i] = -0.5 * (u[0] * f[0] + u[1] * f[1] + u[2] * f[2]);
    }
  } else {
    s->mat.model->energy(s, p->energy);
  }
  double *terms = node_terms(s, 1), sum = 0.0;
  for (int32_t i = 0; i < p->n_owned; ++i) terms[i] = p->energy[i] * p->volume[i];
  peri_sum_owned(s, terms, 1, &sum);
  free(terms);
  return sum;
}

void peri_region_reaction(const peri_sim *s, int region, double out[3]) {
  const peri_particles *p = &s->disc.p;
  const peri_region *r = &s->cond.regions[region];
  double *terms = node_terms(s, 3); /* zero outside the region */
  for (int32_t a = 0; a < r->count; ++a) {
    int32_t i = r->nodes[a];
    for (int d = 0; d < 3; ++d) terms[3 * i + d] = -p->f[3 * i + d] * p->volume[i];
  }
  peri_sum_owned(s, terms, 3, out);
  free(terms);
}

void peri_coupling_region_balance(const peri_sim *s, double ratio[3]) {
  const peri_coupling *c = s->coupling;
  double sum[3] = {0, 0, 0}, magnitude[3] = {0, 0, 0};
  for (int k = 0; k < c->n_balance_regions; ++k) { /* each reaction is already summed over the ranks */
    double R[3];
    peri_region_reaction(s, c->balance_region[k], R);
    for (int d = 0; d < 3; ++d) sum[d] += R[d], magnitude[d] += fabs(R[d]);
  }
  for (int d = 0; d < 3; ++d) ratio[d] = magnitude[d] > 0.0 ? fabs(sum[d]) / magnitude[d] : 0.0;
}
