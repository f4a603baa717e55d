/* Command-line overrides of deck values: "--set key.path=value" (docs/deck.md). Applied to
 * the YAML tree before the deck is parsed, so every check of the parser applies to them;
 * the nodes they bring are positioned "--set:K:C" (K-th --set option, column C of its
 * argument). Path components are mapping keys, or 0-based indices into lists
 * (boundary_conditions.1.layer). The value is YAML: a number, a string, [a, b], {k: v}. */
#ifndef PERI_OVERRIDES_H
#define PERI_OVERRIDES_H
#include "peri/deck.h"

/* Applies the n overrides in order to the tree of `root`. The documents that own the new
 * nodes (and the replaced ones) are returned in *keep (n entries) and must outlive the tree:
 * free them with peri_overrides_free after peri_deck_free(root). Returns PERI_OK, or
 * PERI_ERR_INPUT after a positioned message. */
int peri_deck_apply_overrides(peri_node *root, int n, const char *const *sets, peri_node ***keep);
void peri_overrides_free(peri_node **keep, int n);

#endif
