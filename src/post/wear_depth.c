/* Wear depth of a scratch (include/peri/tools.h; Ebrahimi 2020 section 3.3.2, MODELS.md
 * 17.3): "the average displacement of all particles with partly broken bonds (0 < D < 1),
 * located relatively far from the initial and final tip positions"; particles with D = 1 are
 * left out. Far: two horizons (MODELS.md's default) from either end along the scratch, the
 * tool's path across its direction from its start to its present position. Summed in fixed
 * order over the owned nodes of every rank. */
#include <math.h>
#include <stdlib.h>
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/sim.h"
#include "peri/tools.h"
#include "peri/wear_depth.h"

/* How far from the ends of the scratch a node must lie, in horizons (MODELS.md 17.3). */
#define WEAR_END_EXCLUSION_HORIZONS 2.0

double peri_tool_wear_depth(const peri_sim *s, const peri_tool *tl, const double *phi) {
  const peri_particles *p = &s->disc.p;
  const double *dir = tl->geom.direction;
  /* the scratch: from the start to the present position, across `direction` */
  double path[3], along = 0.0, length = 0.0;
  for (int d = 0; d < 3; ++d) path[d] = tl->at[d] - tl->start[d], along += path[d] * dir[d];
  for (int d = 0; d < 3; ++d) path[d] -= along * dir[d], length += path[d] * path[d];
  length = sqrt(length);
  const double margin = WEAR_END_EXCLUSION_HORIZONS * s->disc.geom.horizon;
  if (!(length > 2.0 * margin)) return 0.0; /* no node is far from both ends */
  const int32_t n = p->n_owned;
  double *terms = peri_calloc(2 * (size_t)(n > 0 ? n : 1), sizeof(double)); /* u . direction, 1 */
  for (int32_t i = 0; i < n; ++i) {
    if (!(phi[i] > 0.0 && phi[i] < 1.0)) continue;
    double xi = 0.0, un = 0.0;
    for (int d = 0; d < 3; ++d) {
      xi += (p->x[3 * (size_t)i + d] - tl->start[d]) * path[d] / length;
      un += p->u[3 * (size_t)i + d] * dir[d];
    }
    if (xi < margin || xi > length - margin) continue;
    terms[2 * (size_t)i] = un;
    terms[2 * (size_t)i + 1] = 1.0;
  }
  double sum[2];
  peri_sum_owned(s, terms, 2, sum);
  free(terms);
  return sum[1] > 0.0 ? sum[0] / sum[1] : 0.0;
}
