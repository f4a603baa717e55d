/* The breaking decision shared by the bond loops: a vector loop screens each family against
 * a per-node lower bound of the critical stretch, and only families with a candidate run the
 * exact scalar test below. Per-bond work does not depend on the damage law when nothing
 * breaks (docs/design.md, compact bonds). */
#include <math.h>
#include "peri/error.h"
#include "bond_kernel.h"

void peri_update_s0_bound(peri_sim *s) {
  peri_particles *p = &s->p;
  if (!p->s0_bound) p->s0_bound = peri_malloc(sizeof(double) * (size_t)(p->n > 0 ? p->n : 1));
  const int nm = s->n_materials;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n; ++i) {
    double bound = INFINITY;
    if (!(p->flags[i] & PERI_NODE_NO_FAIL)) {
      if (s->s0_node) {
        bound = s->s0_node[i];
      } else {
        const int a = p->material[i];
        for (int m = 0; m < nm; ++m) bound = fmin(bound, s->pair_s0[a * nm + m]);
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

long peri_break_family(peri_sim *s, int32_t i) {
  peri_particles *p = &s->p;
  peri_bonds *b = &s->bonds;
  long n = 0;
  for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
    if (b->broken[k]) continue;
    const int32_t j = b->neighbor[k];
    double xi[3], dy[3];
    const double r0 = peri_bond_xi(p->x, i, j, xi);
    for (int c = 0; c < 3; ++c) dy[c] = xi[c] + (p->u[3 * j + c] - p->u[3 * i + c]);
    const double r = sqrt(dy[0] * dy[0] + dy[1] * dy[1] + dy[2] * dy[2]);
    const double stretch = (r - r0) / r0 - peri_bond_thermal_stretch(s->thermal_strain, i, j);
    if (stretch > peri_bond_s0(s, i, j)) {
      b->broken[k] = 1;
      ++n;
    }
  }
  return n;
}
