/* Global quantities for the history: energies and reactions. Sums run in node order over
 * per-node values so that they do not depend on the thread count. */
#include <math.h>
#include "peri/error.h"
#include "peri/solver.h"

double peri_kinetic_energy(const peri_sim *s) {
  const peri_particles *p = &s->p;
  double sum = 0.0;
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const double *v = &p->v[3 * i];
    double rho = s->materials[p->material[i]].density;
    sum += 0.5 * rho * p->volume[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  return sum;
}

void peri_linear_momentum(const peri_sim *s, double out[3]) {
  const peri_particles *p = &s->p;
  out[0] = out[1] = out[2] = 0.0;
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double m = s->materials[p->material[i]].density * p->volume[i];
    for (int d = 0; d < 3; ++d) out[d] += m * p->v[3 * i + d];
  }
}

double peri_strain_energy(peri_sim *s) {
  peri_particles *p = &s->p;
  if (!p->energy) p->energy = peri_calloc(p->n, sizeof(double));
  s->model->energy(s, p->energy);
  double sum = 0.0;
  for (int32_t i = 0; i < p->n_owned; ++i) sum += p->energy[i] * p->volume[i];
  return sum;
}

void peri_region_reaction(const peri_sim *s, int region, double out[3]) {
  const peri_particles *p = &s->p;
  const peri_region *r = &s->regions[region];
  out[0] = out[1] = out[2] = 0.0;
  for (int32_t a = 0; a < r->count; ++a) {
    int32_t i = r->nodes[a];
    for (int d = 0; d < 3; ++d) out[d] -= p->f[3 * i + d] * p->volume[i];
  }
}
