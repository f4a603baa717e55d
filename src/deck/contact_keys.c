/* The contact section of the deck (docs/deck.md "Contact", docs/contact.md): short-range
 * forces and their settings. */
#include <math.h>
#include <string.h>
#include "peri/contact.h"
#include "peri/short_range.h"
#include "peri/error.h"
#include "setup_parts.h"

#define TRY(x) do { int rc_ = (x); if (rc_ != PERI_OK) return rc_; } while (0)

/* Default skin of the pair list, in node spacings: a list kept for a displacement of
 * skin/2 = 0.15 dx between builds (docs/contact.md, "Cost"). */
#define DEFAULT_SKIN_SPACINGS 0.3
/* Default skin of the pruned list: below the 0.1 dx by which the nearest neighbours of a
 * lattice at rest (dx apart) are out of contact (0.9 dx), so that the forces visit no pair of
 * a body at rest or strained less than 2%; the pruned list is kept for a displacement of
 * 0.04 dx (docs/contact.md, "The pair list"). */
#define DEFAULT_PRUNE_SKIN_SPACINGS 0.08

int peri_setup_contact(peri_sim *s, const peri_node *root) {
  const peri_node *contact = peri_deck_get(root, "contact");
  if (!contact) return PERI_OK;
  static const char *const keys[] = {"short_range", NULL};
  TRY(peri_deck_allow(contact, "contact", keys));
  const peri_node *sr = peri_deck_get(contact, "short_range");
  if (!sr) return PERI_OK;
  bool on = true;
  if (sr->kind != PERI_NODE_MAPPING) TRY(peri_deck_bool(contact, "short_range", true, &on));
  if (!on) return PERI_OK;
  peri_contact *c = peri_calloc(1, sizeof *c);
  s->contact = c;
  c->short_range = true;
  c->stiffness_factor = PERI_SHORT_RANGE_FACTOR;
  c->skin = DEFAULT_SKIN_SPACINGS * s->disc.geom.spacing;
  c->prune_skin = DEFAULT_PRUNE_SKIN_SPACINGS * s->disc.geom.spacing;
  if (sr->kind == PERI_NODE_MAPPING) {
    static const char *const sr_keys[] = {"stiffness_factor", "skin", "prune_skin", NULL};
    TRY(peri_deck_allow(sr, "contact.short_range", sr_keys));
    TRY(peri_deck_double(sr, "stiffness_factor", false, &c->stiffness_factor));
    TRY(peri_deck_double(sr, "skin", false, &c->skin));
    const bool prune_given = peri_deck_get(sr, "prune_skin") != NULL;
    TRY(peri_deck_double(sr, "prune_skin", false, &c->prune_skin));
    if (!(c->stiffness_factor > 0.0) || !isfinite(c->stiffness_factor))
      return peri_deck_error(peri_deck_get(sr, "stiffness_factor"), "key 'stiffness_factor': must be a positive number");
    if (!(c->skin > 0.0) || !isfinite(c->skin))
      return peri_deck_error(peri_deck_get(sr, "skin"), "key 'skin': must be a positive length (m)");
    if (!(c->prune_skin > 0.0) || !isfinite(c->prune_skin))
      return peri_deck_error(peri_deck_get(sr, "prune_skin"), "key 'prune_skin': must be a positive length (m)");
    if (prune_given && c->prune_skin > c->skin)
      return peri_deck_error(peri_deck_get(sr, "prune_skin"),
                             "key 'prune_skin': %g m is larger than the list's skin %g m (it prunes that list)",
                             c->prune_skin, c->skin);
  }
  if (c->prune_skin > c->skin) c->prune_skin = c->skin; /* a small skin given alone: nothing to prune */
  if (s->solver.kind == PERI_SOLVER_IMPLICIT)
    return peri_deck_error(sr, "contact.short_range: the implicit solver has no tangent of the short-range "
                               "forces; use solver.type explicit, adr, dynamic_relaxation or nlcg");
  if (s->solver.kind == PERI_SOLVER_HEAT)
    return peri_deck_error(sr, "contact.short_range: a heat conduction run has no forces");
  peri_contact_init(s);
  return PERI_OK;
}
