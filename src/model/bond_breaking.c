/* The breaking decision shared by the bond loops: a vector loop screens each family against
 * a per-node lower bound of the critical stretch (kept here), and only families with a
 * candidate run the exact test (peri_node_blocks_break_family). Per-bond work does not depend
 * on the damage law when nothing breaks (docs/design.md, compact bonds). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "bond_kernel.h"

void peri_update_s0_bound(peri_sim *s) {
  peri_particles *p = &s->disc.p;
  if (!p->s0_bound) p->s0_bound = peri_malloc(sizeof(double) * (size_t)(p->n > 0 ? p->n : 1));
  const int nm = s->mat.n_materials;
  /* each material's bound, the smallest entry of its row of the pair table, once per call */
  double *row_min = peri_malloc(sizeof(double) * (size_t)(nm > 0 ? nm : 1));
  for (int a = 0; a < nm; ++a) {
    row_min[a] = INFINITY;
    for (int m = 0; m < nm; ++m) row_min[a] = fmin(row_min[a], s->mat.pair_s0[a * nm + m]);
  }
  const double *s0_node = s->mat.s0_node;
  const double first = p->n > 0 && !(p->flags[0] & PERI_NODE_NO_FAIL)
                           ? (s0_node ? s0_node[0] : row_min[p->material[0]])
                           : INFINITY;
  bool uniform = true;
#pragma omp parallel for schedule(static) reduction(&& : uniform)
  for (int32_t i = 0; i < p->n; ++i) {
    const double bound = p->flags[i] & PERI_NODE_NO_FAIL ? INFINITY : s0_node ? s0_node[i] : row_min[p->material[i]];
    p->s0_bound[i] = bound;
    uniform = uniform && bound == first;
  }
  p->s0_bound_uniform = uniform;
  free(row_min);
}

bool peri_uniform_volume(const peri_particles *p) {
  bool same = true;
#pragma omp parallel for schedule(static) reduction(&& : same)
  for (int32_t i = 1; i < p->n; ++i) same = same && p->volume[i] == p->volume[0];
  return same;
}

long peri_force_in_breaking_order(peri_sim *s, peri_force_pass pass) {
  if (!s->solver.breaking || !s->solver.break_after_force) return pass(s, true);
  /* the force of the bonds as they are (no s0 update: the test below still uses the
   * previous evaluation's critical stretches), kept; then the cut at the same displacement,
   * whose recomputed forces are dropped. Both passes are those of the default order, so the
   * result has their thread and rank invariance. */
  peri_particles *p = &s->disc.p;
  const size_t n3 = 3 * (size_t)p->n_owned;
  s->solver.breaking = false;
  pass(s, false);
  s->solver.breaking = true;
  double *kept = peri_malloc(sizeof(double) * (n3 > 0 ? n3 : 1));
  memcpy(kept, p->f, sizeof(double) * n3);
  const long broken = pass(s, true);
  memcpy(p->f, kept, sizeof(double) * n3);
  free(kept);
  return broken;
}
