/* The bodies key of the deck (docs/deck.md section 20, docs/contact.md "Bodies"): a list of
 * regions, each a separate body. A body keeps its own geometry (the fill items or mesh blocks
 * its region holds), material and initial velocity (an initial_velocity condition on its
 * region); what makes it a body is that no bond joins it to another body, so the bodies
 * interact only through contact. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/bodies.h"
#include "peri/error.h"
#include "setup_parts.h"

#define TRY(x) do { int rc_ = (x); if (rc_ != PERI_OK) return rc_; } while (0)

/* Label of a node outside every body: such nodes keep their bonds among themselves. */
#define NO_BODY PERI_NO_BODY

/* The body of list `bodies` named by the scalar `at`, or -(error) naming the bodies. */
static int find_body(const peri_node *bodies, const peri_node *at, const char *section) {
  if (at->kind == PERI_NODE_SCALAR)
    for (int k = 0; k < bodies->count; ++k)
      if (bodies->items[k]->kind == PERI_NODE_SCALAR && !strcmp(bodies->items[k]->scalar, at->scalar)) return k;
  return -peri_deck_error(at, "%s: '%s' is not a body; the bodies are the regions listed in 'bodies'", section,
                          at->kind == PERI_NODE_SCALAR ? at->scalar : peri_deck_kind_name(at));
}

/* The one material of body b's nodes, -1 when it has several. */
static int body_material(const peri_sim *s, const int32_t *label, int b) {
  int m = -2;
  for (int32_t i = 0; i < s->disc.p.n; ++i)
    if (label[i] == b) {
      if (m == -2) m = s->disc.p.material[i];
      else if (m != s->disc.p.material[i]) return -1;
    }
  return m;
}

/* Whether the interfaces list (deck.md section 9) names the materials a and b. */
static bool interfaces_name(const peri_sim *s, const peri_node *root, int a, int b) {
  const peri_node *list = peri_deck_get(root, "interfaces");
  for (int k = 0; list && list->kind == PERI_NODE_SEQUENCE && k < list->count; ++k) {
    const peri_node *pair = list->items[k]->kind == PERI_NODE_MAPPING ? peri_deck_get(list->items[k], "materials") : NULL;
    if (!pair || pair->kind != PERI_NODE_SEQUENCE || pair->count != 2) continue;
    const peri_node *p0 = pair->items[0], *p1 = pair->items[1];
    if (p0->kind != PERI_NODE_SCALAR || p1->kind != PERI_NODE_SCALAR) continue;
    const char *na = s->mat.materials[a].name, *nb = s->mat.materials[b].name;
    if ((!strcmp(p0->scalar, na) && !strcmp(p1->scalar, nb)) || (!strcmp(p0->scalar, nb) && !strcmp(p1->scalar, na)))
      return true;
  }
  return false;
}

/* body_interfaces (docs/contact.md "Bodies"): pairs of bodies that stay bonded. Bonded bodies
 * form groups (A-B and B-C bond A, B and C), and the bonds within a group are kept: `group`
 * is the group of each body. A critical stretch of the interface is that of bonds between
 * the two bodies' materials (the pair table of deck.md section 9), so each body must be of
 * one material and the two materials different. */
static int parse_body_interfaces(peri_sim *s, const peri_node *root, const peri_node *bodies, const int32_t *label,
                                 int *group) {
  for (int b = 0; b < bodies->count; ++b) group[b] = b;
  const peri_node *list = peri_deck_get(root, "body_interfaces");
  if (!list) return PERI_OK;
  if (list->kind != PERI_NODE_SEQUENCE)
    return peri_deck_error(list, "key 'body_interfaces': expected a list, got %s", peri_deck_kind_name(list));
  static const char *const keys[] = {"bodies", "critical_stretch", NULL};
  for (int k = 0; k < list->count; ++k) {
    const peri_node *it = list->items[k];
    TRY(peri_deck_allow(it, "body_interfaces", keys));
    const peri_node *pair = peri_deck_get(it, "bodies");
    if (!pair) return peri_deck_error(it, "missing key 'bodies' in body_interfaces");
    if (pair->kind != PERI_NODE_SEQUENCE || pair->count != 2)
      return peri_deck_error(pair, "key 'bodies': expected two body names, e.g. [plate, backing]");
    const int a = find_body(bodies, pair->items[0], "body_interfaces");
    if (a < 0) return -a;
    const int b = find_body(bodies, pair->items[1], "body_interfaces");
    if (b < 0) return -b;
    if (a == b) return peri_deck_error(pair, "body_interfaces: a body is bonded to itself; name two bodies");
    const int from = group[b], to = group[a]; /* merge b's group into a's */
    for (int c = 0; c < bodies->count; ++c)
      if (group[c] == from) group[c] = to;
    double s0 = NAN;
    TRY(peri_deck_double(it, "critical_stretch", false, &s0));
    if (isnan(s0)) continue; /* bonded with the materials' own critical stretch */
    const peri_node *at = peri_deck_get(it, "critical_stretch");
    if (!(s0 > 0.0)) return peri_deck_error(at, "key 'critical_stretch': must be positive");
    const int ma = body_material(s, label, a), mb = body_material(s, label, b);
    if (ma < 0 || mb < 0 || ma == mb)
      return peri_deck_error(at, "body_interfaces: the critical stretch of bodies '%s' and '%s' is that of bonds "
                                 "between their two materials, so each body must be of one material and the two "
                                 "different; %s", pair->items[0]->scalar, pair->items[1]->scalar,
                             ma < 0 || mb < 0 ? "one of them holds several materials"
                                              : "give one body its own material (a copy under another name)");
    if (s->mat.materials[ma].lammps_s0 || s->mat.materials[mb].lammps_s0)
      return peri_deck_error(at, "body_interfaces: not available with the {s00, alpha} critical stretch (bonds take "
                                 "min(s0_i, s0_j))");
    if (interfaces_name(s, root, ma, mb))
      return peri_deck_error(at, "body_interfaces: 'interfaces' also sets the critical stretch between materials "
                                 "'%s' and '%s'; give it in one place", s->mat.materials[ma].name, s->mat.materials[mb].name);
    const int nm = s->mat.n_materials;
    s->mat.pair_s0[ma * nm + mb] = s->mat.pair_s0[mb * nm + ma] = s0;
  }
  return PERI_OK;
}

int peri_setup_bodies(peri_sim *s, const peri_node *root) {
  const peri_node *list = peri_deck_get(root, "bodies");
  if (!list) {
    if (peri_deck_get(root, "body_interfaces"))
      return peri_deck_error(peri_deck_key_node(root, "body_interfaces"), "key 'body_interfaces': needs 'bodies'");
    return PERI_OK;
  }
  if (list->kind != PERI_NODE_SEQUENCE || list->count < 1)
    return peri_deck_error(list, "key 'bodies': expected a list of region names, got %s",
                           peri_deck_kind_name(list));
  /* (every rank builds the labels of all nodes here, before the decomposition; each keeps its
   * own nodes' and its ghosts' after it: peri_bodies_localize) */
  const peri_node *regions = peri_deck_get(root, "regions");
  const peri_particles *p = &s->disc.p;
  int32_t *label = peri_malloc(sizeof(int32_t) * (size_t)(p->n > 0 ? p->n : 1));
  int32_t *first = peri_malloc(sizeof(int32_t) * (size_t)list->count); /* region of each body */
  for (int32_t i = 0; i < p->n; ++i) label[i] = NO_BODY;
  int rc = PERI_OK;
  for (int k = 0; k < list->count && rc == PERI_OK; ++k) {
    const peri_node *it = list->items[k];
    if (it->kind != PERI_NODE_SCALAR) {
      rc = peri_deck_error(it, "bodies: expected a region name, got %s", peri_deck_kind_name(it));
      break;
    }
    const int r = peri_setup_find_region(s, regions, it, it->scalar);
    if (r < 0) { rc = -r; break; }
    first[k] = r;
    for (int b = 0; b < k; ++b)
      if (first[b] == r) {
        rc = peri_deck_error(it, "bodies: region '%s' is listed twice", it->scalar);
        break;
      }
    const peri_region *reg = &s->cond.regions[r];
    if (rc == PERI_OK && reg->count == 0)
      rc = peri_deck_error(it, "bodies: region '%s' contains no node; a body needs nodes", reg->name);
    for (int32_t a = 0; a < reg->count && rc == PERI_OK; ++a) {
      const int32_t i = reg->nodes[a];
      if (label[i] != NO_BODY) {
        const double *x = &p->x[3 * i];
        rc = peri_deck_error(it, "bodies: bodies '%s' and '%s' overlap at t = 0: both hold the node at "
                                 "(%g, %g, %g); a node belongs to at most one body, so separate their regions",
                             s->cond.regions[first[label[i]]].name, reg->name, x[0], x[1], x[2]);
        break;
      }
      label[i] = k;
    }
  }
  if (rc != PERI_OK) {
    free(first);
    free(label);
    return rc;
  }
  /* the bonds are kept within a group of bonded bodies (each body its own group without
   * body_interfaces) */
  int *group = peri_malloc(sizeof(int) * (size_t)list->count);
  rc = parse_body_interfaces(s, root, list, label, group);
  if (rc != PERI_OK) {
    free(group);
    free(first);
    free(label);
    return rc;
  }
  int32_t *kept_with = peri_malloc(sizeof(int32_t) * (size_t)(p->n > 0 ? p->n : 1));
  for (int32_t i = 0; i < p->n; ++i) kept_with[i] = label[i] == NO_BODY ? NO_BODY : group[label[i]];
  peri_bonds_keep_within(&s->disc.bonds, kept_with);
  free(kept_with);
  free(group);
  /* kept for the body output field and the per-body sums of history.csv */
  peri_bodies *bodies = peri_calloc(1, sizeof *bodies);
  *bodies = (peri_bodies){.count = list->count, .region = first, .label = label,
                          .penetration = peri_calloc((size_t)list->count, sizeof(peri_penetration))};
  s->bodies = bodies;
  return PERI_OK;
}

/* x - c split along the unit e and across it: returns (x - c) . e, lateral the rest. */
static double axis_offset(const double *x, const double c[3], const double e[3], double lateral[3]) {
  double along = 0.0;
  for (int d = 0; d < 3; ++d) along += (x[d] - c[d]) * e[d];
  for (int d = 0; d < 3; ++d) lateral[d] = x[d] - c[d] - along * e[d];
  return along;
}

/* output.penetration: {BODY: direction}. The face is the smallest X . e (e the unit direction)
 * over the nodes of everything else that lie ahead of the body's foremost node and within its
 * path: at most the body's own largest distance from its axis (the line along e through its
 * centroid), plus half a spacing, from that axis. */
int peri_setup_penetration(peri_sim *s, const peri_node *root) {
  const peri_node *map = peri_deck_get(peri_deck_get(root, "output"), "penetration");
  if (!map) return PERI_OK;
  if (!s->bodies)
    return peri_deck_error(map, "key 'penetration': needs 'bodies' (the penetration depth is that of a body)");
  if (map->kind != PERI_NODE_MAPPING || map->count < 1)
    return peri_deck_error(map, "key 'penetration': expected a mapping of body names to directions of travel, "
                                "e.g. {projectile: [0, 0, -1]}");
  const peri_particles *p = &s->disc.p;
  const int dim = s->disc.geom.dim;
  const peri_node *bodies = peri_deck_get(root, "bodies");
  for (int k = 0; k < map->count; ++k) {
    const int b = find_body(bodies, map->keys[k], "output.penetration");
    if (b < 0) return -b;
    peri_penetration *pen = &s->bodies->penetration[b];
    double e[3] = {0, 0, 0}, norm = 0.0;
    const peri_node *v = map->items[k];
    if (v->kind != PERI_NODE_SEQUENCE || v->count != dim)
      return peri_deck_error(v, "output.penetration.%s: expected a direction of %d components", map->keys[k]->scalar, dim);
    for (int d = 0; d < dim; ++d) TRY(peri_deck_node_double(v->items[d], "output.penetration", &e[d]));
    for (int d = 0; d < 3; ++d) norm += e[d] * e[d];
    if (!(norm > 0.0) || !isfinite(norm))
      return peri_deck_error(v, "output.penetration.%s: the direction is zero", map->keys[k]->scalar);
    for (int d = 0; d < 3; ++d) e[d] /= sqrt(norm);
    double centroid[3] = {0, 0, 0}, front = -INFINITY, radius = 0.0;
    int32_t count = 0;
    for (int32_t i = 0; i < p->n; ++i)
      if (s->bodies->label[i] == b) {
        for (int d = 0; d < 3; ++d) centroid[d] += p->x[3 * (size_t)i + d];
        ++count;
      }
    for (int d = 0; d < 3; ++d) centroid[d] /= count;
    for (int32_t i = 0; i < p->n; ++i) {
      if (s->bodies->label[i] != b) continue;
      double lateral[3];
      const double at = axis_offset(&p->x[3 * (size_t)i], centroid, e, lateral);
      radius = fmax(radius, sqrt(lateral[0] * lateral[0] + lateral[1] * lateral[1] + lateral[2] * lateral[2]));
      front = fmax(front, at);
    }
    radius += 0.5 * s->disc.geom.spacing;
    double face = INFINITY;
    for (int32_t i = 0; i < p->n; ++i) {
      if (s->bodies->label[i] == b) continue;
      double lateral[3];
      const double at = axis_offset(&p->x[3 * (size_t)i], centroid, e, lateral);
      if (at > front && at < face &&
          lateral[0] * lateral[0] + lateral[1] * lateral[1] + lateral[2] * lateral[2] <= radius * radius)
        face = at;
    }
    if (face == INFINITY)
      return peri_deck_error(v, "output.penetration.%s: no node of another body lies ahead of it in its path along "
                                "this direction", map->keys[k]->scalar);
    double c_along = 0.0; /* face and front relative to the centroid above: back to X . e */
    for (int d = 0; d < 3; ++d) c_along += centroid[d] * e[d];
    *pen = (peri_penetration){.on = true, .direction = {e[0], e[1], e[2]}, .face = face + c_along};
  }
  return PERI_OK;
}
