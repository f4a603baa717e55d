/* The external work of a quasi-static run (the history column external_work, so that
 * energy_balance = kinetic + strain - external means something there too).
 *
 * Between two accepted equilibrium states the work done on the body is
 *   W += sum_i sum_d 1/2 (F_old + F_new)_id (u_new - u_old)_id        (trapezoid rule)
 * with F the external force on a node: the load b V on a free component, and on a
 * prescribed component the reaction -f V of the support (which balances the internal force
 * there). For a linear elastic body loaded quasi-statically the force is linear in u along
 * the path, so the trapezoid is exact and W equals the strain energy U (Clapeyron); with
 * fracture W - U is the energy the broken bonds took. The terms are summed per node in
 * the fixed-order blocks of peri_sum_owned: the same on any number of threads and ranks. */
#include <stdlib.h>
#include <string.h>
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/quasistatic.h"

/* External force on every owned component at the current state, into load[3n]. */
static void external_force(const peri_sim *s, double *load) {
  const peri_particles *p = &s->disc.p;
  for (int32_t i = 0; i < p->n_owned; ++i)
    for (int d = 0; d < 3; ++d) {
      const size_t c = 3 * (size_t)i + d;
      load[c] = (s->cond.prescribed[c] ? -p->f[c] : p->b[c]) * p->volume[i];
    }
}

void peri_qs_work_begin(peri_qs_work *w, const peri_sim *s) {
  const size_t n3 = 3 * (size_t)s->disc.p.n_owned;
  w->u_old = peri_malloc(sizeof(double) * (n3 ? n3 : 1));
  w->load_old = peri_malloc(sizeof(double) * (n3 ? n3 : 1));
  memcpy(w->u_old, s->disc.p.u, sizeof(double) * n3);
  external_force(s, w->load_old);
}

void peri_qs_work_step(peri_qs_work *w, peri_sim *s) {
  const peri_particles *p = &s->disc.p;
  const int32_t n = p->n_owned;
  const size_t n3 = 3 * (size_t)n;
  double *load = peri_malloc(sizeof(double) * (n3 ? n3 : 1));
  double *terms = peri_malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  external_force(s, load);
  for (int32_t i = 0; i < n; ++i) {
    double sum = 0.0;
    for (int d = 0; d < 3; ++d) {
      const size_t c = 3 * (size_t)i + d;
      sum += 0.5 * (w->load_old[c] + load[c]) * (p->u[c] - w->u_old[c]);
    }
    terms[i] = sum;
  }
  double work;
  peri_sum_owned(s, terms, 1, &work); /* fixed-order blocks of the global node order */
  s->state.external_work += work;
  memcpy(w->u_old, p->u, sizeof(double) * n3);
  memcpy(w->load_old, load, sizeof(double) * n3);
  free(load);
  free(terms);
}

void peri_qs_work_free(peri_qs_work *w) {
  free(w->u_old);
  free(w->load_old);
  w->u_old = w->load_old = NULL;
}
