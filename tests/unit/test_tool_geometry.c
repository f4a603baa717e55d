/* Penetration into the rigid tools and the normal along which a point leaves them
 * (src/core/tool_geometry.c): exact distances of elementary geometry. */
#include <criterion/criterion.h>
#include <math.h>
#include "peri/tools.h"

#define TOL 1e-12

static double pen_at(const peri_tool_geometry *g, const double at[3], double x, double y, double z, double n[3]) {
  const double p[3] = {x, y, z};
  return peri_tool_penetration(g, at, p, n);
}

static void expect_normal(const double n[3], double a, double b, double c) {
  cr_expect_float_eq(n[0], a, TOL, "n_x %g, expected %g", n[0], a);
  cr_expect_float_eq(n[1], b, TOL, "n_y %g, expected %g", n[1], b);
  cr_expect_float_eq(n[2], c, TOL, "n_z %g, expected %g", n[2], c);
}

Test(tool_geometry, sphere_radial) {
  const peri_tool_geometry g = {.shape = PERI_TOOL_SPHERE, .radius = 2.0, .direction = {0, 0, -1}};
  const double at[3] = {1, 1, 1};
  double n[3];
  cr_expect_float_eq(pen_at(&g, at, 1, 1, -0.5, n), 0.5, TOL); /* 1.5 below the centre */
  expect_normal(n, 0, 0, -1);
  cr_expect_float_eq(pen_at(&g, at, 1 + 0.6, 1 + 0.8, 1, n), 1.0, TOL); /* r = 1 */
  expect_normal(n, 0.6, 0.8, 0);
  cr_expect(pen_at(&g, at, 1, 1, 3.5, n) < 0.0); /* outside */
}

Test(tool_geometry, cylinder_ignores_the_axis) {
  const peri_tool_geometry g = {.shape = PERI_TOOL_CYLINDER, .radius = 1.0, .direction = {0, 0, -1}, .axis = {0, 1, 0}};
  const double at[3] = {0, 0, 0};
  double n[3];
  cr_expect_float_eq(pen_at(&g, at, 0, 123.0, -0.75, n), 0.25, TOL);
  expect_normal(n, 0, 0, -1);
}

Test(tool_geometry, plane_faces_its_direction) {
  const peri_tool_geometry g = {.shape = PERI_TOOL_PLANE, .direction = {0, 0, -1}};
  const double at[3] = {5, 5, 2};
  double n[3];
  /* pressing down: the tool is the half-space above its face z = 2 */
  cr_expect_float_eq(pen_at(&g, at, -40, 7, 2.25, n), 0.25, TOL);
  expect_normal(n, 0, 0, -1);
  cr_expect_float_eq(pen_at(&g, at, 0, 0, 1.5, n), -0.5, TOL);
}

Test(tool_geometry, flat_punch_face_and_side) {
  const peri_tool_geometry g = {.shape = PERI_TOOL_FLAT_PUNCH, .radius = 1.0, .direction = {0, 0, -1}};
  const double at[3] = {0, 0, 0};
  double n[3];
  /* pressing down: the punch is above its face z = 0 */
  cr_expect_float_eq(pen_at(&g, at, 0.2, 0, 0.1, n), 0.1, TOL); /* nearer the face (0.1) than the side (0.8) */
  expect_normal(n, 0, 0, -1);
  cr_expect_float_eq(pen_at(&g, at, 0.9, 0, 0.5, n), 0.1, TOL); /* nearer the side */
  expect_normal(n, 1, 0, 0);
  cr_expect(!(pen_at(&g, at, 1.5, 0, 0.5, n) > 0.0)); /* beside the punch */
  cr_expect(!(pen_at(&g, at, 0, 0, -0.5, n) > 0.0));  /* in front of its face */
}

/* A 60 degree cone (half-angle 30) on a tip of radius 1 whose apex is at the origin, pressing
 * down: the sphere's centre is at z = 1, the cone touches it at 60 degrees from the tip, and
 * the cone's surface is rho cos 30 + (1 - z) sin 30 = 1 in (rho, z). */
Test(tool_geometry, cone_sphere_tip_and_flank) {
  const double alpha = M_PI / 6.0;
  const peri_tool_geometry g = {.shape = PERI_TOOL_CONE_SPHERE, .radius = 1.0, .half_angle = alpha, .direction = {0, 0, -1}};
  const double at[3] = {0, 0, 0};
  double n[3];
  cr_expect_float_eq(pen_at(&g, at, 0, 0, 0.2, n), 0.2, TOL); /* on the axis above the apex: the sphere */
  expect_normal(n, 0, 0, -1);
  /* at 20 degrees from the tip on a sphere of radius 0.9: the sphere part, 0.1 deep */
  const double a20 = 20.0 * M_PI / 180.0;
  cr_expect_float_eq(pen_at(&g, at, 0.9 * sin(a20), 0, 1 - 0.9 * cos(a20), n), 0.1, TOL);
  expect_normal(n, sin(a20), 0, -cos(a20));
  /* high on the flank: z = 3 (2 above the centre), rho = 2: distance to the cone line */
  const double expected = 1.0 - (2.0 * cos(alpha) + (1.0 - 3.0) * sin(alpha));
  cr_expect_float_eq(pen_at(&g, at, 0, 2.0, 3.0, n), expected, TOL);
  expect_normal(n, 0, cos(alpha), -sin(alpha));
  /* the two parts meet on the tangency circle, 60 degrees from the tip */
  const double a60 = M_PI / 3.0, r = 0.95;
  const double y = r * sin(a60), z = 1 - r * cos(a60);
  cr_expect_float_eq(pen_at(&g, at, 0, y + 1e-9, z, n), pen_at(&g, at, 0, y - 1e-9, z, n), 1e-8);
}

/* The loops' prefilter never drops a point inside a tool: over points on a grid around each
 * shape (some exactly on the surfaces), peri_tool_may_touch is true wherever the penetration
 * is positive, and false for most of the points outside the sphere, cylinder and punch. */
Test(tool_geometry, prefilter_keeps_every_point_inside) {
  const peri_tool_geometry shapes[] = {
      {.shape = PERI_TOOL_SPHERE, .radius = 0.5, .direction = {0, 0, -1}},
      {.shape = PERI_TOOL_CYLINDER, .radius = 0.5, .direction = {0, 0, -1}, .axis = {0, 0.6, 0.8}},
      {.shape = PERI_TOOL_FLAT_PUNCH, .radius = 0.5, .direction = {0.6, 0, -0.8}},
      {.shape = PERI_TOOL_CONE_SPHERE, .radius = 0.5, .half_angle = 0.7, .direction = {0, 0, -1}},
      {.shape = PERI_TOOL_PLANE, .direction = {0, 0, -1}},
  };
  const double at[3] = {0.1, -0.2, 0.05};
  for (size_t k = 0; k < sizeof shapes / sizeof shapes[0]; ++k) {
    long inside = 0, dropped = 0, outside = 0;
    for (int a = -20; a <= 20; ++a)
      for (int b = -20; b <= 20; ++b)
        for (int c = -20; c <= 20; ++c) {
          const double y[3] = {at[0] + 0.05 * a, at[1] + 0.05 * b, at[2] + 0.05 * c};
          double n[3];
          const double pen = peri_tool_penetration(&shapes[k], at, y, n);
          const bool may = peri_tool_may_touch(&shapes[k], at, y);
          inside += pen > 0.0, outside += !(pen > 0.0), dropped += !may;
          cr_assert(may || !(pen > 0.0), "shape %zu: the point (%g, %g, %g), %g deep, dropped", k, y[0], y[1], y[2],
                    pen);
        }
    cr_assert_gt(inside, 0, "shape %zu: no point inside", k);
    if (shapes[k].shape != PERI_TOOL_CONE_SPHERE && shapes[k].shape != PERI_TOOL_PLANE)
      cr_expect_gt(dropped, outside / 2, "shape %zu: %ld of %ld points outside dropped", k, dropped, outside);
  }
}
