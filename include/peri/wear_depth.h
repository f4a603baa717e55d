/* Wear depth of a tool's scratch (src/post/wear_depth.c, docs/contact.md "Rigid tools"). */
#ifndef PERI_WEAR_DEPTH_H
#define PERI_WEAR_DEPTH_H
#include "peri/tools.h"

struct peri_sim;

/* Wear depth of the scratch of tool `tl` (Ebrahimi 2020 section 3.3.2, MODELS.md 17.3,
 * src/post/wear_depth.c): the mean displacement along the tool's direction of the nodes with
 * 0 < phi < 1 (phi the damage index, one per owned node) whose reference position lies
 * along the scratch at least two horizons from its start and from the tool's present
 * position; 0 when there is none. */
double peri_tool_wear_depth(const struct peri_sim *s, const peri_tool *tl, const double *phi);

#endif
