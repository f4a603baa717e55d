/* discretization.horizon as a field of x, y, z and discretization.partial_stress
 * (docs/deck.md section 6, docs/variable_horizon.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/discretize.h"
#include "peri/error.h"
#include "peri/horizon_field.h"
#include "peri/variable_horizon.h"
#include "setup_parts.h"

bool peri_setup_horizon_is_field(const peri_node *d) {
  const peri_node *h = peri_deck_get(d, "horizon");
  if (!h || !h->scalar) return false;
  char *end = NULL;
  strtod(h->scalar, &end);
  while (end && *end == ' ') ++end;
  return !(end && *end == '\0' && end != h->scalar);
}

/* A graded grid with m = horizon / spacing: delta_i = m dx_i, dx_i the node's own spacing. */
static int horizon_from_spacing(peri_sim *s, const peri_node *d) {
  double m = NAN;
  int rc = peri_deck_double(d, "m", true, &m);
  if (rc != PERI_OK) return rc;
  if (!(m > 0.0) || !isfinite(m)) return peri_deck_error(peri_deck_get(d, "m"), "key 'm': must be positive");
  const peri_particles *p = &s->disc.p;
  const peri_geometry *g = &s->disc.geom;
  double *delta = peri_malloc(sizeof(double) * (size_t)(p->n > 0 ? p->n : 1));
  for (int32_t i = 0; i < p->n; ++i)
    delta[i] = m * peri_grid_node_spacing(p->volume[i], g->dim, g->thickness, g->cross_section);
  peri_horizon_field *h = peri_horizon_field_from_values(p->n, delta);
  free(delta);
  s->disc.horizon_field = h;
  s->disc.geom.horizon = h->max;
  s->disc.family.horizon = h->max;
  s->disc.family.node_horizon = h->delta;
  return PERI_OK;
}

int peri_setup_horizon_field(peri_sim *s, const peri_node *d) {
  if (!peri_setup_horizon_is_field(d)) return horizon_from_spacing(s, d);
  peri_expr *e = NULL;
  int rc = peri_deck_expr(d, "horizon", true, &e);
  if (rc != PERI_OK) return rc;
  int32_t bad = -1;
  peri_horizon_field *h = peri_horizon_field_evaluate(&s->disc.p, e, &bad);
  peri_expr_free(e);
  if (!h) {
    const double *x = s->disc.p.x + 3 * (size_t)bad;
    char where[128];
    if (s->disc.geom.dim == 1) snprintf(where, sizeof where, "(%g)", x[0]);
    else if (s->disc.geom.dim == 2) snprintf(where, sizeof where, "(%g, %g)", x[0], x[1]);
    else snprintf(where, sizeof where, "(%g, %g, %g)", x[0], x[1], x[2]);
    peri_expr *again = NULL;
    peri_deck_expr(d, "horizon", true, &again);
    const double value = peri_expr_eval(again, x[0], x[1], x[2], 0.0);
    peri_expr_free(again);
    return peri_deck_error(peri_deck_get(d, "horizon"), "key 'horizon': the horizon is %g at the node at %s; it "
                           "must be positive and finite at every node (or 0 where the node is local)", value, where);
  }
  /* a horizon of 0: a local node, whose gradient stencil reaches local_stencil (default 2 dx: two
   * neighbours a side in 1D, more than the quadratic fit of the zero-energy mode control needs) */
  double radius = 2.0 * s->disc.geom.spacing;
  rc = peri_deck_double(d, "local_stencil", false, &radius);
  if (rc == PERI_OK && (!(radius >= s->disc.geom.spacing) || !isfinite(radius)))
    rc = peri_deck_error(peri_deck_get(d, "local_stencil"), "key 'local_stencil': must be a length of at least the "
                         "spacing %g (the local nodes' gradient needs neighbours)", s->disc.geom.spacing);
  if (rc != PERI_OK) {
    peri_horizon_field_free(h);
    return rc;
  }
  peri_horizon_field_mark_local(h, radius);
  s->disc.horizon_field = h;
  s->disc.geom.horizon = h->max;
  s->disc.family.horizon = h->max;
  s->disc.family.node_horizon = h->delta;
  return PERI_OK;
}

int peri_setup_horizon_coupling(peri_sim *s, const peri_node *root, const bool *s0_from_energy) {
  peri_horizon_field *h = s->disc.horizon_field;
  const peri_node *d = peri_deck_get(root, "discretization");
  const peri_node *at = peri_deck_get(d, "horizon") ? peri_deck_get(d, "horizon") : peri_deck_get(d, "m");
  /* what the per-node models do not cover */
  if (s->disc.surface_correction != PERI_SURFACE_NONE)
    return peri_deck_error(peri_deck_get(d, "surface_correction"),
                           "key 'surface_correction': not with a horizon that varies (the per-node constants of "
                           "docs/variable_horizon.md are calibrated on each node's own family)");
  if (peri_deck_get(root, "thermal"))
    return peri_deck_error(peri_deck_get(root, "thermal"), "key 'thermal': not with a horizon that varies");
  for (int m = 0; m < s->mat.n_materials; ++m) {
    const peri_material *mat = &s->mat.materials[m];
    if (mat->micromodulus_given || mat->lammps_s0)
      return peri_deck_error(at, "key 'horizon': material '%s' gives a %s, which holds for one horizon; give its "
                             "elastic moduli and a critical stretch or fracture energy instead", mat->name,
                             mat->micromodulus_given ? "micromodulus" : "{s00, alpha} critical stretch");
  }
  const peri_model_ops *model = peri_variable_horizon_model(s->mat.model);
  if (!model) return peri_deck_error(at, "key 'horizon': the %s model has no form with a horizon that varies", s->mat.model->name);
  s->mat.model = model;

  /* the coupling region: auto (default), none, or a region's nodes */
  const peri_node *ps = peri_deck_get(d, "partial_stress");
  const char *choice = "auto";
  if (ps) {
    int rc = peri_deck_string(d, "partial_stress", true, &choice);
    if (rc != PERI_OK) return rc;
  }
  if (!strcmp(choice, "auto")) {
    peri_horizon_field_mark_transition(h, &s->disc.bonds, s->disc.p.volume);
  } else if (!strcmp(choice, "none")) {
    if (h->n_local > 0)
      return peri_deck_error(ps, "key 'partial_stress': none leaves the local nodes (horizon 0) without a force; "
                             "use auto or a region");
    h->n_coupled = 0;
  } else {
    int r = peri_setup_find_region(s, peri_deck_get(root, "regions"), ps, choice);
    if (r < 0) return -r;
    const peri_region *region = &s->cond.regions[r];
    for (int32_t k = 0; k < region->count; ++k) h->coupled[region->nodes[k]] = 1;
    h->n_coupled = region->count;
  }
  peri_horizon_field_couple_local(h, &s->disc.bonds); /* whatever the choice */
  h->stabilization = s->disc.geom.dim > 1 ? PERI_PARTIAL_STRESS_STABILIZATION_2D3D : PERI_PARTIAL_STRESS_STABILIZATION;
  int rc = peri_deck_double(d, "partial_stress_stabilization", false, &h->stabilization);
  if (rc != PERI_OK) return rc;
  if (!(h->stabilization >= 0.0) || !isfinite(h->stabilization))
    return peri_deck_error(peri_deck_get(d, "partial_stress_stabilization"),
                           "key 'partial_stress_stabilization': must be a number >= 0");
  if (h->n_coupled > 0 && s->disc.geom.dim > 1)
    peri_warning("partial stress in %dD: explicit runs are stable where the coupling region lies inside the body; "
                 "where it meets a free surface they may still grow (docs/variable_horizon.md, \"Limits\"); "
                 "discretization.partial_stress: none gives full peridynamics",
                 s->disc.geom.dim);
  /* the critical stretch of a failure given as an energy scales as delta^-1/2 (docs/model_reference.md
   * 7.1); the pair table is resolved at the largest horizon */
  h->s0_scale = peri_malloc(sizeof(double) * (size_t)(s->disc.p.n > 0 ? s->disc.p.n : 1));
  for (int32_t i = 0; i < s->disc.p.n; ++i)
    h->s0_scale[i] = s0_from_energy[s->disc.p.material[i]] ? sqrt(h->max / h->delta[i]) : 1.0;
  return PERI_OK;
}

int peri_setup_horizon_solver(const peri_sim *s, const peri_node *root) {
  const peri_horizon_field *h = s->disc.horizon_field;
  if (!h) return PERI_OK;
  const peri_node *d = peri_deck_get(root, "discretization");
  const peri_node *at = peri_deck_get(d, "horizon") ? peri_deck_get(d, "horizon") : peri_deck_get(d, "m");
  const peri_node *ps = peri_deck_get(d, "partial_stress");
  /* on MPI ranks: full peridynamics (each node computes the other end's state of its bonds);
   * the partial stress scatters its reactions to stencil nodes of other ranks */
  if (peri_comm_size() > 1 && (h->n_local > 0 || h->n_coupled > 0))
    return peri_deck_error(ps && h->n_coupled > 0 ? ps : at,
                           "key 'horizon': on MPI ranks (%d here) a horizon that varies runs as full peridynamics "
                           "(discretization.partial_stress: none); this deck has %s: run it in one process",
                           peri_comm_size(), h->n_local > 0 ? "local nodes (horizon 0)" : "a coupling region (the partial stress)");
  if (s->solver.kind == PERI_SOLVER_IMPLICIT)
    return peri_deck_error(at, "key 'horizon': the implicit solver needs a tangent stiffness, which the models with a "
                           "horizon that varies do not have; use adr, dynamic_relaxation or nlcg");
  if (h->n_local > 0 && s->solver.kind == PERI_SOLVER_NLCG)
    return peri_deck_error(at, "key 'horizon': local nodes (horizon 0) run with solver.type explicit, adr or "
                           "dynamic_relaxation: their coupling to the peridynamic nodes (the partial stress) is not "
                           "the gradient of an energy, so nlcg cannot minimise it");
  if (h->n_coupled > 0 && s->solver.kind == PERI_SOLVER_NLCG)
    return peri_deck_error(ps ? ps : at, "the partial-stress force is not the gradient of an energy, so nlcg cannot "
                           "minimise it: use solver.type adr, dynamic_relaxation or explicit, or set "
                           "discretization.partial_stress: none (full peridynamics everywhere)");
  return PERI_OK;
}

int peri_setup_horizon_precracks(const peri_sim *s, const peri_node *root) {
  const peri_horizon_field *h = s->disc.horizon_field;
  if (!h || !h->local) return PERI_OK;
  const peri_bonds *b = &s->disc.bonds;
  const peri_particles *p = &s->disc.p;
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (!h->coupled[i]) continue;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k)
      if (b->broken[k]) {
        const double *x = p->x + 3 * (size_t)i;
        return peri_deck_error(peri_deck_get(root, "precracks"), "key 'precracks': a crack cuts a bond of the node "
                               "at (%g, %g, %g), which is in the coupling region of the local nodes (horizon 0); "
                               "cracks may only run where the force is full peridynamics", x[0], x[1], x[2]);
      }
  }
  return PERI_OK;
}
