/* Region and material names of the deck to their indices, with a suggestion for a misspelt name. */
#include <string.h>
#include "peri/deck.h"
#include "peri/error.h"
#include "setup_parts.h"

int peri_setup_find_region(const peri_sim *s, const peri_node *regions, const peri_node *at,
                           const char *name) {
  if (strcmp(name, "all") == 0) return 0;
  /* regions[k + 1] is the deck's k-th region: a binary search, not a scan per condition */
  int index = peri_deck_key_index(regions, name);
  if (index >= 0 && index + 1 < s->cond.n_regions) return index + 1;
  int best = -1, best_d = 1 << 30;
  for (int r = 0; r < s->cond.n_regions; ++r) {
    int d = peri_edit_distance(name, s->cond.regions[r].name);
    if (d < best_d) best_d = d, best = r;
  }
  if (best >= 0 && best_d <= 2)
    return -peri_deck_error(at, "unknown region '%s'; did you mean '%s'?", name, s->cond.regions[best].name);
  return -peri_deck_error(at, "unknown region '%s' (define it under regions; 'all' is predefined)", name);
}

int peri_setup_find_material(const peri_sim *s, const peri_node *at, const char *name) {
  for (int m = 0; m < s->mat.n_materials; ++m)
    if (strcmp(s->mat.materials[m].name, name) == 0) return m;
  int best = -1, best_d = 1 << 30;
  for (int m = 0; m < s->mat.n_materials; ++m) {
    int d = peri_edit_distance(name, s->mat.materials[m].name);
    if (d < best_d) best_d = d, best = m;
  }
  if (best >= 0 && best_d <= 2)
    return -peri_deck_error(at, "unknown material '%s'; did you mean '%s'?", name, s->mat.materials[best].name);
  return -peri_deck_error(at, "unknown material '%s' (define it under materials)", name);
}
