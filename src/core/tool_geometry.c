/* Penetration of a point into a rigid tool and the normal along which it leaves
 * (include/peri/tools.h). Each shape is convex, so the shortest way out is through the
 * nearest face: the sphere's and cylinder's radius, the plane, the punch's face or side, and
 * for the conospherical tip the sphere below the tangency circle and the cone above it. */
#include <math.h>
#include "peri/tools.h"

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Radial leaving: pen = R - |w|, n = w / |w|. */
static double radial(double R, const double w[3], double r, double n[3]) {
  const double pen = R - r;
  if (pen > 0.0 && r > 0.0)
    for (int d = 0; d < 3; ++d) n[d] = w[d] / r;
  return r > 0.0 ? pen : 0.0; /* on the centre (or axis): no direction, no force */
}

double peri_tool_penetration(const peri_tool_geometry *g, const double position[3], const double y[3], double n[3]) {
  double w[3];
  for (int d = 0; d < 3; ++d) w[d] = y[d] - position[d];
  const double *dir = g->direction;
  switch (g->shape) {
  case PERI_TOOL_SPHERE: return radial(g->radius, w, sqrt(dot3(w, w)), n);
  case PERI_TOOL_CYLINDER: {
    const double along = dot3(w, g->axis);
    double rho[3];
    for (int d = 0; d < 3; ++d) rho[d] = w[d] - along * g->axis[d];
    return radial(g->radius, rho, sqrt(dot3(rho, rho)), n);
  }
  case PERI_TOOL_PLANE: {
    const double pen = -dot3(w, dir); /* the tool lies behind its face, against `direction` */
    if (pen > 0.0)
      for (int d = 0; d < 3; ++d) n[d] = dir[d];
    return pen;
  }
  case PERI_TOOL_FLAT_PUNCH: {
    const double s = dot3(w, dir);
    double rho[3];
    for (int d = 0; d < 3; ++d) rho[d] = w[d] - s * dir[d];
    const double r = sqrt(dot3(rho, rho)), face = -s, side = g->radius - r;
    if (!(face > 0.0) || !(side > 0.0)) return 0.0;
    if (face <= side || r == 0.0) {
      for (int d = 0; d < 3; ++d) n[d] = dir[d];
      return face;
    }
    for (int d = 0; d < 3; ++d) n[d] = rho[d] / r;
    return side;
  }
  case PERI_TOOL_CONE_SPHERE: {
    /* the position is the apex of the tip; the sphere's centre is R behind it */
    const double R = g->radius, sa = sin(g->half_angle), ca = cos(g->half_angle);
    for (int d = 0; d < 3; ++d) w[d] += R * dir[d];
    const double z = dot3(w, dir), r = sqrt(dot3(w, w));
    if (z >= r * sa) return radial(R, w, r, n); /* below the tangency circle: the sphere */
    double rho[3];
    for (int d = 0; d < 3; ++d) rho[d] = w[d] - z * dir[d];
    double rr = sqrt(dot3(rho, rho));
    const double pen = R - (rr * ca + z * sa); /* the cone's surface: rho cos(alpha) + z sin(alpha) = R */
    if (!(pen > 0.0)) return pen;
    if (rr == 0.0) { /* on the axis: any radial direction is as short */
      const double e[3] = {fabs(dir[0]) < 0.9 ? 1.0 : 0.0, fabs(dir[0]) < 0.9 ? 0.0 : 1.0, 0.0};
      const double along = dot3(e, dir);
      for (int d = 0; d < 3; ++d) rho[d] = e[d] - along * dir[d];
      rr = sqrt(dot3(rho, rho));
    }
    for (int d = 0; d < 3; ++d) n[d] = ca * rho[d] / rr + sa * dir[d];
    return pen;
  }
  }
  return 0.0;
}
