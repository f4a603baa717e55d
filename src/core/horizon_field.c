/* A horizon per node: the field from its expression, the default coupling region and the
 * reverse of every bond (include/peri/horizon_field.h). */
#include <math.h>
#include <stdlib.h>
#include "peri/error.h"
#include "peri/horizon_field.h"

static peri_horizon_field *field_alloc(int32_t n) {
  peri_horizon_field *h = peri_calloc(1, sizeof *h);
  h->n = n;
  h->delta = peri_malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  h->coupled = peri_calloc((size_t)(n > 0 ? n : 1), 1);
  h->min = INFINITY, h->max = 0.0;
  return h;
}

peri_horizon_field *peri_horizon_field_from_values(int32_t n, const double *delta) {
  peri_horizon_field *h = field_alloc(n);
  for (int32_t i = 0; i < n; ++i) {
    h->delta[i] = delta[i];
    h->min = fmin(h->min, delta[i]);
    h->max = fmax(h->max, delta[i]);
  }
  return h;
}

peri_horizon_field *peri_horizon_field_evaluate(const peri_particles *p, peri_expr *horizon, int32_t *bad) {
  *bad = -1;
  peri_horizon_field *h = field_alloc(p->n);
  /* serial: an expression binds its variables by address (include/peri/expr.h) */
  for (int32_t i = 0; i < p->n; ++i) {
    const double *x = p->x + 3 * (size_t)i;
    const double d = peri_expr_eval(horizon, x[0], x[1], x[2], 0.0);
    if (!(d >= 0.0) || !isfinite(d)) {
      *bad = i;
      peri_horizon_field_free(h);
      return NULL;
    }
    h->delta[i] = d;
    h->min = fmin(h->min, d);
    h->max = fmax(h->max, d);
  }
  return h;
}

static bool relative_difference(double a, double b) { return fabs(a - b) > 1e-12 * fabs(a); }

void peri_horizon_field_mark_transition(peri_horizon_field *h, const peri_bonds *b, const double *volume) {
  int32_t graded = 0;
#pragma omp parallel for schedule(static) reduction(+ : graded)
  for (int32_t i = 0; i < b->n_nodes; ++i) {
    uint8_t differs = 0, volumes = 0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1] && !differs; ++k) {
      volumes = volumes || relative_difference(volume[b->neighbor[k]], volume[i]);
      differs = volumes || relative_difference(h->delta[b->neighbor[k]], h->delta[i]);
    }
    h->coupled[i] = differs;
    graded += volumes;
  }
  /* Where the volumes change, a node's constants (calibrated on its own family) differ from
   * those of a uniform grid, so a full-PD neighbour reading its force state would see ghost
   * forces: the region takes one more family layer. */
  if (graded > 0) {
    uint8_t *seed = peri_malloc((size_t)(b->n_nodes > 0 ? b->n_nodes : 1));
    for (int32_t i = 0; i < b->n_nodes; ++i) seed[i] = h->coupled[i];
#pragma omp parallel for schedule(static)
    for (int32_t i = 0; i < b->n_nodes; ++i)
      for (int64_t k = b->offset[i]; k < b->offset[i + 1] && !h->coupled[i]; ++k) h->coupled[i] = seed[b->neighbor[k]];
    free(seed);
  }
  int32_t count = 0;
  for (int32_t i = 0; i < b->n_nodes; ++i) count += h->coupled[i];
  h->n_coupled = count;
}

void peri_horizon_field_mark_local(peri_horizon_field *h, double radius) {
  int32_t count = 0;
  for (int32_t i = 0; i < h->n; ++i) count += h->delta[i] == 0.0;
  h->n_local = count;
  h->local_radius = radius;
  if (count == 0) return;
  h->local = peri_calloc((size_t)h->n, 1);
  h->min = INFINITY, h->max = 0.0;
  for (int32_t i = 0; i < h->n; ++i) {
    if (h->delta[i] == 0.0) h->local[i] = 1, h->delta[i] = radius;
    h->min = fmin(h->min, h->delta[i]);
    h->max = fmax(h->max, h->delta[i]);
  }
}

void peri_horizon_field_couple_local(peri_horizon_field *h, const peri_bonds *b) {
  if (!h->local) return;
  for (int32_t i = 0; i < b->n_nodes; ++i) {
    uint8_t reads_local = h->local[i];
    for (int64_t k = b->offset[i]; k < b->offset[i + 1] && !reads_local; ++k) reads_local = h->local[b->neighbor[k]];
    h->coupled[i] = h->coupled[i] || reads_local;
  }
  int32_t count = 0;
  for (int32_t i = 0; i < b->n_nodes; ++i) count += h->coupled[i];
  h->n_coupled = count;
}

void peri_horizon_field_reverse_bonds(peri_horizon_field *h, const peri_bonds *b) {
  free(h->reverse);
  h->reverse = peri_malloc(sizeof(int64_t) * (size_t)(b->n_bonds > 0 ? b->n_bonds : 1));
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < b->n_nodes; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) h->reverse[k] = peri_bonds_find(b, b->neighbor[k], i);
}

void peri_horizon_field_free(peri_horizon_field *h) {
  if (!h) return;
  free(h->delta);
  free(h->s0_scale);
  free(h->coupled);
  free(h->node_constant);
  free(h->theta);
  free(h->pstate);
  free(h->state);
  free(h->reverse);
  free(h->bond_length);
  free(h->bond_pair_state);
  free(h->bond_pair);
  free(h->bond_critical);
  free(h->partial_stress);
  free(h->stencil_offset);
  free(h->stencil_node);
  free(h->stencil_weight);
  free(h->stencil_bond);
  free(h->stencil_fit);
  free(h->stiffness);
  free(h->entry_reaction);
  free(h->target_offset);
  free(h->target_entry);
  free(h->lattice_index);
  free(h->lattice_correction);
  free(h->needs_stress);
  free(h->local);
  free(h->variational);
  free(h);
}
