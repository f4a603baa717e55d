/* The regions section: each region is a shape, a set of the mesh (node_set), a node set file,
 * blocks, materials, or the union, intersection or difference of other regions, named or
 * written in place (docs/deck.md, section 10). Regions may name regions defined after them;
 * a region that names itself through others is an error. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/error.h"
#include "peri/region.h"
#include "peri/setup.h"
#include "setup_parts.h"

#define TRY(expr)                   \
  do {                              \
    int rc_ = (expr);               \
    if (rc_ != PERI_OK) return rc_; \
  } while (0)

static const char *const kinds[] = {"shape", "node_set", "node_set_file", "block", "material",
                                    "union", "intersection", "difference", NULL};
enum { K_SHAPE, K_NODE_SET, K_NODE_SET_FILE, K_BLOCK, K_MATERIAL, K_UNION, K_INTERSECTION, K_DIFFERENCE };

typedef struct ctx {
  peri_sim *s;
  const peri_node *regs;
  const peri_mesh *mesh;
  const int32_t *node_of_point;
  uint8_t *state; /* per deck region: 0 to build, 1 being built, 2 built */
} ctx;

static int by_node(const void *a, const void *b) {
  int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
  return (x > y) - (x < y);
}

/* The nodes of mesh points, ascending. */
static void set_from_points(const ctx *c, peri_region *r, const int32_t *points, int32_t count) {
  int32_t *nodes = peri_malloc(sizeof(int32_t) * (size_t)(count > 0 ? count : 1));
  for (int32_t k = 0; k < count; ++k) nodes[k] = c->node_of_point[points[k]];
  qsort(nodes, (size_t)count, sizeof(int32_t), by_node);
  peri_region_set_nodes(r, nodes, count);
  free(nodes);
}

static int node_set(const ctx *c, const peri_node *v, peri_region *r) {
  if (!c->mesh)
    return peri_deck_error(v, "key 'node_set': the discretization has no mesh file to take sets from "
                              "(discretization.mesh)");
  if (!v->scalar) return peri_deck_error(v, "key 'node_set': expected the name or id of a set of the mesh");
  const peri_mesh_set *set = peri_mesh_find_set(c->mesh, v->scalar);
  char *end;
  long long id = strtoll(v->scalar, &end, 10);
  if (!set && end != v->scalar && !*end) {
    int found = 0;
    for (int k = 0; k < c->mesh->n_sets; ++k)
      if (c->mesh->sets[k].id == id && id != 0) set = &c->mesh->sets[k], found++;
    if (found > 1)
      return peri_deck_error(v, "key 'node_set': several sets of the mesh have id %lld; name one", id);
  }
  if (!set) {
    char list[2048] = "";
    int best = -1, best_d = 1 << 30;
    for (int k = 0; k < c->mesh->n_sets; ++k) {
      snprintf(list + strlen(list), sizeof list - strlen(list), "%s'%s'", k ? ", " : "", c->mesh->sets[k].name);
      int d = peri_edit_distance(v->scalar, c->mesh->sets[k].name);
      if (d < best_d) best_d = d, best = k;
    }
    if (best >= 0 && best_d <= 2)
      return peri_deck_error(v, "key 'node_set': the mesh has no set '%s'; did you mean '%s'?", v->scalar,
                             c->mesh->sets[best].name);
    return peri_deck_error(v, "key 'node_set': the mesh has no set '%s' (its sets: %s)", v->scalar,
                           c->mesh->n_sets ? list : "none");
  }
  set_from_points(c, r, set->points, set->count);
  return PERI_OK;
}

static int node_set_file(const ctx *c, const peri_node *v, peri_region *r) {
  if (!c->mesh)
    return peri_deck_error(v, "key 'node_set_file': node ids need a discretization read from a file "
                              "(discretization.mesh or node_file)");
  if (!v->scalar) return peri_deck_error(v, "key 'node_set_file': expected a file name");
  char full[PATH_MAX + 256];
  const char *slash = strrchr(c->s->deck_path, '/');
  if (v->scalar[0] != '/' && slash)
    snprintf(full, sizeof full, "%.*s/%s", (int)(slash - c->s->deck_path), c->s->deck_path, v->scalar);
  else
    snprintf(full, sizeof full, "%s", v->scalar);
  int32_t *points = NULL, count = 0;
  TRY(peri_node_set_file_read(c->mesh, full, &points, &count));
  set_from_points(c, r, points, count);
  free(points);
  return PERI_OK;
}

/* block: an id or a name of the mesh's blocks, or a list of them. */
static int blocks_or_materials(const ctx *c, const peri_node *v, bool material, peri_region *r) {
  const peri_particles *p = &c->s->disc.p;
  const int n_items = v->kind == PERI_NODE_SEQUENCE ? v->count : 1;
  if (v->kind == PERI_NODE_MAPPING || n_items == 0)
    return peri_deck_error(v, "key '%s': expected a %s or a list of them", material ? "material" : "block",
                           material ? "material name" : "block id or name");
  int64_t *want = peri_malloc(sizeof(int64_t) * (size_t)n_items);
  int rc = PERI_OK;
  for (int k = 0; k < n_items && rc == PERI_OK; ++k) {
    const peri_node *it = v->kind == PERI_NODE_SEQUENCE ? v->items[k] : v;
    if (!it->scalar) {
      rc = peri_deck_error(it, "expected a %s", material ? "material name" : "block id or name");
    } else if (material) {
      int mi = peri_setup_find_material(c->s, it, it->scalar);
      if (mi < 0) rc = -mi;
      want[k] = mi;
    } else {
      want[k] = -1;
      for (int b = 0; c->mesh && b < c->mesh->n_blocks; ++b)
        if (strcmp(c->mesh->blocks[b].name, it->scalar) == 0) want[k] = c->mesh->blocks[b].id;
      char *end;
      long long id = strtoll(it->scalar, &end, 10);
      if (want[k] < 0 && end != it->scalar && !*end) want[k] = id;
      bool present = false;
      for (int32_t i = 0; i < p->n_owned && !present && want[k] >= 0; ++i) present = p->block[i] == want[k];
      if (!present) {
        char list[1024] = "";
        int32_t seen[64], n_seen = 0;
        for (int32_t i = 0; i < p->n_owned && n_seen < 64; ++i) {
          bool dup = false;
          for (int32_t a = 0; a < n_seen; ++a) dup |= seen[a] == p->block[i];
          if (!dup) seen[n_seen++] = p->block[i];
        }
        qsort(seen, (size_t)n_seen, sizeof(int32_t), by_node);
        for (int32_t a = 0; a < n_seen; ++a)
          snprintf(list + strlen(list), sizeof list - strlen(list), "%s%d", a ? ", " : "", seen[a]);
        rc = peri_deck_error(it, "key 'block': no node is in block '%s' (the blocks: %s%s)", it->scalar, list,
                             c->mesh ? ", or their names in the mesh" : "; a fill shape's block is its place in 'fill'");
      }
    }
  }
  if (rc == PERI_OK) {
    int32_t *nodes = peri_malloc(sizeof(int32_t) * (size_t)(p->n_owned > 0 ? p->n_owned : 1)), count = 0;
    for (int32_t i = 0; i < p->n_owned; ++i)
      for (int k = 0; k < n_items; ++k)
        if ((material ? p->material[i] : p->block[i]) == want[k]) {
          nodes[count++] = i;
          break;
        }
    peri_region_set_nodes(r, nodes, count);
    free(nodes);
  }
  free(want);
  return rc;
}

static int build_region(ctx *c, const peri_node *def, const char *section, peri_region *r, bool top);

/* The nodes of the deck's region called `name` (built now if it is not yet). */
static int named(ctx *c, const peri_node *at, const char *name, const peri_region **out) {
  peri_sim *s = c->s;
  if (strcmp(name, "all") == 0) return *out = &s->cond.regions[0], PERI_OK;
  const int k = peri_deck_key_index(c->regs, name);
  if (k < 0) {
    int r = peri_setup_find_region(s, c->regs, at, name); /* the message, with a suggestion */
    return r < 0 ? -r : peri_deck_error(at, "unknown region '%s'", name);
  }
  if (c->state[k] == 1)
    return peri_deck_error(at, "region '%s' is defined through itself (regions.%s names it, directly or "
                               "through other regions)", name, name);
  if (c->state[k] == 0) {
    c->state[k] = 1;
    char section[300];
    snprintf(section, sizeof section, "regions.%s", name);
    TRY(build_region(c, c->regs->items[k], section, &s->cond.regions[k + 1], true));
    c->state[k] = 2;
  }
  *out = &s->cond.regions[k + 1];
  return PERI_OK;
}

static int boolean(ctx *c, const peri_node *v, const char *section, int kind, peri_region *r) {
  static const char *const words[] = {"union", "intersection", "difference"};
  const char *word = words[kind - K_UNION];
  if (v->kind != PERI_NODE_SEQUENCE || v->count < 2)
    return peri_deck_error(v, "key '%s': expected a list of at least two regions (names, or regions "
                              "written in place)", word);
  const int32_t cap = c->s->disc.p.n_owned;
  int32_t *acc = peri_malloc(sizeof(int32_t) * (size_t)(cap > 0 ? cap : 1)), n_acc = 0;
  int32_t *tmp = peri_malloc(sizeof(int32_t) * 2 * (size_t)(cap > 0 ? cap : 1));
  int rc = PERI_OK;
  for (int k = 0; k < v->count && rc == PERI_OK; ++k) {
    const peri_node *it = v->items[k];
    const peri_region *operand = NULL;
    peri_region inplace = {0};
    if (it->scalar) {
      rc = named(c, it, it->scalar, &operand);
    } else {
      char sub[400];
      snprintf(sub, sizeof sub, "%s.%s[%d]", section, word, k);
      rc = build_region(c, it, sub, &inplace, false);
      operand = &inplace;
    }
    if (rc == PERI_OK) {
      if (k == 0) {
        memcpy(acc, operand->nodes, sizeof(int32_t) * (size_t)operand->count);
        n_acc = operand->count;
      } else {
        /* difference: the first minus each of the others; union, intersection: fold */
        const peri_region_op op = kind == K_UNION ? PERI_REGION_UNION
                                  : kind == K_INTERSECTION ? PERI_REGION_INTERSECTION : PERI_REGION_DIFFERENCE;
        n_acc = peri_region_combine(op, acc, n_acc, operand->nodes, operand->count, tmp);
        memcpy(acc, tmp, sizeof(int32_t) * (size_t)n_acc);
      }
    }
    peri_region_free(&inplace);
  }
  if (rc == PERI_OK) peri_region_set_nodes(r, acc, n_acc);
  free(acc);
  free(tmp);
  return rc;
}

static int build_region(ctx *c, const peri_node *def, const char *section, peri_region *r, bool top) {
  peri_sim *s = c->s;
  if (def->kind != PERI_NODE_MAPPING)
    return peri_deck_error(def, "%s: expected a mapping (a shape, or one of node_set, node_set_file, block, "
                                "material, union, intersection, difference), got %s", section,
                           peri_deck_kind_name(def));
  int kind = -1, given = 0;
  for (int k = 0; kinds[k]; ++k)
    if (peri_deck_get(def, kinds[k])) kind = k, given++;
  if (given != 1)
    return peri_deck_error(def, "%s: give exactly one of shape, node_set, node_set_file, block, material, "
                                "union, intersection, difference", section);
  static const char *const extra[] = {"no_fail", "fictitious_layer", NULL};
  if (kind == K_SHAPE) {
    TRY(peri_shape_parse(def, s->disc.geom.dim, section, top ? extra : NULL, &r->shape));
    peri_region_collect(r, &s->disc.p, 1e-9 * s->disc.geom.spacing);
  } else {
    const char *allowed[] = {kinds[kind], top ? "no_fail" : NULL, top ? "fictitious_layer" : NULL, NULL};
    TRY(peri_deck_allow(def, section, allowed));
    const peri_node *v = peri_deck_get(def, kinds[kind]);
    switch (kind) {
    case K_NODE_SET: TRY(node_set(c, v, r)); break;
    case K_NODE_SET_FILE: TRY(node_set_file(c, v, r)); break;
    case K_BLOCK: TRY(blocks_or_materials(c, v, false, r)); break;
    case K_MATERIAL: TRY(blocks_or_materials(c, v, true, r)); break;
    default: TRY(boolean(c, v, section, kind, r)); break;
    }
  }
  return PERI_OK;
}

int peri_setup_regions(peri_sim *s, const peri_node *root, const peri_mesh *mesh, const int32_t *node_of_point) {
  const peri_node *regs = peri_deck_get(root, "regions");
  int n = regs ? regs->count : 0;
  if (regs && regs->kind != PERI_NODE_MAPPING)
    return peri_deck_error(regs, "key 'regions': expected a mapping of region names to shapes, got %s",
                           peri_deck_kind_name(regs));
  s->cond.regions = peri_calloc(n + 1, sizeof(peri_region));
  s->cond.n_regions = n + 1;
  s->cond.regions[0].name = peri_strdup("all");
  s->cond.regions[0].shape.kind = PERI_SHAPE_ALL;
  peri_region_collect(&s->cond.regions[0], &s->disc.p, 0.0);
  for (int k = 0; k < n; ++k) {
    if (strcmp(regs->keys[k]->scalar, "all") == 0) return peri_deck_error(regs->keys[k], "region name 'all' is predefined");
    s->cond.regions[k + 1].name = peri_strdup(regs->keys[k]->scalar);
  }
  ctx c = {.s = s, .regs = regs, .mesh = mesh, .node_of_point = node_of_point};
  c.state = peri_calloc((size_t)(n > 0 ? n : 1), 1);
  int rc = PERI_OK;
  for (int k = 0; k < n && rc == PERI_OK; ++k) {
    const peri_region *r = NULL;
    rc = named(&c, regs->keys[k], regs->keys[k]->scalar, &r);
    if (rc != PERI_OK) break;
    if (r->count == 0)
      peri_warning("region '%s' (%s:%d) contains no nodes", r->name, regs->keys[k]->file, regs->keys[k]->line);
    bool no_fail = false;
    rc = peri_deck_bool(regs->items[k], "no_fail", false, &no_fail);
    if (rc == PERI_OK && no_fail)
      for (int32_t a = 0; a < r->count; ++a) s->disc.p.flags[r->nodes[a]] |= PERI_NODE_NO_FAIL;
    bool layer = false;
    if (rc == PERI_OK) rc = peri_deck_bool(regs->items[k], "fictitious_layer", false, &layer);
    if (rc == PERI_OK && layer) {
      if (peri_comm_sum_long(r->count) == 0) {
        rc = peri_deck_error(peri_deck_key_node(regs->items[k], "fictitious_layer"),
                             "region '%s': a fictitious layer must contain nodes; this one contains none "
                             "(place it outside the body, within the discretization's fill)", r->name);
        break;
      }
      /* never damaged: its bonds never break (no_fail); prescribed: checked with the boundary
       * conditions (peri_setup_check_layers) */
      for (int32_t a = 0; a < r->count; ++a) s->disc.p.flags[r->nodes[a]] |= PERI_NODE_NO_FAIL | PERI_NODE_FICTITIOUS;
    }
  }
  free(c.state);
  return rc;
}

/* Every node of a fictitious layer must have its motion prescribed: a displacement or velocity
 * condition on every component of the dimension (docs/deck.md section 10). */
int peri_setup_check_layers(const peri_sim *s, const peri_node *root) {
  const peri_node *regs = peri_deck_get(root, "regions");
  const peri_particles *p = &s->disc.p;
  const int dim = s->disc.geom.dim;
  uint8_t *held = peri_calloc((size_t)(p->n_owned > 0 ? p->n_owned : 1), 1);
  for (int b = 0; b < s->cond.n_bcs; ++b) {
    const peri_bc *bc = &s->cond.bcs[b];
    if (bc->kind != PERI_BC_DISPLACEMENT && bc->kind != PERI_BC_VELOCITY) continue;
    const peri_region *r = &s->cond.regions[bc->region];
    for (int32_t a = 0; a < r->count; ++a)
      for (int d = 0; d < dim; ++d)
        if (bc->value[d]) held[r->nodes[a]] |= (uint8_t)(1u << d);
  }
  int rc = PERI_OK;
  for (int k = 0; regs && k < regs->count && rc == PERI_OK; ++k) {
    bool layer = false;
    peri_deck_bool(regs->items[k], "fictitious_layer", false, &layer);
    if (!layer) continue;
    const peri_region *r = &s->cond.regions[k + 1];
    long free_nodes = 0;
    for (int32_t a = 0; a < r->count; ++a) free_nodes += held[r->nodes[a]] != (uint8_t)((1u << dim) - 1);
    if (peri_comm_sum_long(free_nodes) > 0)
      rc = peri_deck_error(peri_deck_key_node(regs->items[k], "fictitious_layer"),
                           "region '%s': %ld node(s) of this fictitious layer have no prescribed motion; a layer's "
                           "nodes need a displacement or velocity condition on every component", r->name,
                           peri_comm_sum_long(free_nodes));
  }
  free(held);
  return rc;
}
