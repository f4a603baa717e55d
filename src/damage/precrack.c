/* Pre-cracks: bonds that cross a crack segment (2D) or rectangle (3D) are removed
 * (Ebrahimi 2020 sec. 5.2.1; Bobaru & Duangpanya 2012 sec. 3.4; docs/model_reference.md 7.4). */
#include <math.h>
#include "peri/damage.h"

static double cross2(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

static bool cuts_segment(const peri_precrack *c, double dx, const double A[3], const double B[3]) {
  double ex = c->b[0] - c->a[0], ey = c->b[1] - c->a[1];
  double len = hypot(ex, ey);
  if (len == 0.0) return false;
  /* shift along the unit normal so that nodes on the line are on one side */
  double shift = 1e-6 * dx;
  double nx = -ey / len * shift, ny = ex / len * shift;
  double C[2] = {c->a[0] + nx, c->a[1] + ny}, D[2] = {c->b[0] + nx, c->b[1] + ny};
  double abx = B[0] - A[0], aby = B[1] - A[1];
  double s1 = cross2(C[0] - A[0], C[1] - A[1], abx, aby);
  double s2 = cross2(D[0] - A[0], D[1] - A[1], abx, aby);
  double cdx = D[0] - C[0], cdy = D[1] - C[1];
  double s3 = cross2(A[0] - C[0], A[1] - C[1], cdx, cdy);
  double s4 = cross2(B[0] - C[0], B[1] - C[1], cdx, cdy);
  return s1 * s2 < 0.0 && s3 * s4 < 0.0;
}

static bool cuts_rectangle(const peri_precrack *c, double dx, const double P[3], const double Q[3]) {
  const double *e1 = c->e1, *e2 = c->e2;
  double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                 e1[0] * e2[1] - e1[1] * e2[0]};
  double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (nn == 0.0) return false;
  for (int d = 0; d < 3; ++d) n[d] /= nn;
  double shift = 1e-6 * dx;
  double dP = 0.0, dQ = 0.0;
  for (int d = 0; d < 3; ++d) {
    dP += (P[d] - c->a[d]) * n[d];
    dQ += (Q[d] - c->a[d]) * n[d];
  }
  dP -= shift;
  dQ -= shift;
  if (!(dP * dQ < 0.0)) return false;
  double t = dP / (dP - dQ);
  double s1 = 0.0, s2 = 0.0, l1 = 0.0, l2 = 0.0;
  for (int d = 0; d < 3; ++d) {
    double X = P[d] + t * (Q[d] - P[d]) - c->a[d];
    s1 += X * e1[d];
    s2 += X * e2[d];
    l1 += e1[d] * e1[d];
    l2 += e2[d] * e2[d];
  }
  return s1 >= 0.0 && s1 <= l1 && s2 >= 0.0 && s2 <= l2;
}

bool peri_precrack_cuts(const peri_precrack *c, double dx, const double xi[3], const double xj[3]) {
  return c->dim == 3 ? cuts_rectangle(c, dx, xi, xj) : cuts_segment(c, dx, xi, xj);
}

long peri_precracks_apply(peri_sim *s) {
  if (s->cond.n_precracks == 0) return 0;
  const peri_particles *p = &s->disc.p;
  peri_bonds *b = &s->disc.bonds;
  long cut = 0;
  /* The test is evaluated with the lower index first so both directions agree exactly. */
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : cut)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      int32_t j = b->neighbor[k];
      int32_t lo = i < j ? i : j, hi = i < j ? j : i;
      for (int c = 0; c < s->cond.n_precracks; ++c) {
        if (peri_precrack_cuts(&s->cond.precracks[c], s->disc.geom.spacing, &p->x[3 * lo], &p->x[3 * hi])) {
          if (!b->broken[k]) ++cut;
          b->broken[k] = 1;
          break;
        }
      }
    }
  }
  ++b->broken_edits;
  return cut;
}
