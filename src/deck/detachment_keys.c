/* discretization.fill items of shape 'detachment': a defect along the boundary between two
 * phases (Le 2014 section 3.4.9, its defect (f): Bi2212 detached from the silver matrix). The
 * nodes of `phase` within `thickness` of a node of `along`, inside the optional `within` shape,
 * become `material` (void: removed). It acts after every other fill shape, whatever its place
 * in the list (docs/microstructures.md section 3, docs/deck.md section 6). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/setup.h"
#include "setup_parts.h"

static const char *const detachment_keys[] = {"shape", "phase", "along", "thickness", "within", "material", NULL};

bool peri_setup_is_detachment_fill(const peri_node *item) {
  const peri_node *shape = item && item->kind == PERI_NODE_MAPPING ? peri_deck_get(item, "shape") : NULL;
  return shape && shape->scalar && strcmp(shape->scalar, "detachment") == 0;
}

/* A material of the deck by the name under `key`, or the void when allow_void and it is "void". */
static int material_key(const peri_sim *s, const peri_node *item, const char *key, bool allow_void, int32_t *out) {
  const char *name = NULL;
  int rc = peri_deck_string(item, key, true, &name);
  if (rc) return rc;
  if (allow_void && strcmp(name, "void") == 0) {
    *out = PERI_PHASE_VOID;
    return PERI_OK;
  }
  const int m = peri_setup_find_material(s, peri_deck_get(item, key), name);
  if (m < 0) return -m;
  *out = m;
  return PERI_OK;
}

int peri_setup_detachment_fill(const peri_sim *s, const peri_node *item, double spacing, peri_fill *out) {
  memset(out, 0, sizeof *out);
  const char *section = "discretization.fill (shape detachment)";
  int rc = peri_deck_allow(item, section, detachment_keys);
  if (rc) return rc;
  peri_detachment d = {0};
  if ((rc = material_key(s, item, "phase", false, &d.phase)) || (rc = material_key(s, item, "along", false, &d.along)) ||
      (rc = material_key(s, item, "material", true, &d.material)) ||
      (rc = peri_deck_double(item, "thickness", true, &d.thickness)))
    return rc;
  if (d.phase == d.along)
    return peri_deck_error(peri_deck_get(item, "along"), "key 'along': a detachment lies between two different "
                                                         "materials; 'phase' and 'along' are both '%s'",
                           peri_deck_get(item, "along")->scalar);
  if (d.material == d.phase)
    return peri_deck_error(peri_deck_get(item, "material"), "key 'material': the detached nodes would stay '%s'; "
                                                            "give 'void' or another material",
                           peri_deck_get(item, "material")->scalar);
  /* neighbouring grid nodes are one spacing apart: a thinner detachment would catch no node */
  if (!(d.thickness >= spacing * (1.0 - 1e-9)) || !isfinite(d.thickness))
    return peri_deck_error(peri_deck_get(item, "thickness"), "key 'thickness': %g is less than the node spacing %g; "
                                                             "a detachment at least one spacing thick reaches the "
                                                             "nodes next to the boundary", d.thickness, spacing);
  const peri_node *within = peri_deck_get(item, "within");
  if (within) {
    if ((rc = peri_shape_parse(within, s->disc.geom.dim, "discretization.fill (detachment within)", NULL, &out->shape)))
      return rc;
  } else {
    out->shape.kind = PERI_SHAPE_ALL;
  }
  out->material = d.material;
  out->detachment = peri_malloc(sizeof *out->detachment);
  *out->detachment = d;
  return PERI_OK;
}
