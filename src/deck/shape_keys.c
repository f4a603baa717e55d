/* Shapes from the deck: the keys of each shape kind and their checks (include/peri/shape.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/setup.h"
#include "peri/shape.h"
#include "peri/error.h"

/* Shape names as written in decks, and the kind each stands for. */
static const char *const shape_names[] = {"box",  "rectangle", "interval", "sphere", "circle",
                                          "disk", "cylinder",  "polygon",  "all",    NULL};
static const peri_shape_kind shape_kinds[] = {
    PERI_SHAPE_BOX,      PERI_SHAPE_BOX,     PERI_SHAPE_BOX,
    PERI_SHAPE_SPHERE,   PERI_SHAPE_SPHERE,  PERI_SHAPE_SPHERE,
    PERI_SHAPE_CYLINDER, PERI_SHAPE_POLYGON, PERI_SHAPE_ALL};

/* Keys each kind reads (besides "shape"). */
static const char *const box_keys[] = {"min", "max", NULL};
static const char *const sphere_keys[] = {"center", "radius", NULL};
static const char *const cylinder_keys[] = {"center", "axis",       "radius",
                                            "inner_radius", "length", "top_radius", NULL};
static const char *const polygon_keys[] = {"vertices", NULL};
static const char *const all_keys[] = {NULL};
static const char *const any_keys[] = {"min",    "max",          "center",   "axis",       "radius",
                                       "length", "inner_radius", "vertices", "top_radius", NULL};

static const char *const *kind_keys(peri_shape_kind k) {
  switch (k) {
  case PERI_SHAPE_BOX: return box_keys;
  case PERI_SHAPE_SPHERE: return sphere_keys;
  case PERI_SHAPE_CYLINDER: return cylinder_keys;
  case PERI_SHAPE_POLYGON: return polygon_keys;
  case PERI_SHAPE_ALL: break;
  }
  return all_keys;
}

static bool in_list(const char *const *list, const char *s) {
  for (; list && *list; list++)
    if (strcmp(*list, s) == 0) return true;
  return false;
}

static int count_list(const char *const *list) {
  int n = 0;
  while (list && list[n]) n++;
  return n;
}

/* Checks the keys of `map` against every shape key, so that a typo gets a "did you mean"
 * suggestion even before the kind is known. */
static int allow_any(const peri_node *map, const char *section, const char *const *extra) {
  int ne = count_list(extra), na = count_list(any_keys);
  const char **allowed = peri_malloc(sizeof(char *) * (size_t)(ne + na + 2));
  int k = 0;
  allowed[k++] = "shape";
  for (int i = 0; i < na; i++) allowed[k++] = any_keys[i];
  for (int i = 0; i < ne; i++) allowed[k++] = extra[i];
  allowed[k] = NULL;
  int rc = peri_deck_allow(map, section, allowed);
  free(allowed);
  return rc;
}

/* Checks that each key applies to the chosen kind (e.g. no 'radius' on a box). */
static int check_keys(const peri_node *map, const char *section, const char *const *extra,
                      peri_shape_kind kind, const char *kind_name) {
  int rc = allow_any(map, section, extra);
  if (rc != PERI_OK) return rc;
  const char *const *mine = kind_keys(kind);
  for (int i = 0; i < map->count; i++) {
    const char *key = map->keys[i]->scalar;
    if (!key || strcmp(key, "shape") == 0 || in_list(extra, key) || in_list(mine, key)) continue;
    return peri_deck_error(map->keys[i], "key '%s' does not apply to shape '%s' in %s", key,
                           kind_name, section);
  }
  return PERI_OK;
}

static int need(const peri_node *map, const char *key, const char *section) {
  if (peri_deck_get(map, key)) return PERI_OK;
  return peri_deck_error(map, "missing key '%s' in %s", key, section);
}

static int positive(const peri_node *map, const char *key, double v, const char *section) {
  if (v > 0 && isfinite(v)) return PERI_OK;
  const peri_node *at = peri_deck_get(map, key);
  return peri_deck_error(at ? at : map, "'%s' in %s must be a positive number, got %g", key,
                         section, v);
}

static int parse_polygon(const peri_node *map, const char *section, peri_shape *out) {
  int rc = need(map, "vertices", section);
  if (rc) return rc;
  const peri_node *seq = peri_deck_get(map, "vertices");
  if (seq->kind != PERI_NODE_SEQUENCE)
    return peri_deck_error(seq, "'vertices' in %s must be a list of points [x, y], found %s",
                           section, peri_deck_kind_name(seq));
  if (seq->count < 3)
    return peri_deck_error(seq, "'vertices' in %s needs at least 3 points, got %d", section,
                           seq->count);
  out->vertices = peri_malloc(sizeof(double) * 2 * (size_t)seq->count);
  out->n_vertices = seq->count;
  for (int i = 0; i < seq->count; i++) {
    const peri_node *v = seq->items[i];
    if (v->kind != PERI_NODE_SEQUENCE)
      return peri_deck_error(v, "vertex %d of 'vertices' in %s must be a point [x, y], found %s",
                             i + 1, section, peri_deck_kind_name(v));
    if (v->count != 2)
      return peri_deck_error(v,
                             "vertex %d of 'vertices' in %s must be a point [x, y], got %d "
                             "numbers",
                             i + 1, section, v->count);
    for (int c = 0; c < 2; c++) {
      rc = peri_deck_node_double(v->items[c], "'vertices' coordinate", &out->vertices[2 * i + c]);
      if (rc) return rc;
    }
  }
  return PERI_OK;
}

static int parse_kind(const peri_node *map, int dim, const char *section, peri_shape *out,
                      const char *kind_name) {
  int rc, cnt;
  switch (out->kind) {
  case PERI_SHAPE_BOX:
    if ((rc = peri_deck_vector_range(map, "min", true, dim, 3, out->min, &cnt))) return rc;
    if ((rc = peri_deck_vector_range(map, "max", true, dim, 3, out->max, &cnt))) return rc;
    for (int d = 0; d < dim; d++)
      if (!(out->min[d] <= out->max[d]))
        return peri_deck_error(peri_deck_get(map, "max"),
                               "'max' must not be below 'min' in %s (component %d: %g < %g)",
                               section, d + 1, out->max[d], out->min[d]);
    return PERI_OK;
  case PERI_SHAPE_SPHERE:
    if ((rc = peri_deck_vector_range(map, "center", true, dim, 3, out->center, &cnt))) return rc;
    if ((rc = peri_deck_double(map, "radius", true, &out->radius))) return rc;
    return positive(map, "radius", out->radius, section);
  case PERI_SHAPE_CYLINDER: {
    if (dim != 3)
      return peri_deck_error(map, "shape '%s' in %s needs a 3D model (use a rectangle in 2D)",
                             kind_name, section);
    static const char *const axes[] = {"x", "y", "z", NULL};
    if ((rc = peri_deck_vector_range(map, "center", true, dim, 3, out->center, &cnt))) return rc;
    if ((rc = peri_deck_choice(map, "axis", true, axes, &out->axis))) return rc;
    if ((rc = peri_deck_double(map, "radius", true, &out->radius))) return rc;
    if ((rc = positive(map, "radius", out->radius, section))) return rc;
    if ((rc = peri_deck_double(map, "length", true, &out->length))) return rc;
    if ((rc = positive(map, "length", out->length, section))) return rc;
    out->top_radius = out->radius;
    if ((rc = peri_deck_double(map, "top_radius", false, &out->top_radius))) return rc;
    if (!(out->top_radius >= 0 && isfinite(out->top_radius)))
      return peri_deck_error(peri_deck_get(map, "top_radius"),
                             "'top_radius' in %s must be a number >= 0, got %g", section,
                             out->top_radius);
    if ((rc = peri_deck_double(map, "inner_radius", false, &out->inner_radius))) return rc;
    double outer_min = fmin(out->radius, out->top_radius);
    if (!(out->inner_radius >= 0 && (out->inner_radius == 0 || out->inner_radius < outer_min)))
      return peri_deck_error(peri_deck_get(map, "inner_radius"),
                             "'inner_radius' in %s must be in [0, min(radius, top_radius)), "
                             "got %g",
                             section, out->inner_radius);
    return PERI_OK;
  }
  case PERI_SHAPE_POLYGON:
    if (dim != 2) return peri_deck_error(map, "shape 'polygon' in %s needs a 2D model", section);
    return parse_polygon(map, section, out);
  case PERI_SHAPE_ALL: return PERI_OK;
  }
  return PERI_OK;
}

int peri_shape_parse(const peri_node *map, int dim, const char *section,
                     const char *const *extra_keys, peri_shape *out) {
  memset(out, 0, sizeof *out);
  if (!map || map->kind != PERI_NODE_MAPPING) {
    if (!map) {
      peri_error("%s: expected a shape mapping", section);
      return PERI_ERR_INPUT;
    }
    return peri_deck_error(map,
                           "%s must be a mapping such as {shape: box, min: [...], max: [...]}, "
                           "found %s",
                           section, peri_deck_kind_name(map));
  }
  int choice = -1;
  /* Report a misspelt key before complaining that 'shape' is missing. */
  if (!peri_deck_get(map, "shape")) {
    int rc = allow_any(map, section, extra_keys);
    if (rc) return rc;
    return peri_deck_error(map, "missing key 'shape' in %s", section);
  }
  int rc = peri_deck_choice(map, "shape", true, shape_names, &choice);
  if (rc) return rc;
  out->kind = shape_kinds[choice];
  if ((rc = check_keys(map, section, extra_keys, out->kind, shape_names[choice]))) return rc;
  rc = parse_kind(map, dim, section, out, shape_names[choice]);
  if (rc) peri_shape_free(out);
  return rc;
}

/* Distance from p to the segment a-b (2D). */
