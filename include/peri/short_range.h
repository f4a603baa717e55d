/* The short-range contact forces' functions (src/solver/contributions/short_range.c; the
 * force itself is the contribution peri_contribution_short_range, contribution.h). */
#ifndef PERI_SHORT_RANGE_H
#define PERI_SHORT_RANGE_H
#include "peri/contact.h"

struct peri_sim;

/* The short-range force's constants of each material, once the model's are known. */
void peri_contact_init(struct peri_sim *s);
/* The contact distance of the farthest pair, 1.35 dx. */
double peri_contact_max_reach(const struct peri_sim *s);
/* The smallest |y_i - y_j| / d_ij over every pair of every rank at the last evaluation of the
 * forces, at most 1 (history column short_range_min_ratio). Collective. */
double peri_contact_min_ratio(const struct peri_sim *s);

/* Pairs (i, j) in the pair lists of every rank, each counted from both ends. Collective. */
long peri_contact_pairs(const struct peri_sim *s);
/* Pairs in the pruned lists of every rank (those the forces visit). Collective. */
long peri_contact_pruned_pairs(const struct peri_sim *s);
/* Contact ghosts of every rank at the last build of the lists (0 in one process). Collective. */
long peri_contact_ghost_count(const struct peri_sim *s);
void peri_contact_free(peri_contact *c);

#endif
