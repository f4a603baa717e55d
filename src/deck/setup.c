/* Builds a simulation from a deck. Every input error is reported with its position
 * before any work starts (exit status 2). The keys are documented in docs/deck.md. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "peri/checkpoint.h"
#include "peri/bodies.h"
#include "peri/contact.h"
#include "peri/short_range.h"
#include "peri/tools.h"
#include "peri/conduction.h"
#include "peri/coupling.h"
#include "peri/dataset.h"
#include "peri/constants.h"
#include "peri/damage.h"
#include "peri/deck.h"
#include "peri/decompose.h"
#include "peri/discretize.h"
#include "peri/error.h"
#include "peri/tensor_plasticity.h"
#include "peri/fem_mesh.h"
#include "peri/frames.h"
#include "peri/nodefile.h"
#include "peri/setup.h"
#include "peri/sim.h"
#include "peri/solver.h"
#include "peri/history.h"
#include "peri/horizon_field.h"
#include "peri/interface_moduli.h"
#include "peri/quasistatic.h"
#include "peri/overrides.h"
#include "peri/thermal.h"
#include "setup_parts.h"

#define TRY(expr)                       \
  do {                                  \
    int rc_ = (expr);                   \
    if (rc_ != PERI_OK) return rc_;     \
  } while (0)

/* Failure inputs kept until the horizon is known. */
typedef struct material_failure {
  double G0, KIc, s0;
  double E, nu, K, mu; /* as given (NaN = absent); resolved once the horizon is known */
  const peri_node *at;
} material_failure;

typedef struct parse_ctx {
  peri_sim *s;
  const peri_node *root;
  material_failure *failure;
  peri_mesh mesh;          /* the discretization's mesh file (its sets and point ids), or empty */
  int32_t *node_of_point;  /* node index of each mesh point, after the node ordering */
  peri_fem_mesh fem_mesh;  /* coupling.graded_mesh, or empty (coupling_keys.c) */
} parse_ctx;

/* ---------------------------------------------------------------- materials */

static const char *const material_keys[] = {
    "model", "density", "youngs_modulus", "poisson_ratio", "bulk_modulus", "shear_modulus",
    "micromodulus", "critical_stretch", "fracture_energy", "fracture_toughness",
    "conductivity", "specific_heat", "thermal_expansion", "force_state",
    "plasticity", NULL};

static int parse_material(parse_ctx *c, const peri_node *key, const peri_node *map, int index) {
  peri_sim *s = c->s;
  peri_material *mat = &s->mat.materials[index];
  char section[160];
  snprintf(section, sizeof section, "materials.%s", key->scalar);
  if (peri_setup_heat_only(c->root)) return peri_setup_heat_material(s, key, map, index); /* docs/heat.md */
  TRY(peri_deck_allow(map, section, material_keys));
  mat->name = peri_strdup(key->scalar);
  TRY(peri_setup_material_thermal_keys(map, mat));
  const char *model_name = NULL;
  TRY(peri_deck_string(map, "model", true, &model_name));
  int model_index = 0;
  TRY(peri_deck_choice(map, "model", true, peri_model_names(), &model_index));
  const peri_model_ops *ops = peri_model_find(model_name);
  if (s->mat.model && s->mat.model != ops)
    return peri_deck_error(peri_deck_get(map, "model"),
                           "key 'model': all materials must use one model (found '%s' and '%s')",
                           s->mat.model->name, ops->name);
  s->mat.model = ops;
  mat->model = model_index;
  TRY(peri_deck_double(map, "density", true, &mat->density));
  if (!(mat->density > 0.0))
    return peri_deck_error(peri_deck_get(map, "density"), "key 'density': must be positive");
  double E = NAN, nu = NAN, K = NAN, mu = NAN, cgiven = NAN;
  TRY(peri_deck_double(map, "youngs_modulus", false, &E));
  TRY(peri_deck_double(map, "poisson_ratio", false, &nu));
  TRY(peri_deck_double(map, "bulk_modulus", false, &K));
  TRY(peri_deck_double(map, "shear_modulus", false, &mu));
  TRY(peri_deck_double(map, "micromodulus", false, &cgiven));
  if (!isnan(cgiven)) {
    if (!ops->fixed_poisson)
      return peri_deck_error(peri_deck_get(map, "micromodulus"),
                             "key 'micromodulus': only bond-based models take a micromodulus");
    mat->micromodulus_given = true;
    mat->micromodulus = cgiven;
  }
  /* the LPS force state (docs/models.md 3.5): the variational form unless the peer form is asked for */
  static const char *const force_states[] = {"variational", "peer", NULL};
  int force_state = 0;
  TRY(peri_deck_choice(map, "force_state", false, force_states, &force_state));
  if (peri_deck_get(map, "force_state") && ops != peri_model_find("lps"))
    return peri_deck_error(peri_deck_get(map, "force_state"), "key 'force_state': only the lps model has a force state");
  mat->peer_force_state = force_state == 1;
  material_failure *in = &c->failure[index];
  in->E = E, in->nu = nu, in->K = K, in->mu = mu;
  /* failure: a number, a LAMMPS-style mapping {s00, alpha}, or from G0 / K_Ic */
  material_failure *f = in;
  f->G0 = f->KIc = f->s0 = NAN;
  f->at = map;
  mat->critical_stretch = INFINITY;
  const peri_node *cs = peri_deck_get(map, "critical_stretch");
  int given = 0;
  if (cs && cs->kind == PERI_NODE_MAPPING) {
    static const char *const lammps_keys[] = {"s00", "alpha", NULL};
    TRY(peri_deck_allow(cs, "critical_stretch", lammps_keys));
    TRY(peri_deck_double(cs, "s00", true, &mat->s00));
    mat->alpha_s = 0.0;
    TRY(peri_deck_double(cs, "alpha", false, &mat->alpha_s));
    if (!(mat->s00 > 0.0)) return peri_deck_error(peri_deck_get(cs, "s00"), "key 's00': must be positive");
    if (mat->alpha_s < 0.0) return peri_deck_error(peri_deck_get(cs, "alpha"), "key 'alpha': must be >= 0");
    mat->lammps_s0 = true;
    given++;
  } else if (cs) {
    TRY(peri_deck_double(map, "critical_stretch", false, &f->s0));
    if (!(f->s0 > 0.0)) return peri_deck_error(cs, "key 'critical_stretch': must be positive");
    given++;
  }
  if (peri_deck_get(map, "fracture_energy")) {
    TRY(peri_deck_double(map, "fracture_energy", true, &f->G0));
    given++;
  }
  if (peri_deck_get(map, "fracture_toughness")) {
    TRY(peri_deck_double(map, "fracture_toughness", true, &f->KIc));
    if (!(f->KIc > 0.0))
      return peri_deck_error(peri_deck_get(map, "fracture_toughness"), "key 'fracture_toughness': must be positive");
    given++;
  }
  if (given > 1)
    return peri_deck_error(map, "%s: give only one of critical_stretch, fracture_energy, "
                                "fracture_toughness", section);
  return PERI_OK;
}

static int parse_materials(parse_ctx *c) {
  peri_sim *s = c->s;
  const peri_node *mats = peri_deck_get(c->root, "materials");
  if (!mats) return peri_deck_error(c->root, "missing key 'materials' in the deck");
  if (mats->kind != PERI_NODE_MAPPING || mats->count == 0)
    return peri_deck_error(mats, "key 'materials': expected a mapping of material names to "
                                 "properties, got %s", peri_deck_kind_name(mats));
  s->mat.n_materials = mats->count;
  s->mat.materials = peri_calloc(mats->count, sizeof(peri_material));
  c->failure = peri_calloc(mats->count, sizeof(material_failure));
  for (int m = 0; m < mats->count; ++m) {
    if (mats->items[m]->kind != PERI_NODE_MAPPING)
      return peri_deck_error(mats->items[m], "material '%s': expected a mapping, got %s",
                             mats->keys[m]->scalar, peri_deck_kind_name(mats->items[m]));
    if (mats->keys[m]->scalar && !strcmp(mats->keys[m]->scalar, "void"))
      return peri_deck_error(mats->keys[m], "material name 'void' is reserved: it means no material (a hole) in "
                                            "discretization.fill");
    TRY(parse_material(c, mats->keys[m], mats->items[m], m));
  }
  return PERI_OK;
}

/* The osb_mo model (src/model/osb_mo.c) has its own influence function delta/|xi| and none of
 * the LPS surface corrections or the LAMMPS-form critical stretch. */
static int check_osb_mo(parse_ctx *c) {
  const peri_sim *s = c->s;
  if (s->mat.model != peri_model_find("osb_mo")) return PERI_OK;
  const peri_node *d = peri_deck_get(c->root, "discretization");
  if (d && peri_deck_get(d, "influence"))
    return peri_deck_error(peri_deck_key_node(d, "influence"), "key 'influence': the osb_mo model has its own influence "
                           "function omega = delta/|xi| (Ebrahimi 2020 eq. 2.22); remove the key, or use model lps "
                           "for another");
  if (s->disc.surface_correction != PERI_SURFACE_NONE)
    return peri_deck_error(peri_deck_key_node(d, "surface_correction"), "key 'surface_correction': not available with "
                           "the osb_mo model (the corrections are those of lps, docs/models.md 4.1)");
  for (int m = 0; m < s->mat.n_materials; ++m)
    if (s->mat.materials[m].lammps_s0)
      return peri_deck_error(c->failure[m].at, "materials.%s: the {s00, alpha} critical stretch is not available "
                             "with the osb_mo model (give a number, a fracture_energy or a fracture_toughness)",
                             s->mat.materials[m].name);
  return PERI_OK;
}

/* Elastic constants (which need the horizon when a micromodulus is given) and the
 * critical stretch of every material and material pair. */
static int resolve_materials(parse_ctx *c) {
  peri_sim *s = c->s;
  bool lps = s->mat.model == peri_model_find("lps");
  for (int m = 0; m < s->mat.n_materials; ++m) {
    peri_material *mat = &s->mat.materials[m];
    material_failure *f = &c->failure[m];
    double E = f->E, K = f->K;
    if (mat->micromodulus_given && isnan(E) && isnan(K) && isnan(f->mu)) {
      /* invert the calibration so that the time step estimate has a modulus */
      double c1 = peri_pmb_micromodulus(&s->disc.geom, 1.0, 1.0);
      if (s->disc.geom.dim == 3) K = mat->micromodulus / c1;
      else E = mat->micromodulus / c1;
    }
    double fixed_nu = s->mat.model->fixed_poisson ? peri_pmb_poisson(&s->disc.geom) : NAN;
    char why[256];
    if (peri_elastic_resolve(E, f->nu, K, f->mu, fixed_nu, &mat->E, &mat->nu, &mat->K, &mat->mu,
                             why, sizeof why) != PERI_OK)
      return peri_deck_error(f->at, "materials.%s: %s", mat->name, why);
    if (!isnan(fixed_nu) && !isnan(f->nu) && fabs(f->nu - fixed_nu) > 1e-9)
      peri_warning("materials.%s: a bond-based model represents Poisson ratio %.4g here; "
                   "poisson_ratio %g only converts the given moduli", mat->name, fixed_nu, f->nu);
    if (lps && s->disc.geom.dim == 2 && s->disc.geom.plane == PERI_PLANE_STRESS && mat->nu >= 0.5)
      return peri_deck_error(f->at, "materials.%s: plane stress LPS needs poisson_ratio < 1/2", mat->name);
    if (!isnan(f->KIc)) f->G0 = peri_fracture_energy_from_toughness(&s->disc.geom, f->KIc, mat->E, mat->nu);
    if (!isnan(f->G0)) {
      if (!(f->G0 > 0.0)) return peri_deck_error(f->at, "materials.%s: fracture energy must be positive", mat->name);
      f->s0 = lps ? peri_critical_stretch_lps(&s->disc.geom, f->G0, mat->E)
                  : peri_critical_stretch_pmb(&s->disc.geom, f->G0, mat->E, mat->K);
    }
    if (!isnan(f->s0)) mat->critical_stretch = f->s0;
  }
  int nm = s->mat.n_materials;
  s->mat.pair_s0 = peri_malloc(sizeof(double) * nm * nm);
  for (int a = 0; a < nm; ++a)
    for (int b = 0; b < nm; ++b)
      s->mat.pair_s0[a * nm + b] = fmin(s->mat.materials[a].critical_stretch, s->mat.materials[b].critical_stretch);
  return PERI_OK;
}

/* interfaces[].youngs_modulus: a positive modulus between two different materials of the
 * bond-based model, whose bonds have a constant of their own (docs/deck.md section 9). */
static int check_interface_modulus(const peri_sim *s, const peri_node *at, double E, int a, int b) {
  if (!(E > 0.0) || !isfinite(E)) return peri_deck_error(at, "interfaces: youngs_modulus must be a positive number of Pa");
  if (a == b)
    return peri_deck_error(at, "interfaces: youngs_modulus needs two different materials (a material's own bonds "
                               "take its youngs_modulus)");
  if (s->mat.model != peri_model_find("pmb"))
    return peri_deck_error(at, "interfaces: youngs_modulus is for the bond-based model pmb; with %s each node's "
                               "force state follows from its own material's moduli and no bond has a constant "
                               "of its own (docs/thin_films.md section 7)", s->mat.model->name);
  if (s->disc.surface_correction != PERI_SURFACE_NONE || s->disc.horizon_field)
    return peri_deck_error(at, "interfaces: youngs_modulus is not available with discretization.surface_correction "
                               "or a variable horizon");
  if (s->mat.materials[a].sublayers || s->mat.materials[b].sublayers)
    return peri_deck_error(at, "interfaces: youngs_modulus is not available with plastic sublayers");
  return PERI_OK;
}

static int parse_interfaces(parse_ctx *c) {
  peri_sim *s = c->s;
  const peri_node *list = peri_deck_get(c->root, "interfaces");
  if (!list) return PERI_OK;
  if (list->kind != PERI_NODE_SEQUENCE)
    return peri_deck_error(list, "key 'interfaces': expected a list, got %s", peri_deck_kind_name(list));
  static const char *const keys[] = {"materials", "critical_stretch", "fracture_energy", "normal_strength",
                                     "youngs_modulus", NULL};
  for (int m = 0; m < s->mat.n_materials; ++m)
    if (s->mat.materials[m].lammps_s0 && list->count > 0)
      return peri_deck_error(list, "key 'interfaces': not available with the {s00, alpha} critical "
                             "stretch of material '%s' (bonds take min(s0_i, s0_j))", s->mat.materials[m].name);
  for (int k = 0; k < list->count; ++k) {
    const peri_node *it = list->items[k];
    TRY(peri_deck_allow(it, "interfaces", keys));
    const peri_node *pair = peri_deck_get(it, "materials");
    if (!pair) return peri_deck_error(it, "missing key 'materials' in interfaces");
    if (pair->kind != PERI_NODE_SEQUENCE || pair->count != 2 || pair->items[0]->kind != PERI_NODE_SCALAR ||
        pair->items[1]->kind != PERI_NODE_SCALAR)
      return peri_deck_error(pair, "key 'materials': expected two material names, e.g. [matrix, fiber]");
    int a = peri_setup_find_material(s, pair->items[0], pair->items[0]->scalar);
    if (a < 0) return -a;
    int b = peri_setup_find_material(s, pair->items[1], pair->items[1]->scalar);
    if (b < 0) return -b;
    double s0 = NAN, G0 = NAN, strength = NAN, modulus = NAN;
    TRY(peri_deck_double(it, "critical_stretch", false, &s0));
    TRY(peri_deck_double(it, "fracture_energy", false, &G0));
    TRY(peri_deck_double(it, "normal_strength", false, &strength));
    TRY(peri_deck_double(it, "youngs_modulus", false, &modulus));
    int nm = s->mat.n_materials;
    if (!isnan(modulus)) { /* the interface bonds' own constant (include/peri/interface_moduli.h) */
      TRY(check_interface_modulus(s, peri_deck_get(it, "youngs_modulus"), modulus, a, b));
      peri_interface_modulus_set(s, a, b, modulus);
    }
    if (!isnan(strength)) { /* the traction criterion of docs/thin_films.md section 6 */
      const peri_node *at = peri_deck_get(it, "normal_strength");
      if (!(strength > 0.0) || !isfinite(strength))
        return peri_deck_error(at, "interfaces: normal_strength must be a positive number of Pa");
      if (a == b)
        return peri_deck_error(at, "interfaces: normal_strength needs two different materials (it acts across "
                                   "the interface between them)");
      if (!s->mat.pair_strength) s->mat.pair_strength = peri_calloc((size_t)nm * (size_t)nm, sizeof(double));
      s->mat.pair_strength[a * nm + b] = s->mat.pair_strength[b * nm + a] = strength;
    }
    if (isnan(s0) && isnan(G0) && !(isnan(strength) && isnan(modulus))) continue; /* min(s0_a, s0_b) */
    if (isnan(s0) == isnan(G0))
      return peri_deck_error(it, "interfaces: give exactly one of critical_stretch, fracture_energy%s",
                             isnan(strength) && isnan(modulus) ? " (or normal_strength, youngs_modulus)"
                                                               : " (besides normal_strength, youngs_modulus)");
    if (!((isnan(s0) ? G0 : s0) > 0.0))
      return peri_deck_error(it, "interfaces: the critical stretch or fracture energy must be positive");
    if (!isnan(G0)) {
      /* the softer side's modulus (docs/model_reference.md 8: designated side) */
      const peri_material *ma = &s->mat.materials[a], *mb = &s->mat.materials[b];
      const peri_material *soft = ma->E <= mb->E ? ma : mb;
      s0 = s->mat.model == peri_model_find("lps") ? peri_critical_stretch_lps(&s->disc.geom, G0, soft->E)
                                             : peri_critical_stretch_pmb(&s->disc.geom, G0, soft->E, soft->K);
    }
    s->mat.pair_s0[a * nm + b] = s->mat.pair_s0[b * nm + a] = s0;
  }
  return PERI_OK;
}

/* ---------------------------------------------------------------- discretization */

static const char *const discretization_keys[] = {
    "spacing", "horizon", "m", "placement", "origin", "thickness", "cross_section",
    "partial_volume", "influence", "weighted_volume", "surface_correction", "fill", "remove", "node_file",
    "blocks", "volume", "max_nodes", "mesh", "mesh_format", "partial_stress",
    "partial_stress_stabilization", "fictitious_layers", "local_stencil", NULL};

static int parse_shape_list(const peri_node *list, int dim, const char *section,
                            const char *const *extra, peri_shape **shapes, int *count) {
  if (list->kind != PERI_NODE_SEQUENCE)
    return peri_deck_error(list, "key '%s': expected a list of shapes, got %s", section,
                           peri_deck_kind_name(list));
  *count = list->count;
  *shapes = peri_calloc(list->count, sizeof(peri_shape));
  for (int k = 0; k < list->count; ++k)
    TRY(peri_shape_parse(list->items[k], dim, section, extra, &(*shapes)[k]));
  return PERI_OK;
}

/* Bytes a node costs at least before its bonds: x u v f b, volume, damage, material,
 * block, flags, the bond loops' copies of x and u, its CSR offset (src/run/summary.c). */
enum { GRID_BYTES_PER_NODE = 200, GRID_BYTES_PER_BOND = 5 };

static double physical_memory(void) {
  long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page_size > 0 ? (double)pages * (double)page_size : 0.0;
}

/* The grid's size from its fill shapes' bounding boxes, before any node is made: a grid
 * larger than the machine's memory (or than max_nodes, when given) is an input error
 * found at once, instead of a generation that runs for minutes and exhausts the memory.
 * `m` is horizon / spacing, for the bonds per node. */
static int check_grid_size(const peri_node *d, const peri_grid_params *gp, double m) {
  const double nodes = peri_grid_points_bound(gp);
  const double family = gp->dim == 3 ? 4.0 / 3.0 * M_PI * m * m * m
                        : gp->dim == 2 ? M_PI * m * m : 2.0 * m;
  const double bytes = nodes * (GRID_BYTES_PER_NODE + GRID_BYTES_PER_BOND * family);
  const peri_node *limit = peri_deck_get(d, "max_nodes");
  if (limit) {
    long max_nodes = 0;
    TRY(peri_deck_int(d, "max_nodes", true, &max_nodes));
    if (max_nodes < 1) return peri_deck_error(limit, "key 'max_nodes': must be >= 1");
    if (nodes > (double)max_nodes)
      return peri_deck_error(limit, "key 'max_nodes': the fill shapes' bounding boxes hold up to "
                             "%.4g grid points at spacing %g, more than max_nodes = %ld; use a "
                             "coarser spacing or raise max_nodes", nodes, gp->spacing, max_nodes);
    return PERI_OK;
  }
  const double memory = physical_memory();
  if (memory > 0.0 && bytes > memory)
    return peri_deck_error(peri_deck_get(d, "spacing"), "discretization: spacing %g gives up to "
                           "%.4g nodes (the grid points in the fill shapes' bounding boxes), at "
                           "least %.3g GB at m = %.3g, more than this machine's memory (%.3g "
                           "GB); use a coarser spacing, or set discretization.max_nodes to "
                           "allow that many nodes", gp->spacing, nodes, bytes / 1e9, m, memory / 1e9);
  return PERI_OK;
}

/* The zones of a graded grid tile the body exactly: cell-centred boxes whose sides are
 * whole multiples of their spacing, no two overlapping (docs/variable_horizon.md). */
static int check_graded_zones(const peri_node *d, const peri_node *fill, const peri_grid_params *gp) {
  if (gp->placement != PERI_PLACE_CENTERS || gp->origin_given)
    return peri_deck_error(peri_deck_key_node(d, gp->origin_given ? "origin" : "placement"), "discretization: a "
                           "graded grid (a fill shape with its own spacing) places each zone's nodes at its own "
                           "cell centres: no 'origin', and 'placement' centers");
  if (peri_deck_get(d, "volume"))
    return peri_deck_error(peri_deck_key_node(d, "volume"), "key 'volume': not on a graded grid (a node's volume is "
                           "its zone's cell, so that the volumes tile the body)");
  for (int k = 0; k < gp->n_fill; ++k) {
    const peri_shape *a = &gp->fill[k].shape;
    const double dx = gp->fill[k].spacing > 0.0 ? gp->fill[k].spacing : gp->spacing;
    if (gp->fill[k].detachment)
      return peri_deck_error(fill->items[k], "discretization.fill item %d: a detachment defect needs a uniform grid "
                             "(no fill shape with its own spacing)", k + 1);
    if (a->kind != PERI_SHAPE_BOX)
      return peri_deck_error(fill->items[k], "discretization.fill item %d: on a graded grid every zone is a box "
                             "(cut holes and notches with 'remove')", k + 1);
    for (int c = 0; c < gp->dim; ++c) {
      const double cells = (a->max[c] - a->min[c]) / dx;
      if (fabs(cells - round(cells)) > 1e-9 * fmax(1.0, cells))
        return peri_deck_error(fill->items[k], "discretization.fill item %d: its side along axis %d is %g "
                               "spacings (%g); on a graded grid a zone's sides are whole multiples of its spacing",
                               k + 1, c + 1, cells, dx);
    }
    for (int j = 0; j < k; ++j) {
      const peri_shape *b = &gp->fill[j].shape;
      bool overlap = true;
      for (int c = 0; c < gp->dim; ++c)
        overlap = overlap && fmin(a->max[c], b->max[c]) - fmax(a->min[c], b->min[c]) > 1e-9 * dx;
      if (overlap)
        return peri_deck_error(fill->items[k], "discretization.fill item %d overlaps item %d; the zones of a "
                               "graded grid do not overlap", k + 1, j + 1);
    }
  }
  return PERI_OK;
}

static int parse_discretization(parse_ctx *c) {
  peri_sim *s = c->s;
  const peri_node *d = peri_deck_get(c->root, "discretization");
  if (!d) return peri_deck_error(c->root, "missing key 'discretization' in the deck");
  TRY(peri_deck_allow(d, "discretization", discretization_keys));
  peri_geometry *g = &s->disc.geom;
  const peri_node *node_file = peri_deck_get(d, "node_file");
  const peri_node *fill = peri_deck_get(d, "fill");
  const peri_node *mesh = peri_deck_get(d, "mesh");
  if (!node_file + !fill + !mesh != 2)
    return peri_deck_error(d, "discretization: give exactly one of 'fill' (shapes on a grid), "
                              "'node_file' (x y [z] block volume) or 'mesh' (an Exodus, Gmsh, Abaqus or text mesh)");
  if (mesh && !node_file) node_file = mesh; /* a file gives the nodes */
  static const char *const grid_only[] = {"placement", "origin", "remove", "max_nodes", NULL};
  if (fill && peri_deck_get(d, "mesh_format"))
    return peri_deck_error(peri_deck_key_node(d, "mesh_format"), "key 'mesh_format': only with 'mesh'");
  for (int k = 0; node_file && grid_only[k]; ++k)
    if (peri_deck_get(d, grid_only[k]))
      return peri_deck_error(peri_deck_key_node(d, grid_only[k]), "key '%s': only with 'fill' (a node "
                             "file gives the node positions)", grid_only[k]);
  if (fill && peri_deck_get(d, "blocks"))
    return peri_deck_error(peri_deck_key_node(d, "blocks"), "key 'blocks': only with 'node_file' or 'mesh' (fill "
                           "shapes name their material)");
  g->spacing = NAN;
  TRY(peri_deck_double(d, "spacing", fill != NULL, &g->spacing));
  double horizon = NAN, m = NAN;
  const bool horizon_expression = peri_setup_horizon_is_field(d); /* an expression of x, y, z (horizon_keys.c) */
  if (!horizon_expression) TRY(peri_deck_double(d, "horizon", false, &horizon));
  TRY(peri_deck_double(d, "m", false, &m));
  bool zone_spacing = false; /* a graded grid: a fill shape with its own spacing */
  for (int k = 0; fill && fill->kind == PERI_NODE_SEQUENCE && k < fill->count; ++k)
    zone_spacing = zone_spacing || peri_deck_get(fill->items[k], "spacing") != NULL;
  /* a horizon per node: an expression, or m times each node's spacing on a graded grid */
  const bool horizon_field = horizon_expression || (zone_spacing && !isnan(m));
  static const char *const field_keys[] = {"partial_stress", "partial_stress_stabilization", "local_stencil", NULL};
  for (int k = 0; !horizon_field && field_keys[k]; ++k)
    if (peri_deck_get(d, field_keys[k]) && !(k == 0 && peri_deck_get(d, field_keys[k])->scalar &&
                                             !strcmp(peri_deck_get(d, field_keys[k])->scalar, "none")))
      return peri_deck_error(peri_deck_key_node(d, field_keys[k]), "key '%s': only with a horizon that varies "
                             "(discretization.horizon an expression of x, y, z, or m on a graded grid)", field_keys[k]);
  if ((isnan(horizon) && !horizon_expression) == isnan(m))
    return peri_deck_error(d, "discretization: give exactly one of 'horizon' (a length) or 'm' "
                              "(horizon / spacing)");
  g->thickness = 1.0;
  g->cross_section = 1.0;
  if (g->dim == 2) TRY(peri_deck_double(d, "thickness", false, &g->thickness));
  else if (peri_deck_get(d, "thickness"))
    return peri_deck_error(peri_deck_key_node(d, "thickness"), "key 'thickness': only for dimension 2");
  if (g->dim == 1) TRY(peri_deck_double(d, "cross_section", false, &g->cross_section));
  else if (peri_deck_get(d, "cross_section"))
    return peri_deck_error(peri_deck_key_node(d, "cross_section"), "key 'cross_section': only for dimension 1");
  if (!(g->thickness > 0.0) || !(g->cross_section > 0.0))
    return peri_deck_error(d, "discretization: thickness and cross_section must be positive");

  static const char *const placements[] = {"centers", "lattice", NULL};
  static const char *const pv_rules[] = {"none", "linear", "lammps", NULL};
  static const char *const influences[] = {"constant", "inverse", "gaussian", NULL};
  static const char *const wv[] = {"discrete", "analytic", NULL};
  int placement = 0, pv = PERI_PV_LINEAR, infl = 0, wvol = 0;
  TRY(peri_deck_choice(d, "placement", false, placements, &placement));
  TRY(peri_deck_choice(d, "partial_volume", false, pv_rules, &pv));
  TRY(peri_deck_choice(d, "influence", false, influences, &infl));
  TRY(peri_deck_choice(d, "weighted_volume", false, wv, &wvol));
  static const char *const corrections[] = {"none", "energy", "volume", "position_aware", NULL}; /* docs/models.md 4.1 */
  int correction = 0;
  TRY(peri_deck_choice(d, "surface_correction", false, corrections, &correction));
  s->disc.surface_correction = correction;
  s->disc.analytic_weighted_volume = wvol == 1;
  s->disc.family.rule = (peri_partial_volume)pv;
  s->disc.family.influence = (peri_influence)infl;

  peri_particles *p = &s->disc.p;
  peri_particles_init(p, g->dim);
  if (fill) {
    if (!(g->spacing > 0.0)) return peri_deck_error(peri_deck_get(d, "spacing"), "key 'spacing': must be positive");
    peri_grid_params gp = {0};
    gp.dim = g->dim;
    gp.spacing = g->spacing;
    gp.placement = (peri_placement)placement;
    gp.thickness = g->thickness;
    gp.cross_section = g->cross_section;
    if (peri_deck_get(d, "origin")) {
      int count = 0;
      TRY(peri_deck_vector_range(d, "origin", true, g->dim, 3, gp.origin, &count));
      gp.origin_given = true;
    }
    if (fill->kind != PERI_NODE_SEQUENCE || fill->count == 0)
      return peri_deck_error(fill, "key 'fill': expected a list of shapes, each with a material");
    gp.n_fill = fill->count;
    gp.fill = peri_calloc(fill->count, sizeof(peri_fill));
    static const char *const fill_extra[] = {"material", "spacing", NULL};
    int rc = PERI_OK;
    for (int k = 0; k < fill->count && rc == PERI_OK; ++k) {
      if (peri_setup_is_image_fill(fill->items[k])) { /* image_keys.c */
        rc = peri_setup_image_fill(s, fill->items[k], g->spacing, &gp.fill[k]);
        continue;
      }
      if (peri_setup_is_detachment_fill(fill->items[k])) { /* detachment_keys.c */
        rc = peri_setup_detachment_fill(s, fill->items[k], g->spacing, &gp.fill[k]);
        continue;
      }
      rc = peri_shape_parse(fill->items[k], g->dim, "discretization.fill", fill_extra, &gp.fill[k].shape);
      if (rc == PERI_OK) rc = peri_deck_double(fill->items[k], "spacing", false, &gp.fill[k].spacing);
      if (rc == PERI_OK && peri_deck_get(fill->items[k], "spacing") && !(gp.fill[k].spacing > 0.0))
        rc = peri_deck_error(peri_deck_get(fill->items[k], "spacing"), "key 'spacing': must be positive");
      if (rc != PERI_OK) break;
      const char *mname = NULL;
      if (s->mat.n_materials == 1 && !peri_deck_get(fill->items[k], "material")) {
        gp.fill[k].material = 0;
        continue;
      }
      rc = peri_deck_string(fill->items[k], "material", true, &mname);
      if (rc != PERI_OK) break;
      if (!strcmp(mname, "void")) { /* a hole over the shapes before it: a void defect (docs/microstructures.md) */
        gp.fill[k].material = PERI_PHASE_VOID;
        continue;
      }
      int mi = peri_setup_find_material(s, peri_deck_get(fill->items[k], "material"), mname);
      if (mi < 0) rc = -mi;
      else gp.fill[k].material = mi;
    }
    const peri_node *remove = peri_deck_get(d, "remove");
    if (rc == PERI_OK && remove)
      rc = parse_shape_list(remove, g->dim, "discretization.remove", NULL, &gp.remove, &gp.n_remove);
    if (rc == PERI_OK && peri_grid_is_graded(&gp)) rc = check_graded_zones(d, fill, &gp);
    if (rc == PERI_OK) rc = check_grid_size(d, &gp, !isnan(m) ? m : horizon_field ? 3.0 : horizon / g->spacing);
    for (int k = 0; k < gp.n_fill && rc == PERI_OK; ++k) /* the finest zone's: ordering, partial volumes */
      if (gp.fill[k].spacing > 0.0) g->spacing = fmin(g->spacing, gp.fill[k].spacing);
    if (rc == PERI_OK && peri_grid_generate(p, &gp) < 0) rc = PERI_ERR_INPUT;
    if (rc == PERI_OK) g->lattice = peri_grid_exact_axes(&gp, p, g->lattice_axis);
    for (int k = 0; k < gp.n_fill; ++k) {
      peri_shape_free(&gp.fill[k].shape);
      peri_phase_map_free(gp.fill[k].phases);
      free(gp.fill[k].phases);
      free(gp.fill[k].detachment);
    }
    for (int k = 0; k < gp.n_remove; ++k) peri_shape_free(&gp.remove[k]);
    free(gp.fill);
    free(gp.remove);
    if (rc != PERI_OK) return rc;
  } else {
    TRY(peri_setup_mesh(s, d, &c->mesh)); /* src/deck/mesh_keys.c */
    if (isnan(g->spacing)) {
      /* mean node spacing from the volumes */
      double vsum = 0.0;
      for (int32_t i = 0; i < p->n; ++i) vsum += p->volume[i];
      double v = vsum / (p->n > 0 ? p->n : 1);
      if (g->dim == 2) v /= g->thickness;
      if (g->dim == 1) v /= g->cross_section;
      g->spacing = pow(v, 1.0 / g->dim);
    }
  }
  if (p->n == 0) return peri_deck_error(d, "discretization: the shapes contain no nodes");
  double volume = NAN;
  TRY(peri_deck_double(d, "volume", false, &volume));
  if (!isnan(volume)) {
    if (!(volume > 0.0)) return peri_deck_error(peri_deck_get(d, "volume"), "key 'volume': must be positive");
    for (int32_t i = 0; i < p->n; ++i) p->volume[i] = volume;
  }
  if (!horizon_field) {
    g->horizon = isnan(horizon) ? m * g->spacing : horizon;
    if (!(g->horizon > 0.0)) return peri_deck_error(d, "discretization: the horizon must be positive");
    s->disc.family.horizon = g->horizon;
  }
  s->disc.family.spacing = g->spacing;
  TRY(peri_setup_graded_mesh(s, c->root, &c->fem_mesh)); /* coupling.graded_mesh (coupling_keys.c) */

  /* order along a space-filling curve so that neighbours are near in memory */
  int32_t *perm = peri_malloc(sizeof(int32_t) * p->n);
  peri_sfc_order(p, g->spacing, perm);
  peri_particles_permute(p, perm);
  if (c->mesh.n > 0) { /* the regions name mesh points */
    c->node_of_point = peri_malloc(sizeof(int32_t) * (size_t)p->n);
    for (int32_t k = 0; k < p->n; ++k) c->node_of_point[perm[k]] = k;
  }
  peri_fem_mesh_permute(&c->fem_mesh, perm);
  free(perm);
  if (horizon_field) {
    if (peri_setup_heat_only(c->root))
      return peri_deck_error(peri_deck_get(d, "horizon"), "key 'horizon': a horizon that varies is for mechanical runs");
    TRY(peri_setup_horizon_field(s, d)); /* after the ordering: per node */
  }
  peri_particles_alloc_state(p);
  return PERI_OK;
}

/* ---------------------------------------------------------------- regions, cracks */

static int parse_regions(parse_ctx *c) { /* src/deck/region_keys.c */
  return peri_setup_regions(c->s, c->root, c->mesh.n > 0 ? &c->mesh : NULL, c->node_of_point);
}

static int parse_precracks(parse_ctx *c) {
  peri_sim *s = c->s;
  const peri_node *list = peri_deck_get(c->root, "precracks");
  if (!list) return PERI_OK;
  if (list->kind != PERI_NODE_SEQUENCE)
    return peri_deck_error(list, "key 'precracks': expected a list, got %s", peri_deck_kind_name(list));
  s->cond.n_precracks = list->count;
  s->cond.precracks = peri_calloc(list->count, sizeof(peri_precrack));
  for (int k = 0; k < list->count; ++k) {
    const peri_node *it = list->items[k];
    peri_precrack *pc = &s->cond.precracks[k];
    if (s->disc.geom.dim == 2) {
      static const char *const keys[] = {"from", "to", NULL};
      TRY(peri_deck_allow(it, "precracks", keys));
      TRY(peri_deck_vector(it, "from", true, 2, pc->a));
      TRY(peri_deck_vector(it, "to", true, 2, pc->b));
      pc->dim = 2;
      if (pc->a[0] == pc->b[0] && pc->a[1] == pc->b[1])
        return peri_deck_error(it, "precracks: 'from' and 'to' are the same point (the crack has no length)");
    } else if (s->disc.geom.dim == 3) {
      static const char *const keys[] = {"corner", "edge1", "edge2", NULL};
      TRY(peri_deck_allow(it, "precracks", keys));
      TRY(peri_deck_vector(it, "corner", true, 3, pc->a));
      TRY(peri_deck_vector(it, "edge1", true, 3, pc->e1));
      TRY(peri_deck_vector(it, "edge2", true, 3, pc->e2));
      pc->dim = 3;
      /* the cut test projects onto the edges, which is the rectangle only for perpendicular ones */
      double l1 = 0.0, l2 = 0.0, dot = 0.0;
      for (int d = 0; d < 3; ++d) l1 += pc->e1[d] * pc->e1[d], l2 += pc->e2[d] * pc->e2[d], dot += pc->e1[d] * pc->e2[d];
      if (l1 == 0.0 || l2 == 0.0)
        return peri_deck_error(it, "precracks: edge%d has zero length", l1 == 0.0 ? 1 : 2);
      if (fabs(dot) > 1e-9 * sqrt(l1 * l2))
        return peri_deck_error(it, "precracks: edge1 and edge2 must be perpendicular (the crack is a rectangle; "
                               "the angle between them is %g degrees)", acos(dot / sqrt(l1 * l2)) * 180.0 / M_PI);
    } else {
      return peri_deck_error(it, "precracks: not available in 1D (remove nodes instead)");
    }
  }
  return PERI_OK;
}

/* ---------------------------------------------------------------- conditions */

static const char *const component_keys[] = {"x", "y", "z"};

static int parse_components(const peri_sim *s, const peri_node *it, peri_expr *value[3], bool need) {
  int given = 0;
  for (int d = 0; d < 3; ++d) {
    const peri_node *v = peri_deck_get(it, component_keys[d]);
    if (!v) continue;
    if (d >= s->disc.geom.dim)
      return peri_deck_error(peri_deck_key_node(it, component_keys[d]),
                             "key '%s': the problem has dimension %d", component_keys[d], s->disc.geom.dim);
    TRY(peri_deck_expr(it, component_keys[d], true, &value[d]));
    given++;
  }
  if (need && given == 0) return peri_deck_error(it, "boundary condition: give at least one of x, y, z");
  return PERI_OK;
}

static int parse_conditions(parse_ctx *c) {
  peri_sim *s = c->s;
  const peri_node *list = peri_deck_get(c->root, "boundary_conditions");
  if (!list) return PERI_OK;
  if (list->kind != PERI_NODE_SEQUENCE)
    return peri_deck_error(list, "key 'boundary_conditions': expected a list, got %s", peri_deck_kind_name(list));
  static const char *const kinds[] = {"displacement", "velocity", "initial_displacement",
                                      "initial_velocity", "body_force", "traction", "temperature",
                                      "heat_flux", "convection", "heat_source", "initial_temperature", NULL};
  static const char *const keys[] = {"type", "region", "x", "y", "z", "layer", NULL};
  s->cond.bcs = peri_calloc(list->count, sizeof(peri_bc));
  for (int k = 0; k < list->count; ++k) {
    const peri_node *it = list->items[k];
    if (peri_setup_is_thermal_bc(it)) continue; /* parsed by peri_setup_thermal */
    TRY(peri_deck_allow(it, "boundary_conditions", keys));
    peri_bc *bc = &s->cond.bcs[s->cond.n_bcs++];
    int kind = 0;
    TRY(peri_deck_choice(it, "type", true, kinds, &kind));
    bc->kind = (peri_bc_kind)kind;
    const char *rname = NULL;
    if (!peri_deck_get(it, "region")) /* the whole body only when the deck says so (docs/deck.md) */
      return peri_deck_error(it, "boundary condition '%s' has no 'region': name one, or write 'region: all' to "
                                 "apply it to the whole body", kinds[kind]);
    TRY(peri_deck_string(it, "region", true, &rname));
    int r = peri_setup_find_region(s, peri_deck_get(c->root, "regions"), peri_deck_get(it, "region"), rname);
    if (r < 0) return -r;
    bc->region = r;
    TRY(parse_components(s, it, bc->value, true));
    bc->layer = s->disc.geom.spacing;
    if (peri_deck_get(it, "layer")) {
      if (bc->kind != PERI_BC_TRACTION)
        return peri_deck_error(peri_deck_key_node(it, "layer"), "key 'layer': only for type traction");
      TRY(peri_deck_double(it, "layer", true, &bc->layer));
      if (!(bc->layer > 0.0)) return peri_deck_error(peri_deck_get(it, "layer"), "key 'layer': must be positive");
    }
  }
  return PERI_OK;
}

static int parse_indenter(parse_ctx *c) {
  peri_sim *s = c->s;
  const peri_node *it = peri_deck_get(c->root, "indenter");
  if (!it) return PERI_OK;
  static const char *const keys[] = {"radius", "stiffness", "center", NULL};
  TRY(peri_deck_allow(it, "indenter", keys));
  peri_indenter *ind = &s->cond.indenter;
  ind->on = true;
  TRY(peri_deck_double(it, "radius", true, &ind->radius));
  TRY(peri_deck_double(it, "stiffness", true, &ind->stiffness));
  const peri_node *center = peri_deck_get(it, "center");
  if (!center) return peri_deck_error(it, "missing key 'center' in indenter");
  if (center->kind != PERI_NODE_SEQUENCE || center->count != s->disc.geom.dim)
    return peri_deck_error(center, "key 'center': expected a list of %d numbers or expressions of t",
                           s->disc.geom.dim);
  for (int d = 0; d < center->count; ++d) TRY(peri_deck_node_expr(center->items[d], "center", &ind->center[d]));
  if (!(ind->radius > 0.0) || !(ind->stiffness > 0.0))
    return peri_deck_error(it, "indenter: radius and stiffness must be positive");
  return PERI_OK;
}

/* ---------------------------------------------------------------- solver, output */

static int parse_solver(parse_ctx *c) {
  peri_sim *s = c->s;
  const peri_node *it = peri_deck_get(c->root, "solver");
  if (!it) return peri_deck_error(c->root, "missing key 'solver' in the deck");
  static const char *const keys[] = {"type", "steps", "end_time", "time_step", "safety_factor",
                                     "damping", "breaking", "breaking_order", PERI_QUASI_STATIC_KEYS, NULL};
  static const char *const types[] = {"explicit", "adr", "dynamic_relaxation", "nlcg", "implicit", "heat", NULL};
  TRY(peri_deck_allow(it, "solver", keys));
  int type = 0;
  TRY(peri_deck_choice(it, "type", false, types, &type));
  s->solver.kind = (peri_solver_kind)type;
  const bool heat = !strcmp(types[type], "heat"); /* conduction only: the explicit keys (docs/heat.md) */
  if (heat) s->solver.kind = PERI_SOLVER_EXPLICIT;
  TRY(peri_quasi_static_parse(s, it)); /* quasi-static keys (docs/solvers.md) */
  /* when a bond breaks within a force evaluation (docs/models.md 5.1) */
  static const char *const orders[] = {"before_force", "after_force", NULL};
  int order = 0;
  TRY(peri_deck_choice(it, "breaking_order", false, orders, &order));
  if (order == 1 && (s->solver.kind != PERI_SOLVER_EXPLICIT || heat))
    return peri_deck_error(peri_deck_get(it, "breaking_order"),
                           "key 'breaking_order': after_force is for the explicit solver only (a quasi-static "
                           "solver re-solves after every break)");
  s->solver.break_after_force = order == 1;
  if (s->solver.kind != PERI_SOLVER_EXPLICIT) return PERI_OK;
  long steps = -1;
  double end_time = NAN;
  TRY(peri_deck_int(it, "steps", false, &steps));
  TRY(peri_deck_double(it, "end_time", false, &end_time));
  if ((steps < 0) == isnan(end_time))
    return peri_deck_error(it, "solver: give exactly one of 'steps' or 'end_time'");
  if (steps < 0 && !(end_time > 0.0)) return peri_deck_error(peri_deck_get(it, "end_time"), "key 'end_time': must be positive");
  s->solver.steps = steps;
  s->solver.end_time = end_time;
  s->solver.dt_given = 0.0;
  s->solver.safety_factor = 0.8;
  TRY(peri_deck_double(it, "time_step", false, &s->solver.dt_given));
  TRY(peri_deck_double(it, "safety_factor", false, &s->solver.safety_factor));
  TRY(peri_deck_double(it, "damping", false, &s->solver.damping));
  if (peri_deck_get(it, "time_step") && !(s->solver.dt_given > 0.0))
    return peri_deck_error(peri_deck_get(it, "time_step"), "key 'time_step': must be positive");
  if (!(s->solver.safety_factor > 0.0 && s->solver.safety_factor <= 1.0))
    return peri_deck_error(peri_deck_get(it, "safety_factor"), "key 'safety_factor': must be in (0, 1]");
  if (s->solver.damping < 0.0) return peri_deck_error(peri_deck_get(it, "damping"), "key 'damping': must be >= 0");
  s->solver.breaking = true;
  TRY(peri_deck_bool(it, "breaking", false, &s->solver.breaking));
  if (heat) s->solver.kind = PERI_SOLVER_HEAT;
  return PERI_OK;
}

static int parse_output(parse_ctx *c) {
  peri_sim *s = c->s;
  peri_output *o = &s->out;
  const peri_node *it = peri_deck_get(c->root, "output");
  static const char *const keys[] = {"directory", "every", "frames", "fields", "compress",
                                     "history_every", "history_digits", "picture", "plot", "checkpoint_every",
                                     "checkpoint_file", "format", "phase_stress",
                                     "interface_history", "region_energy", "wrinkles", "dataset", "penetration", NULL};
  /* defaults */
  const char *base = strrchr(s->deck_path, '/');
  base = base ? base + 1 : s->deck_path;
  o->basename = peri_strdup(base);
  char *dot = strrchr(o->basename, '.');
  if (dot) *dot = '\0';
  o->compress = true;
  o->picture = s->disc.geom.dim >= 2; /* 3D: a slice through the middle (docs/output.md) */
  o->picture_normal = 2;
  o->vtu = true;
  o->picture_field = peri_strdup("damage");
  o->picture_width = 1200;
  o->progress_every = 10.0; /* seconds between progress lines off a terminal (--progress) */
  long every = -1, frames = -1, history_every = -1, history_digits = 10;
  const char *dir = NULL;
  if (it) {
    TRY(peri_deck_allow(it, "output", keys));
    TRY(peri_deck_string(it, "directory", false, &dir));
    TRY(peri_deck_int(it, "every", false, &every));
    TRY(peri_deck_int(it, "frames", false, &frames));
    TRY(peri_deck_int(it, "history_every", false, &history_every));
    TRY(peri_deck_bool(it, "compress", false, &o->compress));
    TRY(peri_output_format_parse(s, it)); /* output.format (src/deck/output_keys.c) */
    if (every >= 0 && frames >= 0) return peri_deck_error(it, "output: give only one of 'every' or 'frames'");
    if (peri_deck_get(it, "every") && every < 1) return peri_deck_error(peri_deck_get(it, "every"), "key 'every': must be >= 1");
    if (peri_deck_get(it, "frames") && frames < 0) return peri_deck_error(peri_deck_get(it, "frames"), "key 'frames': must be >= 0");
    if (peri_deck_get(it, "history_every") && history_every < 1)
      return peri_deck_error(peri_deck_get(it, "history_every"), "key 'history_every': must be >= 1");
    TRY(peri_deck_int(it, "history_digits", false, &history_digits));
    if (history_digits < 1 || history_digits > 17)
      return peri_deck_error(peri_deck_get(it, "history_digits"), "key 'history_digits': must be from 1 to 17");
    const peri_node *fields = peri_deck_get(it, "fields");
    if (fields) {
      if (fields->kind != PERI_NODE_SEQUENCE)
        return peri_deck_error(fields, "key 'fields': expected a list of field names");
      o->fields = peri_calloc(fields->count, sizeof(char *));
      for (int k = 0; k < fields->count; ++k) {
        const peri_node *f = fields->items[k];
        int which = -1;
        for (int n = 0; peri_frame_fields[n] && f->scalar; ++n)
          if (strcmp(peri_frame_fields[n], f->scalar) == 0) which = n;
        if (which < 0) {
          int best = 0, best_d = 1 << 30;
          for (int n = 0; peri_frame_fields[n]; ++n) {
            int dd = f->scalar ? peri_edit_distance(f->scalar, peri_frame_fields[n]) : 99;
            if (dd < best_d) best_d = dd, best = n;
          }
          char list[1024] = "";
          for (int n = 0; peri_frame_fields[n]; ++n)
            snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", n ? ", " : "", peri_frame_fields[n]);
          return peri_deck_error(f, "unknown output field '%s'; did you mean '%s'? (fields: %s)",
                                 f->scalar ? f->scalar : "", peri_frame_fields[best], list);
        }
        if (!strcmp(f->scalar, "dilatation") && s->mat.model != peri_model_find("lps") &&
            s->mat.model != peri_model_find("osb_mo"))
          return peri_deck_error(f, "output field 'dilatation': the %s model has no dilatation", s->mat.model->name);
        if (!strcmp(f->scalar, "horizon") && !s->disc.horizon_field)
          return peri_deck_error(f, "output field 'horizon': only with a horizon that varies (discretization.horizon "
                                    "an expression of x, y, z)");
        o->fields[o->n_fields++] = peri_strdup(f->scalar);
      }
    }
    TRY(peri_deck_bool(it, "phase_stress", false, &o->phase_stress)); /* before the plot names its columns */
    TRY(peri_setup_film_output(s, c->root, it)); /* interfaces, regions, wrinkles (film_keys.c) */
    TRY(peri_plot_parse(s, it)); /* output.plot (src/deck/plot_keys.c) */
    TRY(peri_checkpoint_parse(s, it)); /* output.checkpoint_* (src/deck/checkpoint_keys.c) */
    TRY(peri_dataset_parse(s, it)); /* output.dataset (src/deck/dataset_keys.c) */
    const peri_node *pic = peri_deck_get(it, "picture");
    if (pic && pic->kind == PERI_NODE_MAPPING) {
      static const char *const pkeys[] = {"field", "width", "view", "normal", "at", NULL};
      TRY(peri_deck_allow(pic, "output.picture", pkeys));
      int which = 3;
      TRY(peri_deck_choice(pic, "field", false, peri_frame_fields, &which));
      if (!strcmp(peri_frame_fields[which], "dilatation") && s->mat.model != peri_model_find("lps") &&
          s->mat.model != peri_model_find("osb_mo"))
        return peri_deck_error(peri_deck_get(pic, "field"), "picture field 'dilatation': the %s model has no "
                               "dilatation", s->mat.model->name);
      free(o->picture_field);
      o->picture_field = peri_strdup(peri_frame_fields[which]);
      long width = o->picture_width;
      TRY(peri_deck_int(pic, "width", false, &width));
      if (width < 64 || width > 10000) return peri_deck_error(peri_deck_get(pic, "width"), "key 'width': must be in 64..10000 pixels");
      o->picture_width = (int)width;
      o->picture = true;
      TRY(peri_picture_view_parse(s, pic)); /* output.picture view, normal, at (src/deck/output_keys.c) */
    } else if (pic) {
      TRY(peri_deck_bool(it, "picture", false, &o->picture));
    }
    if (o->picture && s->disc.geom.dim < 2) {
      const peri_node *at = pic ? pic : it;
      return peri_deck_error(at, "key 'picture': pictures are drawn for 2D and 3D problems only");
    }
  }
  if (!o->fields) {
    static const char *const defaults[] = {"displacement", "velocity", "damage"};
    o->fields = peri_calloc(3, sizeof(char *));
    for (int k = 0; k < 3; ++k) o->fields[o->n_fields++] = peri_strdup(defaults[k]);
  }
  if (dir) o->directory = peri_strdup(dir);
  else {
    char buf[4096];
    snprintf(buf, sizeof buf, "output/%s", o->basename);
    o->directory = peri_strdup(buf);
  }
  o->every = every >= 1 ? every : 0;
  if (frames >= 0) o->every = -frames; /* resolved once the step count is known */
  o->history_every = history_every >= 1 ? history_every : 0;
  o->history_digits = (int)history_digits;
  return peri_checkpoint_check_names(s, c->root); /* src/deck/checkpoint_names.c */
}

/* ---------------------------------------------------------------- assembly */

static const char *const top_keys[] = {"dimension", "plane", "discretization", "materials",
                                       "interfaces", "regions", "precracks", "boundary_conditions",
                                       "indenter", "solver", "output", "thermal", "coupling", "contact",
                                       "bodies", "imperfection", "body_interfaces", "tools", "j_integral", NULL};

/* A count derived from the ratio of two deck numbers, such as end_time / time_step. The
 * ratio is rounded up (less a rounding allowance); a count that a long cannot hold is an
 * input error at `at`, not a negative step count. */
static int step_count(const peri_node *at, const char *ratio_name, const char *count_name,
                      const char *remedy, double ratio, long *out) {
  const double count = ceil(ratio - 1e-9);
  if (!(count < 9223372036854775808.0)) /* 2^63: LONG_MAX + 1, exact as a double */
    return peri_deck_error(at, "%s = %.3g %s, more than the largest count %ld; %s", ratio_name,
                           count, count_name, LONG_MAX, remedy);
  *out = (long)count;
  return PERI_OK;
}

/* Coupled heat conduction advances in sub-steps of thermal.time_step; their number over
 * the run must be countable too (src/solver/heat.c counts them in a long). */
static int check_heat_substeps(const peri_sim *s, const peri_node *root) {
  const peri_thermal *th = s->thermal;
  if (!th || s->solver.kind == PERI_SOLVER_HEAT || !(th->dt > 0.0)) return PERI_OK;
  const peri_node *thermal = peri_deck_get(root, "thermal");
  const peri_node *at = peri_deck_get(thermal, "time_step");
  long ignored;
  return step_count(at ? at : thermal, "run time / thermal time_step", "heat sub-steps",
                    "use a longer thermal time_step or a shorter run", (double)s->solver.steps * (s->solver.dt / th->dt), &ignored);
}

static int build(parse_ctx *c) {
  peri_sim *s = c->s;
  const peri_node *root = c->root;
  TRY(peri_deck_allow(root, "the deck", top_keys));
  long dim = 0;
  TRY(peri_deck_int(root, "dimension", true, &dim));
  if (dim < 1 || dim > 3) return peri_deck_error(peri_deck_get(root, "dimension"), "key 'dimension': expected 1, 2 or 3, got %ld", dim);
  s->disc.geom.dim = (int)dim;
  static const char *const planes[] = {"stress", "strain", NULL};
  if (dim == 2) {
    int plane = 0;
    TRY(peri_deck_choice(root, "plane", false, planes, &plane));
    s->disc.geom.plane = plane == 0 ? PERI_PLANE_STRESS : PERI_PLANE_STRAIN;
  } else if (peri_deck_get(root, "plane")) {
    return peri_deck_error(peri_deck_key_node(root, "plane"), "key 'plane': only for dimension 2");
  }
  const bool heat_only = peri_setup_heat_only(root);
  TRY(parse_materials(c));
  TRY(parse_discretization(c));
  if (!heat_only) TRY(check_osb_mo(c));
  if (!heat_only) TRY(resolve_materials(c));
  if (!heat_only) TRY(peri_setup_plasticity(s, root)); /* sublayers (plasticity_keys.c, docs/plasticity.md) */
  TRY(parse_regions(c));
  TRY(peri_setup_fictitious_layers(s, root)); /* discretization.fictitious_layers (layer_keys.c) */
  peri_bonds_build(&s->disc.bonds, &s->disc.p, &s->disc.family);
  TRY(peri_setup_bodies(s, root)); /* no bonds across bodies (docs/contact.md) */
  if (s->disc.horizon_field) { /* the coupling region and the per-node models (horizon_keys.c) */
    bool from_energy[s->mat.n_materials];
    for (int m = 0; m < s->mat.n_materials; ++m) from_energy[m] = !isnan(c->failure[m].G0) || !isnan(c->failure[m].KIc);
    TRY(peri_setup_horizon_coupling(s, root, from_energy));
  }
  TRY(parse_precracks(c));
  peri_precracks_apply(s);
  TRY(peri_setup_horizon_precracks(s, root)); /* none into the local region (horizon_keys.c) */
  if (!heat_only) TRY(parse_interfaces(c));
  TRY(peri_setup_imperfection(s, root)); /* a film's offset reference positions (film_keys.c) */
  TRY(s->mat.model->init(s));
  TRY(parse_conditions(c));
  TRY(peri_setup_check_layers(c->s, c->root));
  TRY(peri_setup_check_fictitious_layers(c->s, c->root));
  TRY(parse_indenter(c));
  TRY(parse_solver(c));
  if (s->solver.kind == PERI_SOLVER_IMPLICIT && s->mat.model == peri_model_find("osb_mo")) {
    const peri_node *solver = peri_deck_get(c->root, "solver");
    return peri_deck_error(solver ? peri_deck_get(solver, "type") : c->root, "solver.type implicit: the %s model has "
                           "no tangent stiffness (use nlcg, adr or dynamic_relaxation)", s->mat.model->name);
  }
  if (s->mat.pair_strength && !peri_is_quasi_static(s)) /* the criterion runs between load steps */
    return peri_deck_error(peri_deck_get(root, "interfaces"), "interfaces: normal_strength needs a quasi-static "
                           "solver (solver.type nlcg, adr, dynamic_relaxation or implicit)");
  TRY(peri_setup_coupling(s, root, &c->fem_mesh)); /* PD-FEM coupling (src/deck/coupling_keys.c) */
  TRY(peri_setup_horizon_solver(s, root)); /* horizon_keys.c */
  TRY(peri_setup_contact(s, root)); /* short-range forces (docs/contact.md) */
  TRY(peri_setup_tools(s, root)); /* rigid tools (tool_keys.c, docs/contact.md) */
  TRY(peri_setup_plasticity_solver(s, root));
  TRY(peri_setup_j_integral(s, root)); /* J-integral columns (j_integral_keys.c, docs/plasticity.md) */
  TRY(parse_output(c));
  TRY(peri_setup_penetration(s, root)); /* output.penetration of bodies (body_keys.c, docs/contact.md) */
  TRY(peri_setup_thermal(s, root)); /* heat conduction, thermal strain (docs/heat.md) */
  TRY(peri_plot_check(s, peri_deck_get(root, "output"))); /* the columns, thermal ones included */

  /* lammps-form critical stretch: s0 starts unbounded (no breaking in the first step) */
  bool lammps = false;
  for (int m = 0; m < s->mat.n_materials; ++m) lammps |= s->mat.materials[m].lammps_s0;
  if (lammps) {
    for (int m = 0; m < s->mat.n_materials; ++m)
      if (!s->mat.materials[m].lammps_s0)
        return peri_deck_error(c->failure[m].at, "materials.%s: when one material uses the "
                               "{s00, alpha} critical stretch, all must", s->mat.materials[m].name);
    s->mat.s0_node = peri_malloc(sizeof(double) * s->disc.p.n);
    s->disc.p.smin = peri_malloc(sizeof(double) * s->disc.p.n);
    for (int32_t i = 0; i < s->disc.p.n; ++i) s->mat.s0_node[i] = INFINITY;
  }
  s->cond.prescribed = peri_calloc(3 * (size_t)s->disc.p.n, 1);

  /* time step and step count */
  const double dt_estimate = s->solver.kind == PERI_SOLVER_HEAT ? peri_thermal_stable_dt(s->thermal) : peri_stable_dt(s);
  double dt_stable = s->solver.safety_factor * dt_estimate;
  if (s->solver.dt_given > 0.0) {
    s->solver.dt = s->solver.dt_given;
    if (s->solver.dt > dt_estimate)
      peri_warning("time_step %g exceeds the stable estimate %g; the run may diverge", s->solver.dt,
                   dt_estimate);
  } else {
    s->solver.dt = dt_stable;
  }
  if (!(s->solver.dt > 0.0) || !isfinite(s->solver.dt))
    return peri_deck_error(peri_deck_get(root, "solver"), "solver: cannot estimate a time step (no bonds?); give time_step");
  if (s->solver.steps < 0) {
    const peri_node *solver = peri_deck_get(root, "solver");
    TRY(step_count(peri_deck_get(solver, "end_time"), "end_time / time_step", "steps",
                   "use a longer time step or a shorter end time", s->solver.end_time / s->solver.dt, &s->solver.steps));
  }
  TRY(check_heat_substeps(s, root));
  if (s->out.every < 0) {
    long frames = -s->out.every; /* frames per run, rounded up; steps + frames could overflow */
    s->out.every = frames > 0 ? s->solver.steps / frames + (s->solver.steps % frames != 0) : 0;
  } else if (s->out.every == 0 && !peri_deck_get(peri_deck_get(root, "output"), "every") &&
             !peri_deck_get(peri_deck_get(root, "output"), "frames")) { /* (frames: 0, the first and last only) */
    s->out.every = s->solver.steps >= 10 ? s->solver.steps / 10 : 1;
  }
  if (s->out.history_every == 0)  /* quasi-static: a row per load step */
    s->out.history_every = s->solver.steps >= 100 && (s->solver.kind == PERI_SOLVER_EXPLICIT || s->solver.kind == PERI_SOLVER_HEAT)
                               ? s->solver.steps / 100 : 1;
  return PERI_OK;
}

static int from_tree(peri_sim *s, peri_node *root, int n_sets, const char *const *sets);

int peri_sim_from_deck(peri_sim *s, const char *path) { return peri_sim_from_deck_with(s, path, 0, NULL); }

int peri_sim_from_deck_with(peri_sim *s, const char *path, int n_sets, const char *const *sets) {
  memset(s, 0, sizeof *s);
  s->deck_path = peri_strdup(path);
  s->par.threads = 0;
  return from_tree(s, peri_deck_load(path), n_sets, sets);
}

int peri_sim_from_string_with(peri_sim *s, const char *text, const char *name, int n_sets, const char *const *sets) {
  memset(s, 0, sizeof *s);
  s->deck_path = peri_strdup(name);
  s->par.threads = 0;
  return from_tree(s, peri_deck_parse_string(text, name), n_sets, sets);
}

/* The simulation of a deck's tree (NULL: the deck could not be read, after a message), with
 * the --set overrides applied first; frees the tree. */
static int from_tree(peri_sim *s, peri_node *root, int n_sets, const char *const *sets) {
  if (!root) return PERI_ERR_INPUT;
  peri_node **keep = NULL; /* --set overrides (src/deck/overrides.c) */
  int rc = peri_deck_apply_overrides(root, n_sets, sets, &keep);
  parse_ctx c = {.s = s, .root = root, .failure = NULL};
  if (rc == PERI_OK) rc = build(&c);
  free(c.failure);
  peri_mesh_free(&c.mesh);
  free(c.node_of_point);
  peri_fem_mesh_free(&c.fem_mesh);
  peri_deck_free(root);
  peri_overrides_free(keep, n_sets);
  return rc;
}

void peri_sim_free(peri_sim *s) {
  peri_decomposition_free(s->par.dd); /* distributed runs (src/parallel/decompose.c) */
  free(s->par.reach_offset);
  free(s->par.reach_node);
  peri_particles_free(&s->disc.p);
  peri_bonds_free(&s->disc.bonds);
  peri_horizon_field_free(s->disc.horizon_field);
  peri_node_blocks_free(s->disc.node_blocks);
  for (int m = 0; m < s->mat.n_materials; ++m) free(s->mat.materials[m].name), free(s->mat.materials[m].sublayers);
  free(s->mat.materials);
  free(s->mat.pair_s0);
  free(s->mat.pair_strength);
  peri_interface_moduli_free(s);
  free(s->mat.s0_node);
  peri_thermal_free(s->thermal);
  peri_coupling_free(s->coupling);
  free(s->coupling);
  free(s->state.thermal_strain);
  free(s->state.plastic_stretch);
  free(s->state.plastic_committed);
  free(s->state.plastic_nodes);
  free(s->state.plastic_reverse);
  peri_tensor_free(s->state.plastic_tensor);
  free(s->state.plastic_bond_term);
  free(s->state.plastic_slots.item_slot);
  free(s->state.plastic_slots.bond_slot);
  free(s->state.plastic_slots.entry_reverse);
  free(s->state.plastic_bond_weight);
  for (int r = 0; r < s->cond.n_regions; ++r) peri_region_free(&s->cond.regions[r]);
  free(s->cond.regions);
  for (int k = 0; k < s->cond.n_bcs; ++k)
    for (int d = 0; d < 3; ++d) peri_expr_free(s->cond.bcs[k].value[d]);
  free(s->cond.bcs);
  free(s->cond.precracks);
  for (int d = 0; d < 3; ++d) peri_expr_free(s->cond.indenter.center[d]);
  free(s->cond.indenter.block_force);
  peri_contact_free(s->contact);
  peri_bodies_free(s->bodies);
  peri_tools_free(s->tools);
  free(s->cond.prescribed);
  for (int k = 0; k < s->out.n_fields; ++k) free(s->out.fields[k]);
  free(s->out.fields);
  free(s->out.directory);
  free(s->out.basename);
  free(s->out.picture_field);
  free(s->out.plot_x);
  free(s->out.plot_y);
  peri_expr_free(s->out.plot_reference);
  free(s->out.j_integral);
  free(s->out.checkpoint_file);
  peri_dataset_output_free(s->out.dataset);
  free(s->state.step_load);
  peri_restart_free(s->state.restart);
  free(s->deck_path);
  memset(s, 0, sizeof *s);
}
