/* The breaking decision shared by the bond loops: a vector loop screens each family against
 * a per-node lower bound of the critical stretch (kept here), and only families with a
 * candidate run the exact test (peri_node_blocks_break_family). Per-bond work does not depend
 * on the damage law when nothing breaks (docs/design.md, compact bonds). */
#include <math.h>
#include "peri/error.h"
#include "bond_kernel.h"

void peri_update_s0_bound(peri_sim *s) {
  peri_particles *p = &s->disc.p;
  if (!p->s0_bound) p->s0_bound = peri_malloc(sizeof(double) * (size_t)(p->n > 0 ? p->n : 1));
  const int nm = s->mat.n_materials;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n; ++i) {
    double bound = INFINITY;
    if (!(p->flags[i] & PERI_NODE_NO_FAIL)) {
      if (s->mat.s0_node) {
        bound = s->mat.s0_node[i];
      } else {
        const int a = p->material[i];
        for (int m = 0; m < nm; ++m) bound = fmin(bound, s->mat.pair_s0[a * nm + m]);
      }
    }
    p->s0_bound[i] = bound;
  }
}

bool peri_uniform_volume(const peri_particles *p) {
  bool same = true;
#pragma omp parallel for schedule(static) reduction(&& : same)
  for (int32_t i = 1; i < p->n; ++i) same = same && p->volume[i] == p->volume[0];
  return same;
}
