/* discretization.fill items of shape 'image': a PNG whose colours name the materials (or
 * voids) of the pixels, at a pixel size, placed in the plane (docs/microstructures.md,
 * docs/deck.md section 6). Le 2014 section 3.2 maps processed micrographs this way: each
 * grid node takes the phase of the pixel under it, and the grid is never finer than the
 * pixels, since oversampling turns the pixels' staircase into artificial sharp corners. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/image_reader.h"
#include "setup_parts.h"

static const char *const image_keys[] = {"shape", "file", "pixel_size", "origin", "colors", NULL};

bool peri_setup_is_image_fill(const peri_node *item) {
  const peri_node *shape = item && item->kind == PERI_NODE_MAPPING ? peri_deck_get(item, "shape") : NULL;
  return shape && shape->scalar && strcmp(shape->scalar, "image") == 0;
}

/* "#rrggbb" (or "rrggbb") into 0xrrggbb; -1 if it is not one. */
static long parse_colour(const char *text) {
  if (!text) return -1;
  if (text[0] == '#') text++;
  if (strlen(text) != 6) return -1;
  long v = 0;
  for (int k = 0; k < 6; ++k) {
    const char c = text[k];
    const int digit = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10
                      : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
    if (digit < 0) return -1;
    v = 16 * v + digit;
  }
  return v;
}

typedef struct colour_entry {
  long rgb;
  int32_t phase;
} colour_entry;

/* colors: {"#rrggbb": material or void, ...} */
static int parse_colours(const peri_sim *s, const peri_node *map, colour_entry **table, int *count) {
  if (map->kind != PERI_NODE_MAPPING || map->count == 0)
    return peri_deck_error(map, "key 'colors': expected a mapping of colours to materials, e.g. "
                                "{\"#ffffff\": silver, \"#ff0000\": void}, found %s", peri_deck_kind_name(map));
  *table = peri_calloc((size_t)map->count, sizeof(colour_entry));
  *count = map->count;
  for (int k = 0; k < map->count; ++k) {
    const peri_node *key = map->keys[k], *value = map->items[k];
    const long rgb = parse_colour(key->scalar);
    if (rgb < 0)
      return peri_deck_error(key, "key 'colors': '%s' is not a colour; write \"#rrggbb\" (quoted: # starts a "
                                  "comment in YAML)", key->scalar ? key->scalar : "");
    for (int j = 0; j < k; ++j)
      if ((*table)[j].rgb == rgb) return peri_deck_error(key, "key 'colors': colour #%06lx is given twice", rgb);
    if (!value->scalar)
      return peri_deck_error(value, "key 'colors': the colour #%06lx needs a material name or 'void', found %s", rgb,
                             peri_deck_kind_name(value));
    int32_t phase = PERI_PHASE_VOID;
    if (strcmp(value->scalar, "void") != 0) {
      const int m = peri_setup_find_material(s, value, value->scalar);
      if (m < 0) return -m;
      phase = m;
    }
    (*table)[k] = (colour_entry){rgb, phase};
  }
  return PERI_OK;
}

int peri_setup_image_fill(const peri_sim *s, const peri_node *item, double spacing, peri_fill *out) {
  memset(out, 0, sizeof *out);
  const char *section = "discretization.fill (shape image)";
  int rc = peri_deck_allow(item, section, image_keys);
  if (rc) return rc;
  if (s->disc.geom.dim != 2) return peri_deck_error(item, "shape 'image' in discretization.fill needs a 2D model");
  const char *file = NULL;
  if ((rc = peri_deck_string(item, "file", true, &file))) return rc;
  if (!peri_deck_get(item, "pixel_size"))
    return peri_deck_error(item, "missing key 'pixel_size' in %s: the side of a pixel of %s, in metres", section, file);
  double pixel = NAN, origin[3] = {0, 0, 0};
  if ((rc = peri_deck_double(item, "pixel_size", true, &pixel))) return rc;
  const peri_node *pixel_key = peri_deck_get(item, "pixel_size");
  if (!(pixel > 0)) return peri_deck_error(pixel_key, "key 'pixel_size': must be positive, got %g", pixel);
  if (spacing < pixel * (1.0 - 1e-9))
    return peri_deck_error(pixel_key, "discretization.spacing %g is finer than the pixel size %g of %s: a grid finer "
                                      "than the pixels turns their staircase into artificial sharp corners (Le 2014 "
                                      "section 3.2); use a spacing of at least one pixel", spacing, pixel, file);
  int n_origin = 0;
  if (peri_deck_get(item, "origin") && (rc = peri_deck_vector_range(item, "origin", true, 2, 2, origin, &n_origin)))
    return rc;
  const peri_node *colours = peri_deck_get(item, "colors");
  if (!colours) return peri_deck_error(item, "missing key 'colors' in %s: the material (or void) of each colour", section);
  colour_entry *table = NULL;
  int n_colours = 0;
  if ((rc = parse_colours(s, colours, &table, &n_colours))) {
    free(table);
    return rc;
  }

  char path[4096];
  peri_setup_deck_path(s, file, path, sizeof path);
  int width = 0, height = 0;
  uint8_t *rgba = NULL;
  if ((rc = peri_image_read_rgba(path, &width, &height, &rgba))) {
    free(table);
    return peri_deck_error(peri_deck_get(item, "file"), "key 'file': cannot use the image %s (above)", path);
  }
  peri_phase_map *map = peri_calloc(1, sizeof *map);
  *map = (peri_phase_map){width, height, pixel, {origin[0], origin[1]},
                          peri_malloc(sizeof(int32_t) * (size_t)width * (size_t)height)};
  int last = 0; /* neighbouring pixels mostly share a colour */
  for (size_t k = 0; k < (size_t)width * (size_t)height && rc == PERI_OK; ++k) {
    const long rgb = (long)rgba[4 * k] << 16 | (long)rgba[4 * k + 1] << 8 | rgba[4 * k + 2];
    if (table[last].rgb != rgb) {
      last = -1;
      for (int c = 0; c < n_colours && last < 0; ++c)
        if (table[c].rgb == rgb) last = c;
    }
    if (last < 0) {
      rc = peri_deck_error(colours, "image %s: pixel (%zu, %zu) (column, row from the top-left corner, from 0) has "
                                    "the colour #%06lx, which is not in 'colors'", path, k % (size_t)width,
                           k / (size_t)width, rgb);
      break;
    }
    map->phase[k] = table[last].phase;
  }
  free(rgba);
  free(table);
  if (rc) {
    peri_phase_map_free(map);
    free(map);
    return rc;
  }
  out->phases = map;
  out->material = PERI_PHASE_VOID;
  out->shape.kind = PERI_SHAPE_BOX;
  out->shape.min[0] = origin[0], out->shape.min[1] = origin[1];
  out->shape.max[0] = origin[0] + width * pixel, out->shape.max[1] = origin[1] + height * pixel;
  return PERI_OK;
}
