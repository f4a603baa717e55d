/* The coupling section of the deck (docs/coupling.md, docs/deck.md): which nodes are PD, the
 * micromodulus family of the PD side, and the solver settings the coupled stiffness needs. */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include "peri/coupling.h"
#include "peri/error.h"
#include "peri/fem_mesh.h"
#include "peri/implicit.h"
#include "peri/mesh.h"
#include "peri/setup.h"
#include "setup_parts.h"

#define TRY(expr)                   \
  do {                              \
    int rc_ = (expr);               \
    if (rc_ != PERI_OK) return rc_; \
  } while (0)

/* What the crack growth of the coupled model (src/fem/switching.c) does not do: switch a node
 * of a state-based PD side (its tangent row is kept from the start), break the lattice
 * families of the exact partial volumes, the {s00, alpha} critical stretch, the explicit
 * phases of dynamic_switch, and restart (the node types are not in the checkpoint). */
static int check_fracture(const peri_sim *s, const peri_node *root, const peri_node *cp, bool state_based,
                          bool exact) {
  const peri_node *solver = peri_deck_get(root, "solver"), *breaking = peri_deck_get(solver, "breaking");
  if (state_based)
    return peri_deck_error(breaking, "key 'breaking': crack growth with switching needs the bond-based PD side "
                                     "(model pmb); model %s keeps its linearised rows", s->mat.model->name);
  if (exact)
    return peri_deck_error(peri_deck_get(cp, "partial_volume"), "key 'partial_volume': exact families are not "
                                                                "bonds and cannot break; use discretization with "
                                                                "solver.breaking");
  for (int m = 0; m < s->mat.n_materials; ++m)
    if (s->mat.materials[m].lammps_s0)
      return peri_deck_error(breaking, "key 'breaking': the coupled model takes a fixed critical stretch (fracture "
                                       "energy or critical_stretch), not the {s00, alpha} form of material %s",
                             s->mat.materials[m].name);
  if (peri_deck_get(solver, "dynamic_switch"))
    return peri_deck_error(peri_deck_get(solver, "dynamic_switch"), "key 'dynamic_switch': not with a coupling "
                                                                     "(crack growth with switching is quasi-static "
                                                                     "or, with solver.type: explicit, dynamic)");
  const peri_node *every = peri_deck_get(peri_deck_get(root, "output"), "checkpoint_every");
  if (every)
    return peri_deck_error(every, "key 'checkpoint_every': a coupled run with switching cannot restart (the node "
                                  "types are not checkpointed)");
  return PERI_OK;
}

/* coupling.mesh: the FEM part on the elements of a Gmsh file (src/io/gmsh_fem_mesh.c), joined
 * to the PD grid of the fill where its nodes coincide with it (src/fem/file_mesh.c). */
static int setup_file_mesh(peri_sim *s, const peri_node *root, const peri_node *cp, peri_fem_mesh *m) {
  const peri_node *at = peri_deck_get(cp, "mesh"), *d = peri_deck_get(root, "discretization");
  const peri_geometry *g = &s->disc.geom;
  if (peri_deck_get(cp, "graded_mesh"))
    return peri_deck_error(peri_deck_key_node(cp, "graded_mesh"), "key 'graded_mesh': not with coupling.mesh (the "
                                                                  "mesh file is the FEM part)");
  const peri_node *fill = peri_deck_get(d, "fill");
  bool zones = false;
  for (int k = 0; fill && fill->kind == PERI_NODE_SEQUENCE && k < fill->count; ++k)
    zones = zones || peri_deck_get(fill->items[k], "spacing") != NULL;
  if (!fill || zones || peri_setup_horizon_is_field(d) || !(g->horizon > 0.0))
    return peri_deck_error(at, "key 'mesh': needs a uniform grid (discretization.fill with one spacing and one "
                               "horizon): the PD grid the mesh's nodes meet");
  const char *path = NULL, *material_name = NULL;
  TRY(peri_deck_string(cp, "mesh", true, &path));
  TRY(peri_deck_string(cp, "mesh_material", false, &material_name));
  int material = 0;
  if (material_name) {
    material = peri_setup_find_material(s, peri_deck_get(cp, "mesh_material"), material_name);
    if (material < 0) return -material;
  } else if (s->mat.n_materials > 1) {
    return peri_deck_error(at, "key 'mesh': the deck has %d materials; name the mesh's with coupling.mesh_material",
                           s->mat.n_materials);
  }
  char full[4096];
  peri_setup_deck_path(s, path, full, sizeof full);
  peri_fem_mesh_file file;
  if (peri_fem_mesh_file_read(full, g->dim, &file) != PERI_OK) /* the message names the file and the entity */
    return peri_deck_error(at, "key 'mesh': '%s' is not a mesh peri can use (above)", path);
  /* a PD row reaches its bonds (one horizon, two for a state-based tangent) plus half a cell of
   * partial volume: every node within it must be on the PD grid */
  const double reach = (s->mat.model && s->mat.model->tangent_reach == 2 ? 2.0 : 1.0) * g->horizon + g->spacing;
  const double h = g->dim == 2 ? g->thickness : g->dim == 1 ? g->cross_section : 1.0;
  char why[1024];
  int rc = peri_fem_mesh_from_file(&s->disc.p, g->spacing, reach, h, material, &file, m, why, sizeof why);
  peri_fem_mesh_file_free(&file);
  if (rc != PERI_OK) return peri_deck_error(at, "coupling.mesh: %s", why);
  return PERI_OK;
}

int peri_setup_graded_mesh(peri_sim *s, const peri_node *root, peri_fem_mesh *m) {
  const peri_node *cp = peri_deck_get(root, "coupling"), *gm = peri_deck_get(cp, "graded_mesh");
  if (peri_deck_get(cp, "mesh")) return setup_file_mesh(s, root, cp, m);
  if (!gm) return PERI_OK;
  const peri_node *at = peri_deck_key_node(cp, "graded_mesh"), *d = peri_deck_get(root, "discretization");
  static const char *const keys[] = {"fine", "levels", "layers", NULL};
  TRY(peri_deck_allow(gm, "coupling.graded_mesh", keys));
  if (s->disc.geom.dim != 2)
    return peri_deck_error(at, "key 'graded_mesh': 2D only (a graded mesh of Q4 elements and triangles)");
  const peri_node *fill = peri_deck_get(d, "fill");
  bool zones = false;
  for (int k = 0; fill && fill->kind == PERI_NODE_SEQUENCE && k < fill->count; ++k)
    zones = zones || peri_deck_get(fill->items[k], "spacing") != NULL;
  if (!fill || zones || peri_setup_horizon_is_field(d) || !(s->disc.geom.horizon > 0.0))
    return peri_deck_error(at, "key 'graded_mesh': needs a uniform grid (discretization.fill with one spacing "
                               "and one horizon): the mesh is made on its lattice");
  if (peri_deck_get(d, "volume"))
    return peri_deck_error(peri_deck_key_node(d, "volume"), "key 'volume': not with coupling.graded_mesh (a coarse "
                                                             "node's volume is its share of its elements)");
  long levels = 3, layers = 2;
  TRY(peri_deck_int(gm, "levels", false, &levels));
  TRY(peri_deck_int(gm, "layers", false, &layers));
  if (levels < 1 || levels > 10)
    return peri_deck_error(peri_deck_get(gm, "levels"), "key 'levels': expected 1 to 10, got %ld", levels);
  if (layers < 1 || layers > 1000)
    return peri_deck_error(peri_deck_get(gm, "layers"), "key 'layers': expected 1 to 1000, got %ld", layers);
  const peri_node *fine = peri_deck_get(gm, "fine");
  if (!fine) return peri_deck_error(gm, "coupling.graded_mesh: missing key 'fine' (the shapes kept at the spacing)");
  const bool list = fine->kind == PERI_NODE_SEQUENCE;
  const int n_shapes = list ? fine->count : 1;
  if (n_shapes < 1) return peri_deck_error(fine, "key 'fine': expected a shape or a list of shapes");
  peri_shape *shapes = peri_calloc((size_t)n_shapes, sizeof *shapes);
  int rc = PERI_OK, parsed = 0;
  for (; parsed < n_shapes && rc == PERI_OK; ++parsed)
    rc = peri_shape_parse(list ? fine->items[parsed] : fine, 2, "coupling.graded_mesh.fine", NULL, &shapes[parsed]);
  const peri_geometry *g = &s->disc.geom;
  /* a PD row reaches its bonds (one horizon, two for a state-based tangent) plus half a cell of
   * partial volume: no coarse node or left-out point may lie within it */
  const double reach = (s->mat.model && s->mat.model->tangent_reach == 2 ? 2.0 : 1.0) * g->horizon + g->spacing;
  char why[512];
  if (rc == PERI_OK) {
    rc = peri_graded_mesh_build(&s->disc.p, g->spacing, reach, g->thickness, shapes, n_shapes, (int)levels,
                                (int)layers, m, why, sizeof why);
    if (rc != PERI_OK) peri_deck_error(at, "coupling.graded_mesh: %s", why);
  }
  for (int k = 0; k < parsed; ++k) peri_shape_free(&shapes[k]);
  free(shapes);
  return rc;
}

/* coupling.balance_regions: the regions whose reactions enter the history's
 * out_of_balance_reactions_* (e_r of eqs. 2.114, 2.116: the supports and the load points). */
static int balance_regions(peri_sim *s, const peri_node *root, const peri_node *cp) {
  const peri_node *list = peri_deck_get(cp, "balance_regions");
  if (!list) return PERI_OK;
  if (list->kind != PERI_NODE_SEQUENCE || list->count < 2)
    return peri_deck_error(list, "key 'balance_regions': expected a list of at least two region names (the "
                                 "supports and the load)");
  peri_coupling *c = s->coupling;
  c->balance_region = peri_calloc((size_t)list->count, sizeof(int));
  for (int k = 0; k < list->count; ++k) {
    const peri_node *it = list->items[k];
    if (!it->scalar)
      return peri_deck_error(it, "key 'balance_regions': expected a region name, got %s", peri_deck_kind_name(it));
    const int r = peri_setup_find_region(s, peri_deck_get(root, "regions"), it, it->scalar);
    if (r < 0) return -r;
    if (r == 0)
      return peri_deck_error(it, "key 'balance_regions': region 'all' sums every nodal force (that is "
                                 "out_of_balance_*); name the supports and the load");
    for (int j = 0; j < c->n_balance_regions; ++j)
      if (c->balance_region[j] == r) return peri_deck_error(it, "key 'balance_regions': region '%s' is listed twice", it->scalar);
    c->balance_region[c->n_balance_regions++] = r;
  }
  return PERI_OK;
}

/* coupling.tractions: named points of a straight interface where the history reports the
 * nonlocal and the local traction (eqs. A.15, A.34, 2.107): {at: point, normal: +x ...}, the
 * normal pointing from the PD side into the FEM side. */
static int tractions(peri_sim *s, const peri_node *cp) {
  const peri_node *map = peri_deck_get(cp, "tractions");
  if (!map) return PERI_OK;
  if (map->kind != PERI_NODE_MAPPING || map->count < 1)
    return peri_deck_error(map, "key 'tractions': expected a mapping of names to {at: point, normal: +x|-x|+y|...}");
  const int dim = s->disc.geom.dim;
  peri_coupling *c = s->coupling;
  c->traction = peri_calloc((size_t)map->count, sizeof *c->traction);
  static const char *const keys[] = {"at", "normal", NULL};
  static const char *const normals[] = {"+x", "-x", "+y", "-y", "+z", "-z", NULL};
  for (int k = 0; k < map->count; ++k) {
    const peri_node *def = map->items[k];
    peri_interface_traction *tr = &c->traction[c->n_tractions];
    if (def->kind != PERI_NODE_MAPPING)
      return peri_deck_error(def, "coupling.tractions.%s: expected {at: point, normal: +x|-x|+y|...}", map->keys[k]->scalar);
    TRY(peri_deck_allow(def, "coupling.tractions", keys));
    TRY(peri_deck_vector(def, "at", true, dim, tr->at));
    int normal = 0;
    TRY(peri_deck_choice(def, "normal", true, normals, &normal));
    tr->axis = normal / 2, tr->sign = normal % 2 ? -1 : 1;
    if (tr->axis >= dim)
      return peri_deck_error(peri_deck_get(def, "normal"), "key 'normal': %s is not an axis of a %dD deck",
                             normals[normal], dim);
    tr->name = peri_strdup(map->keys[k]->scalar);
    c->n_tractions++;
    char why[256];
    if (peri_coupling_traction_locate(s, tr, why, sizeof why) != PERI_OK)
      return peri_deck_error(peri_deck_get(def, "at"), "coupling.tractions.%s: %s", tr->name, why);
  }
  return PERI_OK;
}

int peri_setup_coupling(peri_sim *s, const peri_node *root, const peri_fem_mesh *mesh) {
  const peri_node *cp = peri_deck_get(root, "coupling");
  if (!cp) return PERI_OK;
  static const char *const keys[] = {"pd_region", "micromodulus_exponent", "gamma", "partial_volume",
                                     "switch_radius", "graded_mesh", "mesh", "mesh_material",
                                     "balance_regions", "tractions", NULL};
  TRY(peri_deck_allow(cp, "coupling", keys));
  const char *name = NULL;
  TRY(peri_deck_string(cp, "pd_region", false, &name));
  int r = -1; /* no pd_region: every node starts FEM (the PD patch grows from pre-cracks) */
  if (name) {
    r = peri_setup_find_region(s, peri_deck_get(root, "regions"), peri_deck_get(cp, "pd_region"), name);
    if (r < 0) return -r;
  }
  double alpha = s->disc.geom.dim == 1 ? 1.0 : 3.0, gamma = 1.0;
  TRY(peri_deck_double(cp, "micromodulus_exponent", false, &alpha));
  const peri_node *gamma_at = peri_deck_get(cp, "gamma");
  const bool gamma_auto = gamma_at && gamma_at->scalar && !strcmp(gamma_at->scalar, "auto"); /* Remark A.2's */
  if (!gamma_auto) TRY(peri_deck_double(cp, "gamma", false, &gamma));
  static const char *const rules[] = {"discretization", "exact", NULL};
  int rule = 0;
  TRY(peri_deck_choice(cp, "partial_volume", false, rules, &rule));
  if (rule == 1 && s->disc.geom.dim == 3)
    return peri_deck_error(peri_deck_get(cp, "partial_volume"), "key 'partial_volume': exact is for 1D and 2D "
                                                                "(Ongaro 2022 gives no 3D rule)");
  if (!(gamma > 0.0)) return peri_deck_error(peri_deck_get(cp, "gamma"), "key 'gamma': expected a positive factor, got %g", gamma);
  const bool state_based = s->mat.model->tangent_reach == 2 && s->mat.model->tangent;
  if (strcmp(s->mat.model->name, "pmb") != 0 && !state_based)
    return peri_deck_error(cp, "coupling: the PD side is bond-based (pmb) or a state-based model with a tangent "
                               "(lps): the materials have model %s", s->mat.model->name);
  static const char *const bond_only[] = {"micromodulus_exponent", "gamma", "partial_volume"};
  for (int k = 0; state_based && k < 3; ++k)
    if (peri_deck_get(cp, bond_only[k]))
      return peri_deck_error(peri_deck_key_node(cp, bond_only[k]), "key '%s': only for the bond-based PD side (model "
                                                                  "pmb); model %s takes its rows from its tangent",
                             bond_only[k], s->mat.model->name);
  const peri_node *solver = peri_deck_get(root, "solver");
  const bool explicit_run = s->solver.kind == PERI_SOLVER_EXPLICIT; /* coupled dynamics (docs/coupling.md) */
  if (s->solver.kind != PERI_SOLVER_IMPLICIT && !explicit_run)
    return peri_deck_error(solver ? solver : cp, "coupling: needs solver type implicit (the coupled stiffness is "
                                                 "assembled and solved by PETSc) or explicit (dynamics)");
  if (s->solver.breaking && !peri_deck_get(solver, "breaking"))
    s->solver.breaking = false; /* the coupled model is linear elastic: nothing breaks */
  double radius = 2.0; /* MODELS.md 14.5: scheme 2 by default */
  TRY(peri_deck_double(cp, "switch_radius", false, &radius));
  if (peri_deck_get(cp, "switch_radius") && !s->solver.breaking)
    return peri_deck_error(peri_deck_key_node(cp, "switch_radius"),
                           "key 'switch_radius': only with solver.breaking: true (nodes switch to PD as bonds break)");
  if (!(radius >= 0.0) || !isfinite(radius))
    return peri_deck_error(peri_deck_key_node(cp, "switch_radius"),
                           "key 'switch_radius': expected a number of horizons >= 0, got %g", radius);
  if (s->solver.breaking) TRY(check_fracture(s, root, cp, state_based, rule == 1));
  /* the coupled stiffness is not symmetric: LU by default, GMRES on request, never CG */
  if (!explicit_run && !peri_deck_get(solver, "linear_solver")) {
    s->solver.qs.linear_solver = PERI_LINEAR_DIRECT;
    s->solver.qs.petsc_preconditioner = PERI_PC_LU;
  } else if (!explicit_run && s->solver.qs.linear_solver == PERI_LINEAR_CG) {
    return peri_deck_error(peri_deck_get(solver, "linear_solver"), "key 'linear_solver': the coupled stiffness is "
                                                                   "not symmetric: use direct or gmres");
  }
  const peri_region *pd = r >= 0 ? &s->cond.regions[r] : NULL;
  char why[512];
  if (rule == 1 && mesh->file)
    return peri_deck_error(peri_deck_key_node(cp, "mesh"), "key 'mesh': not with partial_volume exact (its "
                                                            "families are whole lattice cells)");
  if (mesh->file && s->solver.breaking)
    return peri_deck_error(peri_deck_key_node(cp, "mesh"), "key 'mesh': not with solver.breaking yet (the switching "
                                                            "walks the lattice's own cells or a graded mesh)");
  if (peri_deck_get(cp, "mesh_material") && !mesh->file)
    return peri_deck_error(peri_deck_key_node(cp, "mesh_material"), "key 'mesh_material': only with coupling.mesh");
  if (rule == 1 && mesh->nodes)
    return peri_deck_error(peri_deck_key_node(cp, "graded_mesh"), "key 'graded_mesh': not with partial_volume exact "
                                                                   "(its families are whole lattice cells)");
  if (peri_coupling_build_on_mesh(s, mesh->nodes ? mesh : NULL, pd ? pd->nodes : NULL, pd ? pd->count : 0, alpha,
                                  gamma, rule == 1, why, sizeof why) != PERI_OK)
    return peri_deck_error(cp, "coupling: %s", why);
  if (gamma_auto) peri_coupling_set_gamma(s, peri_coupling_linear_field_gamma(s)); /* linear_field_gamma.c */
  if (s->solver.breaking && peri_coupling_set_switching(s, radius, why, sizeof why) != PERI_OK) /* switching.c */
    return peri_deck_error(cp, "coupling: the PD patch around the pre-cracks: %s", why);
  TRY(balance_regions(s, root, cp));
  return tractions(s, cp);
}
