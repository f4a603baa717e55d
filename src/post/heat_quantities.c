/* Derived quantities of heat conduction (docs/heat.md): the total heat, the heat flowing into
 * a region, the peridynamic heat flux field, and the history columns of thermomechanics. */
#include <math.h>
#include <stdlib.h>
#include "peri/comm.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/sim.h"
#include "peri/thermal.h"

/* Ghost temperatures from their owners before a pass reads T of neighbours (MPI ranks,
 * docs/parallel.md; a no-op in one process). */
/* The extent of the missing dimensions (thickness in 2D, cross-section in 1D): node areas times it are volumes. */
static double gfac_of(const peri_sim *s) {
  if (s->disc.geom.dim == 2) return s->disc.geom.thickness;
  if (s->disc.geom.dim == 1) return s->disc.geom.cross_section;
  return 1.0;
}

static void exchange(const peri_sim *s, double *T) { peri_sim_exchange((peri_sim *)s, T, 1); }

double peri_thermal_total_heat(const peri_sim *s) {
  const peri_thermal *th = s->thermal;
  double *terms = peri_malloc(sizeof(double) * (size_t)(th->n > 0 ? th->n : 1)), sum = 0.0;
  for (int32_t i = 0; i < th->n; ++i) terms[i] = th->rhoc[i] * th->T[i] * th->area[i];
  peri_sum_owned(s, terms, 1, &sum); /* fixed-order blocks: independent of threads and ranks */
  free(terms);
  return sum * gfac_of(s);
}

double peri_thermal_region_inflow(const peri_sim *s, int region) {
  const peri_thermal *th = s->thermal;
  const peri_bonds *b = &s->disc.bonds;
  const peri_region *r = &s->cond.regions[region];
  const int32_t n_all = s->disc.p.n; /* owned and ghosts: membership of ghosts from their owners */
  double *in = peri_calloc((size_t)(n_all > 0 ? n_all : 1), sizeof(double));
  double *terms = peri_calloc((size_t)(th->n > 0 ? th->n : 1), sizeof(double));
  for (int32_t a = 0; a < r->count; ++a) in[r->nodes[a]] = 1.0;
  exchange(s, in);
  exchange(s, th->T);
  double sum = 0.0;
  for (int32_t a = 0; a < r->count; ++a) {
    const int32_t i = r->nodes[a];
    double si = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      if (in[j] != 0.0) continue;
      const double w = th->cut[k] ? th->crack_conductance * th->H[k] : th->H[k];
      si += w * (th->T[j] - th->T[i]);
    }
    terms[i] = si * th->area[i];
  }
  peri_sum_owned(s, terms, 1, &sum);
  free(terms);
  free(in);
  return sum * gfac_of(s);
}

void peri_thermal_flux(const peri_sim *s) {
  const peri_thermal *th = s->thermal;
  const peri_bonds *b = &s->disc.bonds;
  const double *x = s->disc.p.x;
  exchange(s, th->T);
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < th->n; ++i) {
    double q[3] = {0.0, 0.0, 0.0};
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      const double dT = th->T[j] - th->T[i];
      if (!(dT > 0.0)) continue;
      const double w = (th->cut[k] ? th->crack_conductance : 1.0) * (th->H[k] - th->Hs[k]) * dT;
      for (int d = 0; d < 3; ++d) q[d] += w * (x[3 * j + d] - x[3 * i + d]);
    }
    for (int d = 0; d < 3; ++d) th->flux[3 * i + d] = q[d];
  }
}

int peri_thermal_history_count(const peri_sim *s) { return s->thermal ? 3 : 0; }

void peri_thermal_history_names(const peri_sim *s, char **names) {
  if (!s->thermal) return;
  names[0] = peri_strdup("total_heat");
  names[1] = peri_strdup("min_temperature");
  names[2] = peri_strdup("max_temperature");
}

void peri_thermal_history_values(const peri_sim *s, double *values) {
  const peri_thermal *th = s->thermal;
  if (!th) return;
  double lo = INFINITY, hi = -INFINITY;
  for (int32_t i = 0; i < th->n; ++i) {
    if (th->T[i] < lo) lo = th->T[i];
    if (th->T[i] > hi) hi = th->T[i];
  }
  values[0] = peri_thermal_total_heat(s);
  values[1] = peri_comm_min(lo); /* over all ranks */
  values[2] = peri_comm_max(hi);
}
