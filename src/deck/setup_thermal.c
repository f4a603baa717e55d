/* Deck parsing of heat conduction and thermomechanics: thermal material keys, the
 * `thermal` section, the thermal boundary conditions and growing cracks. Every input
 * error is reported with its position before any work (docs/heat.md, docs/deck.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/conduction.h"
#include "peri/damage.h"
#include "peri/error.h"
#include "peri/heat.h"
#include "peri/thermal.h"
#include "setup_parts.h"

#define TRY(expr)                   \
  do {                              \
    int rc_ = (expr);               \
    if (rc_ != PERI_OK) return rc_; \
  } while (0)

static const char *const thermal_bc_types[] = {"temperature", "heat_flux", "convection", "heat_source",
                                               "initial_temperature", NULL};

bool peri_setup_heat_only(const peri_node *root) {
  const peri_node *solver = peri_deck_get(root, "solver");
  const peri_node *type = solver && solver->kind == PERI_NODE_MAPPING ? peri_deck_get(solver, "type") : NULL;
  return type && type->scalar && strcmp(type->scalar, "heat") == 0;
}

bool peri_setup_is_thermal_bc(const peri_node *item) {
  if (!item || item->kind != PERI_NODE_MAPPING) return false;
  const peri_node *type = peri_deck_get(item, "type");
  if (!type || !type->scalar) return false;
  for (int k = 0; thermal_bc_types[k]; ++k)
    if (!strcmp(type->scalar, thermal_bc_types[k])) return true;
  return false;
}

static int positive_key(const peri_node *map, const char *key, bool required, double *out) {
  TRY(peri_deck_double(map, key, required, out));
  if (peri_deck_get(map, key) && !(*out > 0.0))
    return peri_deck_error(peri_deck_get(map, key), "key '%s': must be positive", key);
  return PERI_OK;
}

int peri_setup_material_thermal_keys(const peri_node *map, peri_material *mat) {
  mat->conductivity = NAN;
  mat->specific_heat = NAN;
  mat->thermal_expansion = 0.0;
  TRY(positive_key(map, "conductivity", false, &mat->conductivity));
  TRY(positive_key(map, "specific_heat", false, &mat->specific_heat));
  TRY(peri_deck_double(map, "thermal_expansion", false, &mat->thermal_expansion));
  return PERI_OK;
}

int peri_setup_heat_material(peri_sim *s, const peri_node *key, const peri_node *map, int index) {
  peri_material *mat = &s->mat.materials[index];
  char section[160];
  snprintf(section, sizeof section, "materials.%s", key->scalar);
  static const char *const keys[] = {"density", "conductivity", "specific_heat", NULL};
  if (peri_deck_allow(map, section, keys) != PERI_OK) {
    fprintf(stderr, "  (with solver type heat a material has only density, conductivity and specific_heat)\n");
    return PERI_ERR_INPUT;
  }
  mat->name = peri_strdup(key->scalar);
  TRY(positive_key(map, "density", true, &mat->density));
  TRY(positive_key(map, "conductivity", true, &mat->conductivity));
  TRY(positive_key(map, "specific_heat", true, &mat->specific_heat));
  mat->thermal_expansion = 0.0;
  mat->critical_stretch = INFINITY;
  s->mat.model = &peri_model_heat_only;
  return PERI_OK;
}

/* ---------------------------------------------------------------- conditions */

static int parse_thermal_bc(peri_sim *s, const peri_node *regions, const peri_node *it,
                            peri_thermal_bc *bc) {
  int kind = 0;
  TRY(peri_deck_choice(it, "type", true, thermal_bc_types, &kind));
  static const char *const k_value[] = {"type", "region", "value", NULL};
  static const char *const k_flux[] = {"type", "region", "value", "layer", NULL};
  static const char *const k_conv[] = {"type", "region", "coefficient", "ambient", "layer", NULL};
  const char *const *allowed = kind == 1 ? k_flux : kind == 2 ? k_conv : k_value;
  TRY(peri_deck_allow(it, "boundary_conditions", allowed));
  static const peri_thermal_bc_kind kinds[] = {PERI_TBC_TEMPERATURE, PERI_TBC_HEAT_FLUX, PERI_TBC_CONVECTION,
                                               PERI_TBC_HEAT_SOURCE, PERI_TBC_INITIAL};
  bc->kind = kinds[kind];
  const char *rname = NULL;
  if (!peri_deck_get(it, "region")) /* the whole body only when the deck says so (docs/deck.md) */
    return peri_deck_error(it, "boundary condition '%s' has no 'region': name one, or write 'region: all' to "
                               "apply it to the whole body", thermal_bc_types[kind]);
  TRY(peri_deck_string(it, "region", true, &rname));
  int r = peri_setup_find_region(s, regions, peri_deck_get(it, "region"), rname);
  if (r < 0) return -r;
  bc->region = r;
  bc->layer = s->disc.geom.spacing;
  bc->normal_axis = -1;
  if (bc->kind == PERI_TBC_CONVECTION) {
    TRY(peri_deck_expr(it, "coefficient", true, &bc->value));
    TRY(peri_deck_expr(it, "ambient", true, &bc->ambient));
  } else {
    TRY(peri_deck_expr(it, "value", true, &bc->value));
  }
  if (peri_deck_get(it, "layer")) TRY(positive_key(it, "layer", true, &bc->layer));
  return PERI_OK;
}

/* ---------------------------------------------------------------- growing cracks */

typedef struct {
  double time;
  int64_t bond;
} timed_bond;

static int cmp_timed(const void *a, const void *b) {
  const timed_bond *x = a, *y = b;
  if (x->time != y->time) return x->time < y->time ? -1 : 1;
  return (x->bond > y->bond) - (x->bond < y->bond);
}

/* Every bond crossing a growing crack's full path, with the time the tip reaches it. */
static void growing_bonds(peri_sim *s) {
  peri_thermal *th = s->thermal;
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  size_t cap = 1024, count = 0;
  timed_bond *list = peri_malloc(cap * sizeof *list);
  for (int c = 0; c < th->n_growing; ++c) {
    const peri_growing_crack *g = &th->growing[c];
    peri_precrack seg = {.dim = 2};
    memcpy(seg.a, g->from, sizeof seg.a);
    memcpy(seg.b, g->to, sizeof seg.b);
    const double ex = g->to[0] - g->from[0], ey = g->to[1] - g->from[1];
    const double len = hypot(ex, ey);
    for (int32_t i = 0; i < p->n_owned; ++i)
      for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
        const int32_t j = b->neighbor[k];
        const int32_t lo = i < j ? i : j, hi = i < j ? j : i;
        const double *A = &p->x[3 * lo], *B = &p->x[3 * hi];
        if (!peri_precrack_cuts(&seg, s->disc.geom.spacing, A, B)) continue;
        /* crossing point A + u (B - A) = from + v (to - from) */
        const double bx = B[0] - A[0], by = B[1] - A[1];
        const double den = ex * by - ey * bx;
        double v = den != 0.0 ? ((A[0] - g->from[0]) * by - (A[1] - g->from[1]) * bx) / den : 0.0;
        if (v < 0.0) v = 0.0;
        if (v > 1.0) v = 1.0;
        if (count == cap) list = peri_realloc(list, (cap *= 2) * sizeof *list);
        list[count].time = g->start + v * len / g->speed;
        list[count].bond = k;
        count++;
      }
  }
  qsort(list, count, sizeof *list, cmp_timed);
  th->n_growing_bonds = (int64_t)count;
  th->growing_bond = peri_malloc(sizeof(int64_t) * (count ? count : 1));
  th->growing_time = peri_malloc(sizeof(double) * (count ? count : 1));
  for (size_t k = 0; k < count; ++k) {
    th->growing_bond[k] = list[k].bond;
    th->growing_time[k] = list[k].time;
  }
  free(list);
}

static int parse_growing(peri_sim *s, const peri_node *list) {
  peri_thermal *th = s->thermal;
  if (list->kind != PERI_NODE_SEQUENCE)
    return peri_deck_error(list, "key 'growing_cracks': expected a list, got %s", peri_deck_kind_name(list));
  if (s->disc.geom.dim != 2) return peri_deck_error(list, "key 'growing_cracks': only for dimension 2");
  th->n_growing = list->count;
  th->growing = peri_calloc((size_t)list->count + 1, sizeof(peri_growing_crack));
  static const char *const keys[] = {"from", "to", "speed", "start_time", NULL};
  for (int k = 0; k < list->count; ++k) {
    const peri_node *it = list->items[k];
    peri_growing_crack *g = &th->growing[k];
    TRY(peri_deck_allow(it, "thermal.growing_cracks", keys));
    TRY(peri_deck_vector(it, "from", true, 2, g->from));
    TRY(peri_deck_vector(it, "to", true, 2, g->to));
    TRY(positive_key(it, "speed", true, &g->speed));
    g->start = 0.0;
    TRY(peri_deck_double(it, "start_time", false, &g->start));
    if (g->from[0] == g->to[0] && g->from[1] == g->to[1])
      return peri_deck_error(it, "thermal.growing_cracks: 'from' and 'to' are the same point");
  }
  return PERI_OK;
}

/* ---------------------------------------------------------------- the section */

static const char *const thermal_keys[] = {
    "kernel", "quadrature", "self_term", "bond_conductivity", "initial_temperature",
    "reference_temperature", "integrator", "time_step", "safety_factor", "insulation", "coupling",
    "crack_conductance", "growing_cracks", NULL};

static bool uses_thermal_fields(const peri_sim *s) {
  for (int k = 0; k < s->out.n_fields; ++k)
    if (!strcmp(s->out.fields[k], "temperature") || !strcmp(s->out.fields[k], "heat_flux")) return true;
  return s->out.picture_field &&
         (!strcmp(s->out.picture_field, "temperature") || !strcmp(s->out.picture_field, "heat_flux"));
}

int peri_setup_thermal(peri_sim *s, const peri_node *root) {
  const bool heat_only = s->solver.kind == PERI_SOLVER_HEAT;
  const peri_node *sec = peri_deck_get(root, "thermal");
  const peri_node *mats = peri_deck_get(root, "materials");
  const peri_node *bcs = peri_deck_get(root, "boundary_conditions");
  if (!heat_only && !sec) {
    /* mechanics only: thermal inputs would be ignored */
    for (int m = 0; m < s->mat.n_materials; ++m) {
      const peri_node *map = peri_deck_get(mats, s->mat.materials[m].name);
      static const char *const tk[] = {"conductivity", "specific_heat", "thermal_expansion", NULL};
      for (int k = 0; tk[k]; ++k)
        if (peri_deck_get(map, tk[k]))
          return peri_deck_error(peri_deck_key_node(map, tk[k]), "key '%s': thermal material keys need a "
                                 "'thermal' section (or solver type heat)", tk[k]);
    }
    for (int k = 0; bcs && bcs->kind == PERI_NODE_SEQUENCE && k < bcs->count; ++k)
      if (peri_setup_is_thermal_bc(bcs->items[k]))
        return peri_deck_error(bcs->items[k], "boundary condition of type '%s' needs a 'thermal' section "
                               "(or solver type heat)", peri_deck_get(bcs->items[k], "type")->scalar);
    if (uses_thermal_fields(s))
      return peri_deck_error(peri_deck_get(root, "output"), "output: temperature and heat_flux need a 'thermal' "
                             "section (or solver type heat)");
    return PERI_OK;
  }
  if (sec && sec->kind != PERI_NODE_MAPPING)
    return peri_deck_error(sec, "key 'thermal': expected a mapping, got %s", peri_deck_kind_name(sec));
  if (sec) TRY(peri_deck_allow(sec, "thermal", thermal_keys));
  if (heat_only) {
    static const char *const not_heat[] = {"interfaces", "indenter", NULL};
    for (int k = 0; not_heat[k]; ++k)
      if (peri_deck_get(root, not_heat[k]))
        return peri_deck_error(peri_deck_key_node(root, not_heat[k]), "key '%s': not used by solver type heat "
                               "(conduction only)", not_heat[k]);
    const peri_node *solver = peri_deck_get(root, "solver");
    static const char *const not_solver[] = {"damping", "breaking", NULL};
    for (int k = 0; not_solver[k]; ++k)
      if (peri_deck_get(solver, not_solver[k]))
        return peri_deck_error(peri_deck_key_node(solver, not_solver[k]), "key '%s': not used by solver type "
                               "heat (conduction only)", not_solver[k]);
    static const char *const coupled_only[] = {"coupling", "time_step", "safety_factor", NULL};
    for (int k = 0; sec && coupled_only[k]; ++k)
      if (peri_deck_get(sec, coupled_only[k]))
        return peri_deck_error(peri_deck_key_node(sec, coupled_only[k]), "key '%s': only with solver type "
                               "explicit (for solver type heat, give time_step and safety_factor under "
                               "solver)", coupled_only[k]);
    for (int k = 0; bcs && bcs->kind == PERI_NODE_SEQUENCE && k < bcs->count; ++k)
      if (!peri_setup_is_thermal_bc(bcs->items[k]))
        return peri_deck_error(bcs->items[k], "boundary condition: solver type heat takes only the thermal "
                               "types (temperature, heat_flux, convection, heat_source, "
                               "initial_temperature)");
    if (!peri_deck_get(solver, "safety_factor")) s->solver.safety_factor = 0.9;
  } else {
    for (int m = 0; m < s->mat.n_materials; ++m) {
      const peri_material *mat = &s->mat.materials[m];
      if (isnan(mat->conductivity) || isnan(mat->specific_heat))
        return peri_deck_error(peri_deck_get(mats, mat->name), "materials.%s: a thermal run needs "
                               "'conductivity' and 'specific_heat'", mat->name);
    }
  }

  peri_thermal *th = peri_calloc(1, sizeof *th);
  s->thermal = th;
  int v = 0;
  static const char *const kernels[] = {"conical", "constant", NULL};
  static const char *const quads[] = {"bonds", "bobaru2012", NULL};
  static const char *const selfs[] = {"none", "cell", "bobaru2012", NULL};
  static const char *const rules[] = {"lower", "harmonic", NULL};
  static const char *const integrators[] = {"rk4", "euler", NULL};
  static const char *const couplings[] = {"two_way", "one_way", NULL};
  static const char *const insulations[] = {"natural", "algebraic", NULL};
  if (sec) {
    TRY(peri_deck_choice(sec, "kernel", false, kernels, &v));
    th->kernel = (peri_thermal_kernel)v;
    v = 0;
    TRY(peri_deck_choice(sec, "quadrature", false, quads, &v));
    th->quadrature = (peri_thermal_quadrature)v;
  }
  const bool bobaru = th->quadrature == PERI_TQUAD_BOBARU2012;
  v = bobaru ? PERI_TSELF_BOBARU2012 : PERI_TSELF_CELL;
  if (sec) TRY(peri_deck_choice(sec, "self_term", false, selfs, &v));
  th->self_term = (peri_thermal_self)v;
  v = bobaru ? PERI_TINSULATION_ALGEBRAIC : PERI_TINSULATION_NATURAL;
  if (sec) TRY(peri_deck_choice(sec, "insulation", false, insulations, &v));
  th->insulation = (peri_thermal_insulation)v;
  v = 0;
  if (sec) TRY(peri_deck_choice(sec, "bond_conductivity", false, rules, &v));
  th->bond_rule = (peri_thermal_bond_rule)v;
  v = 0;
  if (sec) TRY(peri_deck_choice(sec, "integrator", false, integrators, &v));
  th->integrator = (peri_thermal_integrator)v;
  v = 0;
  if (sec) TRY(peri_deck_choice(sec, "coupling", false, couplings, &v));
  th->coupling = (peri_thermal_coupling)v;
  th->safety_factor = 0.9;
  double dt_given = 0.0;
  if (sec) {
    TRY(peri_deck_double(sec, "crack_conductance", false, &th->crack_conductance));
    if (!(th->crack_conductance >= 0.0 && th->crack_conductance <= 1.0))
      return peri_deck_error(peri_deck_get(sec, "crack_conductance"), "key 'crack_conductance': must be in [0, 1]");
    TRY(peri_deck_double(sec, "safety_factor", false, &th->safety_factor));
    if (!(th->safety_factor > 0.0 && th->safety_factor <= 1.0))
      return peri_deck_error(peri_deck_get(sec, "safety_factor"), "key 'safety_factor': must be in (0, 1]");
    if (peri_deck_get(sec, "time_step")) TRY(positive_key(sec, "time_step", true, &dt_given));
  }
  if (bobaru) {
    const peri_node *d = peri_deck_get(root, "discretization");
    const peri_node *pl = peri_deck_get(d, "placement");
    const peri_node *at = peri_deck_get(sec, "quadrature");
    if (peri_deck_get(d, "fill") && !(pl && pl->scalar && !strcmp(pl->scalar, "lattice")))
      return peri_deck_error(at, "quadrature bobaru2012: needs 'placement: lattice' in discretization (a "
                             "vertex-centred grid with nodes on the boundary, Bobaru & Duangpanya 2012 sec. 3)");
    if (s->disc.family.rule != PERI_PV_LINEAR)
      return peri_deck_error(at, "quadrature bobaru2012: needs 'partial_volume: linear' (neighbours out to "
                             "delta + dx/2, Bobaru & Duangpanya 2012 Algorithm 1)");
  }

  /* conditions */
  int n_thermal_bcs = 0;
  for (int k = 0; bcs && bcs->kind == PERI_NODE_SEQUENCE && k < bcs->count; ++k)
    n_thermal_bcs += peri_setup_is_thermal_bc(bcs->items[k]);
  th->bcs = peri_calloc((size_t)n_thermal_bcs + 1, sizeof(peri_thermal_bc));
  for (int k = 0; bcs && bcs->kind == PERI_NODE_SEQUENCE && k < bcs->count; ++k) {
    if (!peri_setup_is_thermal_bc(bcs->items[k])) continue;
    TRY(parse_thermal_bc(s, peri_deck_get(root, "regions"), bcs->items[k], &th->bcs[th->n_bcs++]));
  }
  const peri_node *grow = peri_deck_get(sec, "growing_cracks");
  if (grow) TRY(parse_growing(s, grow));

  /* the operator */
  TRY(peri_thermal_build(s));
  const int32_t n = th->n;
  th->fixed = peri_calloc((size_t)n + 1, 1);
  for (int c = 0; c < th->n_bcs; ++c) {
    if (th->bcs[c].kind != PERI_TBC_TEMPERATURE) continue;
    const peri_region *r = &s->cond.regions[th->bcs[c].region];
    for (int32_t a = 0; a < r->count; ++a) th->fixed[r->nodes[a]] = 1;
  }
  if (th->insulation == PERI_TINSULATION_ALGEBRAIC) {
    th->alg_bc = peri_malloc(sizeof(int32_t) * ((size_t)n + 1));
    for (int32_t i = 0; i < n; ++i) {
      th->alg_bc[i] = -1;
      if (th->alg_axis[i] != 0 && !th->fixed[i]) th->fixed[i] = 2;
    }
    bool warned = false;
    for (int c = 0; c < th->n_bcs; ++c) {
      if (th->bcs[c].kind != PERI_TBC_HEAT_FLUX) continue;
      const peri_region *r = &s->cond.regions[th->bcs[c].region];
      for (int32_t a = 0; a < r->count; ++a) {
        const int32_t i = r->nodes[a];
        if (th->fixed[i] == 2) th->alg_bc[i] = c;
        else if (!th->fixed[i] && !warned) {
          peri_warning("heat_flux on region '%s': with insulation algebraic the flux is imposed on boundary "
                       "nodes only; interior nodes of the region are left alone", r->name);
          warned = true;
        }
      }
    }
  }

  /* initial and reference temperature */
  th->T = peri_calloc((size_t)n + 1, sizeof(double));
  th->T_ref = peri_calloc((size_t)n + 1, sizeof(double));
  peri_expr *init = NULL, *ref = NULL;
  if (sec) {
    TRY(peri_deck_expr(sec, "initial_temperature", false, &init));
    TRY(peri_deck_expr(sec, "reference_temperature", false, &ref));
  }
  const double *x = s->disc.p.x;
  for (int32_t i = 0; i < n; ++i)
    th->T[i] = init ? peri_expr_eval(init, x[3 * i], x[3 * i + 1], x[3 * i + 2], 0.0) : 0.0;
  for (int c = 0; c < th->n_bcs; ++c) {
    if (th->bcs[c].kind != PERI_TBC_INITIAL) continue;
    const peri_region *r = &s->cond.regions[th->bcs[c].region];
    for (int32_t a = 0; a < r->count; ++a) {
      const int32_t i = r->nodes[a];
      th->T[i] = peri_expr_eval(th->bcs[c].value, x[3 * i], x[3 * i + 1], x[3 * i + 2], 0.0);
    }
  }
  for (int32_t i = 0; i < n; ++i)
    th->T_ref[i] = ref ? peri_expr_eval(ref, x[3 * i], x[3 * i + 1], x[3 * i + 2], 0.0) : th->T[i];
  peri_expr_free(init);
  peri_expr_free(ref);

  /* cut bonds: the mechanical flags, or (one-way coupling) a private copy of the pre-cracks */
  if (!heat_only && th->coupling == PERI_COUPLING_ONE_WAY) {
    size_t nb = (size_t)(s->disc.bonds.n_bonds > 0 ? s->disc.bonds.n_bonds : 1);
    th->cut = peri_malloc(nb);
    memcpy(th->cut, s->disc.bonds.broken, (size_t)s->disc.bonds.n_bonds);
    th->own_cut = true;
  } else {
    th->cut = s->disc.bonds.broken;
  }
  if (th->n_growing) growing_bonds(s);
  peri_thermal_prepare(s);
  peri_thermal_grow_cracks(s, 0.0);
  peri_thermal_constrain(s, th->T, 0.0);
  th->dt_stable = peri_thermal_stable_dt(th);
  th->dt = dt_given > 0.0 ? dt_given : th->safety_factor * th->dt_stable;
  if (dt_given > th->dt_stable)
    peri_warning("thermal time_step %g exceeds the stable estimate %g; the temperature may diverge", dt_given,
                 th->dt_stable);

  if (!heat_only) {
    s->state.thermal_strain = peri_calloc((size_t)s->disc.p.n + 1, sizeof(double));
    peri_thermal_update_strain(s);
    th->every = 0; /* set at the first coupled step, once the mechanical step is known */
  }

  /* output defaults of conduction-only runs */
  if (heat_only) {
    const peri_node *out = peri_deck_get(root, "output");
    if (!peri_deck_get(out, "fields")) {
      for (int k = 0; k < s->out.n_fields; ++k) free(s->out.fields[k]);
      free(s->out.fields);
      static const char *const defaults[] = {"temperature", "heat_flux", "damage"};
      s->out.fields = peri_calloc(3, sizeof(char *));
      s->out.n_fields = 0;
      for (int k = 0; k < 3; ++k) s->out.fields[s->out.n_fields++] = peri_strdup(defaults[k]);
    }
    const peri_node *pic = peri_deck_get(out, "picture");
    if (!(pic && pic->kind == PERI_NODE_MAPPING && peri_deck_get(pic, "field"))) {
      free(s->out.picture_field);
      s->out.picture_field = peri_strdup("temperature");
    }
    for (int k = 0; k < s->out.n_fields; ++k) {
      static const char *const mech[] = {"displacement", "velocity", "force", "dilatation",
                                         "strain_energy_density", NULL};
      for (int m = 0; mech[m]; ++m)
        if (!strcmp(s->out.fields[k], mech[m]))
          return peri_deck_error(peri_deck_get(out, "fields"), "output field '%s': not available with solver "
                                 "type heat (fields: temperature, heat_flux, damage, material, volume, block)",
                                 mech[m]);
    }
  }
  return PERI_OK;
}
