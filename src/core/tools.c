/* The tools' storage (include/peri/tools.h). */
#include <stdlib.h>
#include "peri/tools.h"

void peri_tools_free(peri_tools *t) {
  if (!t) return;
  for (int k = 0; k < t->count; ++k) {
    peri_tool *tl = &t->tool[k];
    free(tl->name);
    for (int d = 0; d < 3; ++d) peri_expr_free(tl->position[d]);
    peri_expr_free(tl->load);
    free(tl->block_force);
  }
  free(t->tool);
  free(t);
}
