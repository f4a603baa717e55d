/* The materials' plasticity keys (docs/deck.md "Plasticity", docs/plasticity.md): the
 * sublayers given as weights and yield stretches, or built from a stress-strain curve (a
 * table of points or a power law at given strains or stresses). Run once the elastic constants are
 * resolved (the construction needs E). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/deck.h"
#include "peri/error.h"
#include "peri/plasticity.h"
#include "peri/tensor_plasticity.h"
#include "setup_parts.h"

#define TRY(expr)                   \
  do {                              \
    int rc_ = (expr);               \
    if (rc_ != PERI_OK) return rc_; \
  } while (0)

/* The item `bad` of the sequence under `key` (for the position of a message), else the key's value. */
static const peri_node *item_or(const peri_node *map, const char *key, int bad) {
  const peri_node *seq = peri_deck_get(map, key);
  if (seq && seq->kind == PERI_NODE_SEQUENCE && bad >= 0 && bad < seq->count) return seq->items[bad];
  return seq ? seq : map;
}

/* critical_bond_energy: {fracture_energy: G0} (J/m^2) or {work: w_c} (J/m^6). */
static int parse_bond_energy(const peri_sim *s, const peri_node *pl, const char *section, peri_sublayers *sl) {
  const peri_node *it = peri_deck_get(pl, "critical_bond_energy");
  sl->critical_bond_work = INFINITY;
  if (!it) return PERI_OK;
  static const char *const keys[] = {"fracture_energy", "work", NULL};
  char where[300];
  snprintf(where, sizeof where, "%s.critical_bond_energy", section);
  if (it->kind != PERI_NODE_MAPPING)
    return peri_deck_error(it, "%s: expected a mapping {fracture_energy: G0} or {work: w_c}", where);
  TRY(peri_deck_allow(it, where, keys));
  const peri_node *g = peri_deck_get(it, "fracture_energy"), *w = peri_deck_get(it, "work");
  if (!g == !w) return peri_deck_error(it, "%s: give one of fracture_energy (J/m^2) or work (J/m^6)", where);
  double value = 0.0;
  TRY(peri_deck_double(it, g ? "fracture_energy" : "work", true, &value));
  if (!(value > 0.0) || !isfinite(value))
    return peri_deck_error(g ? g : w, "%s: %s must be positive", where, g ? "fracture_energy" : "work");
  const peri_geometry *geo = &s->disc.geom;
  sl->critical_bond_work =
      g ? peri_critical_bond_work(geo->dim, value, s->disc.family.horizon, geo->thickness, geo->cross_section) : value;
  return PERI_OK;
}

/* cowper_symonds: {d: D (1/s), p: q}, both positive. */
static int parse_cowper_symonds(const peri_node *pl, const char *section, peri_sublayers *sl) {
  const peri_node *it = peri_deck_get(pl, "cowper_symonds");
  if (!it) return PERI_OK;
  static const char *const keys[] = {"d", "p", NULL};
  char where[300];
  snprintf(where, sizeof where, "%s.cowper_symonds", section);
  if (it->kind != PERI_NODE_MAPPING) return peri_deck_error(it, "%s: expected a mapping {d: D, p: q}", where);
  TRY(peri_deck_allow(it, where, keys));
  TRY(peri_deck_double(it, "d", true, &sl->rate_d));
  TRY(peri_deck_double(it, "p", true, &sl->rate_p));
  if (!(sl->rate_d > 0.0) || !isfinite(sl->rate_d))
    return peri_deck_error(peri_deck_get(it, "d"), "%s: d must be a positive rate (1/s)", where);
  if (!(sl->rate_p > 0.0) || !isfinite(sl->rate_p))
    return peri_deck_error(peri_deck_get(it, "p"), "%s: p must be positive", where);
  return PERI_OK;
}

/* calibration: bond (the construction of model reference 16.1, exact for a bond and a 1D bar)
 * or family (a 2D or 3D family fitted to the curve under uniaxial stress, docs/plasticity.md
 * section 4). The curve is checked by the bond construction either way. */
static int calibrate_to_family(const peri_sim *s, const peri_node *pl, const char *section, const peri_material *mat,
                               int n, const double *strain, const double *stress, peri_sublayers *sl) {
  static const char *const choices[] = {"bond", "family", NULL};
  int which = 0;
  TRY(peri_deck_choice(pl, "calibration", false, choices, &which));
  if (which == 0) return PERI_OK;
  const peri_geometry *geo = &s->disc.geom;
  if (geo->dim == 1)
    return peri_deck_error(peri_deck_get(pl, "calibration"), "%s.calibration: family is for dimension 2 or 3 (a 1D "
                           "bar follows the bond construction exactly)", section);
  /* the bar's lateral contraction in the plane of the family: plane strain nu / (1 - nu) */
  const double nu = geo->dim == 2 && geo->plane == PERI_PLANE_STRAIN ? mat->nu / (1.0 - mat->nu) : mat->nu;
  peri_sublayers_fit_family(geo->dim, nu, mat->E, n, strain, stress, sl);
  return PERI_OK;
}

/* yield_rule: bond (each bond's sublayers on its stretch), deviatoric (the state-based rule
 * of docs/plasticity.md section 8: LPS in 3D, sublayers from a curve, none of the bond
 * rule's failure and rate keys, whose quantities are a bond's) or deviatoric_tensor (the same
 * with one plastic tensor per node and sublayer, section 10). */
static int parse_yield_rule(const peri_sim *s, const peri_node *pl, const char *section, const peri_material *mat,
                            peri_sublayers *sl) {
  static const char *const choices[] = {"bond", "deviatoric", "deviatoric_tensor", NULL};
  int which = 0;
  TRY(peri_deck_choice(pl, "yield_rule", false, choices, &which));
  if (which == 0) return PERI_OK;
  const char *rule = choices[which];
  const peri_node *at = peri_deck_get(pl, "yield_rule");
  if (strcmp(s->mat.model->name, "lps") != 0)
    return peri_deck_error(at, "%s.yield_rule: %s is a rule of the lps model (model here: %s)", section, rule,
                           s->mat.model->name);
  if (s->disc.geom.dim != 3)
    return peri_deck_error(at, "%s.yield_rule: %s is for dimension 3 (its von Mises calibration is the 3D "
                           "family's)", section, rule);
  if (mat->peer_force_state)
    return peri_deck_error(at, "%s.yield_rule: %s needs force_state variational", section, rule);
  static const char *const bond_only[] = {"weights", "yield_stretches", "calibration", "critical_plastic_stretch",
                                          "critical_bond_energy", "cowper_symonds", NULL};
  for (int k = 0; bond_only[k]; ++k)
    if (peri_deck_get(pl, bond_only[k]))
      return peri_deck_error(peri_deck_key_node(pl, bond_only[k]), "%s.%s: not with yield_rule %s (%s)",
                             section, bond_only[k], rule,
                             k < 2 ? "give the uniaxial curve: strains with stresses or power_law"
                                   : "a key of the bond rule");
  sl->deviatoric = true;
  sl->tensor = which == 2;
  return PERI_OK;
}

/* The breakpoints of a uniaxial curve: strains with stresses (a table), or a power law at
 * the given strains or at the given stresses (docs/plasticity.md section 1). */
static int parse_curve(const peri_node *pl, const char *section, const peri_node *law, double *strain,
                       double *stress, int *n, const char **given_points) {
  const bool has_strains = peri_deck_get(pl, "strains") != NULL, has_stresses = peri_deck_get(pl, "stresses") != NULL;
  if (!law) {
    int ns = 0;
    TRY(peri_deck_vector_range(pl, "strains", true, 1, PERI_MAX_SUBLAYERS, strain, n));
    TRY(peri_deck_vector_range(pl, "stresses", true, 1, PERI_MAX_SUBLAYERS, stress, &ns));
    if (ns != *n)
      return peri_deck_error(peri_deck_get(pl, "stresses"), "%s: %d strains but %d stresses", section, *n, ns);
    return PERI_OK;
  }
  if (has_strains == has_stresses)
    return peri_deck_error(law, "%s: with power_law give the breakpoints as strains or as stresses (one of them)",
                           section);
  static const char *const law_keys[] = {"yield_stress", "yield_strain", "exponent", NULL};
  double sigma0 = 0.0, eps0 = 0.0, exponent = 0.0;
  TRY(peri_deck_allow(law, "power_law", law_keys));
  TRY(peri_deck_double(law, "yield_stress", true, &sigma0));
  TRY(peri_deck_double(law, "yield_strain", true, &eps0));
  TRY(peri_deck_double(law, "exponent", true, &exponent));
  if (!(sigma0 > 0.0) || !(eps0 > 0.0))
    return peri_deck_error(law, "power_law: yield_stress and yield_strain must be positive");
  if (!(exponent >= 0.0 && exponent <= 1.0))
    return peri_deck_error(peri_deck_get(law, "exponent"), "power_law: exponent must be in [0, 1]");
  if (has_strains) {
    TRY(peri_deck_vector_range(pl, "strains", true, 1, PERI_MAX_SUBLAYERS, strain, n));
    for (int k = 0; k < *n; ++k)
      if (strain[k] < eps0 * (1.0 - 1e-9))
        return peri_deck_error(item_or(pl, "strains", k), "%s: strain %g is below the power law's yield_strain %g",
                               section, strain[k], eps0);
    peri_power_law_stresses(sigma0, eps0, exponent, *n, strain, stress);
    return PERI_OK;
  }
  *given_points = "stresses";
  if (!(exponent > 0.0))
    return peri_deck_error(peri_deck_get(law, "exponent"),
                           "power_law: exponent 0 (perfectly plastic) has no strain at a stress; give strains");
  TRY(peri_deck_vector_range(pl, "stresses", true, 1, PERI_MAX_SUBLAYERS, stress, n));
  for (int k = 0; k < *n; ++k)
    if (stress[k] < sigma0 * (1.0 - 1e-9))
      return peri_deck_error(item_or(pl, "stresses", k), "%s: stress %g is below the power law's yield_stress %g",
                             section, stress[k], sigma0);
  peri_power_law_strains(sigma0, eps0, exponent, *n, stress, strain);
  return PERI_OK;
}

static int parse_one(const peri_sim *s, const peri_node *pl, peri_material *mat) {
  static const char *const keys[] = {"weights", "yield_stretches", "strains", "stresses", "power_law",
                                     "critical_plastic_stretch", "critical_bond_energy", "cowper_symonds", "calibration",
                                     "yield_rule", NULL};
  char section[200];
  snprintf(section, sizeof section, "materials.%s.plasticity", mat->name);
  TRY(peri_deck_allow(pl, section, keys));
  peri_sublayers sl = {0};
  TRY(parse_yield_rule(s, pl, section, mat, &sl));
  char why[256];
  int bad = -1;
  const bool given = peri_deck_get(pl, "weights") || peri_deck_get(pl, "yield_stretches");
  const bool curve = peri_deck_get(pl, "strains") || peri_deck_get(pl, "stresses") || peri_deck_get(pl, "power_law");
  if (given == curve)
    return peri_deck_error(pl, "%s: give either weights and yield_stretches, or strains with stresses or power_law",
                           section);
  if (given) {
    if (peri_deck_get(pl, "calibration"))
      return peri_deck_error(peri_deck_key_node(pl, "calibration"), "%s.calibration: only with a curve (strains with "
                             "stresses or power_law)", section);
    int nw = 0, ny = 0;
    TRY(peri_deck_vector_range(pl, "weights", true, 1, PERI_MAX_SUBLAYERS, sl.weight, &nw));
    TRY(peri_deck_vector_range(pl, "yield_stretches", true, 1, PERI_MAX_SUBLAYERS, sl.yield, &ny));
    if (nw != ny)
      return peri_deck_error(peri_deck_get(pl, "yield_stretches"), "%s: %d weights but %d yield_stretches", section, nw,
                             ny);
    sl.n = nw;
    if (peri_sublayers_check(&sl, &bad, why, sizeof why) != 0) {
      const peri_node *at = bad < 0 ? peri_deck_get(pl, "weights")
                            : !(sl.weight[bad] > 0.0) ? item_or(pl, "weights", bad)
                                                       : item_or(pl, "yield_stretches", bad);
      return peri_deck_error(at, "%s: %s", section, why);
    }
  } else {
    double strain[PERI_MAX_SUBLAYERS], stress[PERI_MAX_SUBLAYERS];
    int n = 0;
    const peri_node *law = peri_deck_get(pl, "power_law");
    /* the key whose items are the breakpoints the deck gave (errors point at them) */
    const char *given_points = "strains";
    TRY(parse_curve(pl, section, law, strain, stress, &n, &given_points));
    if (peri_sublayers_from_curve(mat->E, n, strain, stress, &sl, &bad, why, sizeof why) != 0)
      return peri_deck_error(item_or(pl, law ? given_points : "stresses", bad), "%s: %s", section, why);
    TRY(calibrate_to_family(s, pl, section, mat, n, strain, stress, &sl));
    if (sl.deviatoric) { /* the same construction on the deviatoric curve (docs/plasticity.md section 8) */
      double dev_strain[PERI_MAX_SUBLAYERS], dev_stress[PERI_MAX_SUBLAYERS];
      peri_deviatoric_curve(mat->K, n, strain, stress, dev_strain, dev_stress);
      if (peri_sublayers_from_curve(2.0 * mat->mu, n, dev_strain, dev_stress, &sl, &bad, why, sizeof why) != 0)
        return peri_deck_error(item_or(pl, law ? given_points : "stresses", bad), "%s: the deviatoric curve: %s", section,
                               why);
    }
    if (peri_sublayers_check(&sl, &bad, why, sizeof why) != 0) /* (the weights of a curve sum to 1 exactly) */
      return peri_deck_error(pl, "%s: %s", section, why);
  }
  sl.critical_plastic_stretch = INFINITY;
  if (peri_deck_get(pl, "critical_plastic_stretch")) {
    TRY(peri_deck_double(pl, "critical_plastic_stretch", true, &sl.critical_plastic_stretch));
    if (!(sl.critical_plastic_stretch > 0.0))
      return peri_deck_error(peri_deck_get(pl, "critical_plastic_stretch"),
                             "key 'critical_plastic_stretch': must be positive");
  }
  TRY(parse_bond_energy(s, pl, section, &sl));
  TRY(parse_cowper_symonds(pl, section, &sl));
  mat->sublayers = peri_malloc(sizeof sl);
  *mat->sublayers = sl;
  return PERI_OK;
}

int peri_setup_plasticity(peri_sim *s, const peri_node *root) {
  const peri_node *mats = peri_deck_get(root, "materials");
  for (int m = 0; m < s->mat.n_materials && mats; ++m) {
    const peri_node *pl = peri_deck_get(mats->items[m], "plasticity");
    if (!pl) continue;
    if (pl->kind != PERI_NODE_MAPPING)
      return peri_deck_error(pl, "materials.%s.plasticity: expected a mapping, got %s", s->mat.materials[m].name,
                             peri_deck_kind_name(pl));
    TRY(parse_one(s, pl, &s->mat.materials[m]));
  }
  /* one rule for the run: the two rules' force passes are different loops */
  const peri_sublayers *first = NULL;
  for (int m = 0; m < s->mat.n_materials && mats; ++m) {
    const peri_sublayers *sl = s->mat.materials[m].sublayers;
    if (!sl) continue;
    if (first && (sl->deviatoric != first->deviatoric || sl->tensor != first->tensor))
      return peri_deck_error(peri_deck_get(mats->items[m], "plasticity"),
                             "materials.%s.plasticity: all plastic materials take the same yield_rule",
                             s->mat.materials[m].name);
    first = sl;
  }
  return PERI_OK;
}

int peri_setup_plasticity_solver(peri_sim *s, const peri_node *root) {
  if (!s->state.plastic_stretch && !s->state.plastic_tensor) return PERI_OK;
  if (s->disc.surface_correction != 0) {
    const peri_node *d = peri_deck_get(root, "discretization");
    return peri_deck_error(d ? peri_deck_get(d, "surface_correction") : root,
                           "discretization.surface_correction: not available with plastic materials");
  }
  const peri_node *mats = peri_deck_get(root, "materials");
  if (s->solver.kind == PERI_SOLVER_EXPLICIT) return PERI_OK;
  /* the stretch rate is the bonds' rate in time (src/model/plastic_bonds.c) */
  for (int m = 0; m < s->mat.n_materials; ++m)
    if (s->mat.materials[m].sublayers && s->mat.materials[m].sublayers->rate_d > 0.0) {
      const peri_node *pl = mats ? peri_deck_get(mats->items[m], "plasticity") : NULL;
      return peri_deck_error(pl ? peri_deck_get(pl, "cowper_symonds") : root,
                             "materials.%s.plasticity.cowper_symonds: rate dependence needs solver type explicit "
                             "(a quasi-static solver has no time)",
                             s->mat.materials[m].name);
    }
  if (s->solver.kind == PERI_SOLVER_ADR || s->solver.kind == PERI_SOLVER_DYNAMIC_RELAXATION) {
    /* load steps map from the accepted state (src/model/plastic_bonds.c) */
    if (s->state.plastic_tensor) {
      s->state.plastic_tensor->quasi_static = true;
      return PERI_OK;
    }
    const size_t n = (size_t)s->state.plastic_layers * (size_t)s->disc.bonds.n_bonds;
    s->state.plastic_committed = peri_calloc_aligned(n > 0 ? n : 1, sizeof(double));
    return PERI_OK;
  }
  /* a line search or a Newton iteration evaluates the force at trial states, which would
   * commit plastic flow that the accepted state never reaches */
  const peri_node *solver = peri_deck_get(root, "solver");
  return peri_deck_error(solver ? peri_deck_get(solver, "type") : root,
                         "solver: plasticity needs solver type explicit, adr or dynamic_relaxation (the plastic state "
                         "follows every force evaluation)");
}
