/* The j_integral section (docs/deck.md "J-integral", docs/plasticity.md section 6): a crack
 * tip, the direction it grows in, and square rings around it over which history.csv reports J. */
#include <math.h>
#include <string.h>
#include "peri/error.h"
#include "peri/j_integral.h"
#include "setup_parts.h"

#define TRY(expr)                   \
  do {                              \
    int rc_ = (expr);               \
    if (rc_ != PERI_OK) return rc_; \
  } while (0)

/* Default damage a node on a crack line has: about half its family lies across the crack
 * (a node next to a straight crack in 2D loses 0.3-0.5 of its bond volume), so 0.3 marks
 * the crack's nodes and not those merely near it. */
#define J_DEFAULT_DAMAGE_THRESHOLD 0.3

int peri_setup_j_integral(peri_sim *s, const peri_node *root) {
  const peri_node *it = peri_deck_get(root, "j_integral");
  if (!it) return PERI_OK;
  static const char *const keys[] = {"tip", "direction", "contours", "damage_threshold", "band", NULL};
  if (it->kind != PERI_NODE_MAPPING)
    return peri_deck_error(it, "j_integral: expected a mapping, got %s", peri_deck_kind_name(it));
  TRY(peri_deck_allow(it, "j_integral", keys));
  if (s->disc.geom.dim != 2)
    return peri_deck_error(it, "j_integral: only for dimension 2 (J per unit length of a through crack)");
  peri_j_integral j = {.direction = {1.0, 0.0, 0.0}, .damage_threshold = J_DEFAULT_DAMAGE_THRESHOLD,
                       .band = s->disc.family.horizon, .thickness = s->disc.geom.thickness};
  TRY(peri_deck_vector(it, "tip", true, 2, j.tip));
  TRY(peri_deck_vector(it, "direction", false, 2, j.direction));
  const double length = hypot(j.direction[0], j.direction[1]);
  if (!(length > 0.0) || !isfinite(length))
    return peri_deck_error(peri_deck_get(it, "direction"), "j_integral.direction: must be a nonzero vector");
  j.direction[0] /= length, j.direction[1] /= length;
  TRY(peri_deck_double(it, "damage_threshold", false, &j.damage_threshold));
  if (!(j.damage_threshold > 0.0 && j.damage_threshold <= 1.0))
    return peri_deck_error(peri_deck_get(it, "damage_threshold"), "j_integral.damage_threshold: must be in (0, 1]");
  TRY(peri_deck_double(it, "band", false, &j.band));
  if (!(j.band > 0.0)) return peri_deck_error(peri_deck_get(it, "band"), "j_integral.band: must be positive");
  const peri_node *contours = peri_deck_get(it, "contours");
  if (!contours) return peri_deck_error(it, "missing key 'contours' in j_integral");
  if (contours->kind != PERI_NODE_SEQUENCE || contours->count < 1 || contours->count > PERI_MAX_J_CONTOURS)
    return peri_deck_error(contours, "j_integral.contours: expected a list of 1 to %d [inner, outer] half-widths",
                           PERI_MAX_J_CONTOURS);
  for (int c = 0; c < contours->count; ++c) {
    const peri_node *ring = contours->items[c];
    if (ring->kind != PERI_NODE_SEQUENCE || ring->count != 2)
      return peri_deck_error(ring, "j_integral.contours: each contour is [inner, outer], the half-widths (m) of the "
                                   "square ring around the tip");
    TRY(peri_deck_node_double(ring->items[0], "j_integral.contours inner half-width", &j.inner[c]));
    TRY(peri_deck_node_double(ring->items[1], "j_integral.contours outer half-width", &j.outer[c]));
    if (!(j.inner[c] > 0.0) || !(j.outer[c] > j.inner[c]) || !isfinite(j.outer[c]))
      return peri_deck_error(ring, "j_integral.contours: need 0 < inner < outer, got [%g, %g]", j.inner[c],
                             j.outer[c]);
  }
  j.n_contours = contours->count;
  s->out.j_integral = peri_malloc(sizeof j);
  *s->out.j_integral = j;
  return PERI_OK;
}
