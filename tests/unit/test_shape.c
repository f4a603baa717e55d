/* Shapes: containment, bounds, and parsing from deck mappings. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "peri/deck.h"
#include "peri/error.h"
#include "peri/setup.h"
#include "peri/shape.h"

static char msg[4096];

/* Parses `text` (a deck whose key "s" holds the shape) into *out; captures stderr in msg. */
static int parse(const char *text, int dim, const char *const *extra, peri_shape *out) {
  fflush(stderr);
  FILE *tmp = tmpfile();
  cr_assert_not_null(tmp);
  int saved = dup(2);
  dup2(fileno(tmp), 2);
  peri_node *root = peri_deck_parse_string(text, "deck.yaml");
  int rc = root ? peri_shape_parse(peri_deck_get(root, "s"), dim, "regions.s", extra, out) : -1;
  fflush(stderr);
  dup2(saved, 2);
  close(saved);
  rewind(tmp);
  size_t n = fread(msg, 1, sizeof msg - 1, tmp);
  msg[n] = '\0';
  fclose(tmp);
  peri_deck_free(root);
  return rc;
}

#define PT(a, b, c) ((const double[3]){a, b, c})

Test(shape, box) {
  peri_shape s;
  cr_assert_eq(parse("s: {shape: rectangle, min: [0, 0], max: [0.1, 0.04]}", 2, NULL, &s), 0, "%s",
               msg);
  cr_assert_eq(s.kind, PERI_SHAPE_BOX);
  cr_assert(peri_shape_contains(&s, 2, PT(0, 0, 0), 0));
  cr_assert(peri_shape_contains(&s, 2, PT(0.1, 0.04, 5), 0)); /* z is ignored in 2D */
  cr_assert(!peri_shape_contains(&s, 2, PT(0.1 + 1e-6, 0.02, 0), 0));
  cr_assert(peri_shape_contains(&s, 2, PT(0.1 + 1e-6, 0.02, 0), 2e-6));
  double lo[3], hi[3];
  cr_assert(peri_shape_bounds(&s, 2, lo, hi));
  cr_assert_eq(hi[0], 0.1);
  cr_assert_eq(hi[1], 0.04);
  cr_assert_eq(hi[2], 0.0);
  peri_shape_free(&s);
  cr_assert_eq(parse("s: {shape: box, min: [0, 0, 0], max: [1, 2, 3]}", 3, NULL, &s), 0, "%s", msg);
  cr_assert(peri_shape_contains(&s, 3, PT(1, 2, 3), 0));
  cr_assert(!peri_shape_contains(&s, 3, PT(1, 2, 3.1), 0));
  cr_assert_eq(parse("s: {shape: interval, min: [-1], max: [1]}", 1, NULL, &s), 0, "%s", msg);
  cr_assert(peri_shape_contains(&s, 1, PT(-1, 7, 7), 0));
}

Test(shape, sphere_and_aliases) {
  const char *names[] = {"sphere", "circle", "disk"};
  for (int i = 0; i < 3; i++) {
    char text[128];
    snprintf(text, sizeof text, "s: {shape: %s, center: [0.05, 0.02], radius: 0.01}", names[i]);
    peri_shape s;
    cr_assert_eq(parse(text, 2, NULL, &s), 0, "%s", msg);
    cr_assert_eq(s.kind, PERI_SHAPE_SPHERE);
    cr_assert(peri_shape_contains(&s, 2, PT(0.06, 0.02, 0), 1e-12));
    cr_assert(!peri_shape_contains(&s, 2, PT(0.06, 0.021, 0), 1e-12));
    double lo[3], hi[3];
    cr_assert(peri_shape_bounds(&s, 2, lo, hi));
    cr_assert_float_eq(lo[0], 0.04, 1e-15);
    cr_assert_float_eq(hi[1], 0.03, 1e-15);
  }
  peri_shape s;
  cr_assert_eq(parse("s: {shape: sphere, center: [0, 0, 0], radius: 1}", 3, NULL, &s), 0, "%s",
               msg);
  cr_assert(peri_shape_contains(&s, 3, PT(0.5, 0.5, 0.5), 0));
  cr_assert(!peri_shape_contains(&s, 3, PT(0.6, 0.6, 0.6), 0));
}

Test(shape, cylinder) {
  peri_shape s;
  cr_assert_eq(parse("s: {shape: cylinder, center: [0, 0, 0], axis: z, radius: 0.025, "
                     "inner_radius: 0.02, length: 0.1}",
                     3, NULL, &s),
               0, "%s", msg);
  cr_assert_eq(s.kind, PERI_SHAPE_CYLINDER);
  cr_assert_eq(s.axis, 2);
  cr_assert(peri_shape_contains(&s, 3, PT(0.022, 0, 0.05), 0));
  cr_assert(peri_shape_contains(&s, 3, PT(0.02, 0, 0.1), 0));
  cr_assert(!peri_shape_contains(&s, 3, PT(0.01, 0, 0.05), 0)); /* in the bore */
  cr_assert(!peri_shape_contains(&s, 3, PT(0.03, 0, 0.05), 0));
  cr_assert(!peri_shape_contains(&s, 3, PT(0.022, 0, 0.11), 0));
  cr_assert(!peri_shape_contains(&s, 3, PT(0.022, 0, -0.01), 0));
  double lo[3], hi[3];
  cr_assert(peri_shape_bounds(&s, 3, lo, hi));
  cr_assert_eq(lo[2], 0.0);
  cr_assert_eq(hi[2], 0.1);
  cr_assert_eq(lo[0], -0.025);
  cr_assert_eq(parse("s: {shape: cylinder, center: [0, -0.005, 0], axis: y, radius: 0.005, "
                     "length: 0.005}",
                     3, NULL, &s),
               0, "%s", msg);
  cr_assert_eq(s.axis, 1);
  cr_assert_eq(s.inner_radius, 0.0);
  cr_assert(peri_shape_contains(&s, 3, PT(0.003, 0, 0.004), 1e-12));
  cr_assert(peri_shape_contains(&s, 3, PT(0, -0.005, 0), 0));
  /* A truncated cone: radius 2 at the base z = 1, 1 at the top z = 3, so 1.5 half-way. */
  cr_assert_eq(parse("s: {shape: cylinder, center: [0, 0, 1], axis: z, radius: 2, "
                     "top_radius: 1, length: 2}",
                     3, NULL, &s),
               0, "%s", msg);
  cr_assert(peri_shape_contains(&s, 3, PT(1.49, 0, 2), 0));
  cr_assert(!peri_shape_contains(&s, 3, PT(1.51, 0, 2), 0));
  cr_assert(peri_shape_contains(&s, 3, PT(0, 1.99, 1), 0));
  cr_assert(!peri_shape_contains(&s, 3, PT(0, 1.01, 3), 0));
  cr_assert(peri_shape_bounds(&s, 3, lo, hi));
  cr_assert_eq(lo[0], -2.0);
  cr_assert_eq(hi[1], 2.0);
}

Test(shape, polygon) {
  peri_shape s;
  /* an L shape: concave, to exercise the even-odd test */
  cr_assert_eq(parse("s: {shape: polygon, vertices: [[0,0], [2,0], [2,1], [1,1], [1,2], [0,2]]}", 2,
                     NULL, &s),
               0, "%s", msg);
  cr_assert_eq(s.kind, PERI_SHAPE_POLYGON);
  cr_assert_eq(s.n_vertices, 6);
  cr_assert(peri_shape_contains(&s, 2, PT(0.5, 0.5, 0), 0));
  cr_assert(peri_shape_contains(&s, 2, PT(1.5, 0.5, 0), 0));
  cr_assert(peri_shape_contains(&s, 2, PT(0.5, 1.5, 0), 0));
  cr_assert(!peri_shape_contains(&s, 2, PT(1.5, 1.5, 0), 0));
  cr_assert(!peri_shape_contains(&s, 2, PT(-0.1, 0.5, 0), 0));
  /* boundary, vertices and the re-entrant corner count as inside */
  cr_assert(peri_shape_contains(&s, 2, PT(2, 0.5, 0), 1e-12));
  cr_assert(peri_shape_contains(&s, 2, PT(1.5, 1, 0), 1e-12));
  cr_assert(peri_shape_contains(&s, 2, PT(1, 1, 0), 1e-12));
  cr_assert(peri_shape_contains(&s, 2, PT(0, 2, 0), 1e-12));
  cr_assert(peri_shape_contains(&s, 2, PT(1.5, 1 + 1e-10, 0), 1e-9));
  cr_assert(!peri_shape_contains(&s, 2, PT(1.5, 1 + 1e-8, 0), 1e-9));
  double lo[3], hi[3];
  cr_assert(peri_shape_bounds(&s, 2, lo, hi));
  cr_assert_eq(lo[0], 0.0);
  cr_assert_eq(hi[1], 2.0);
  peri_shape_free(&s);
  cr_assert_null(s.vertices);
}

Test(shape, all_and_extra_keys) {
  peri_shape s;
  const char *const extra[] = {"material", "name", NULL};
  cr_assert_eq(parse("s: {shape: all, material: glass}", 3, extra, &s), 0, "%s", msg);
  cr_assert_eq(s.kind, PERI_SHAPE_ALL);
  cr_assert(peri_shape_contains(&s, 3, PT(1e9, -1e9, 0), 0));
  double lo[3], hi[3];
  cr_assert(!peri_shape_bounds(&s, 3, lo, hi));
  cr_assert_eq(parse("s: {shape: box, min: [0,0], max: [1,1], name: top}", 2, extra, &s), 0, "%s",
               msg);
}

static void expect_error(const char *text, int dim, const char *want1, const char *want2) {
  peri_shape s;
  memset(&s, 0, sizeof s);
  int rc = parse(text, dim, NULL, &s);
  cr_expect_eq(rc, PERI_ERR_INPUT, "%s: rc %d", text, rc);
  cr_expect(strstr(msg, want1), "%s\n  message: %s\n  wanted: %s", text, msg, want1);
  if (want2) cr_expect(strstr(msg, want2), "%s\n  message: %s\n  wanted: %s", text, msg, want2);
  cr_expect_null(s.vertices);
}

Test(shape, errors) {
  expect_error("s: {shape: bx, min: [0,0], max: [1,1]}", 2, "deck.yaml:1:", "did you mean 'box'");
  expect_error("s: {shape: box, min: [0,0], mx: [1,1]}", 2, "unknown key 'mx' in regions.s",
               "did you mean 'max'");
  expect_error("s: {shpe: box, min: [0,0], max: [1,1]}", 2, "unknown key 'shpe'", "'shape'");
  expect_error("s: {min: [0,0], max: [1,1]}", 2, "missing key 'shape' in regions.s", NULL);
  expect_error("s: {shape: box, min: [0,0], max: [1,1], radius: 2}", 2,
               "key 'radius' does not apply to shape 'box'", NULL);
  expect_error("s: {shape: box, min: [0], max: [1,1]}", 2, "min", "2 to 3 numbers");
  expect_error("s: {shape: box, min: [0,2], max: [1,1]}", 2, "'max' must not be below 'min'", NULL);
  expect_error("s: {shape: circle, center: [0,0], radius: -1}", 2, "radius", "positive");
  expect_error("s: {shape: circle, center: [0,0]}", 2, "missing key 'radius'", NULL);
  expect_error("s: {shape: cylinder, center: [0,0,0], axis: w, radius: 1, length: 1}", 3, "axis",
               "choices");
  expect_error("s: {shape: cylinder, center: [0,0,0], axis: x, radius: 1, length: 1, "
               "inner_radius: 2}",
               3, "inner_radius", NULL);
  expect_error("s: {shape: cylinder, center: [0,0,0], axis: x, radius: 2, length: 1, "
               "top_radius: 1, inner_radius: 1.5}",
               3, "inner_radius", "min(radius, top_radius)");
  expect_error("s: {shape: cylinder, center: [0,0,0], axis: x, radius: 2, length: 1, "
               "top_radius: -1}",
               3, "top_radius", ">= 0");
  expect_error("s: {shape: cylinder, center: [0,0], axis: x, radius: 1, length: 1}", 2,
               "needs a 3D model", NULL);
  expect_error("s: {shape: polygon, vertices: [[0,0], [1,0]]}", 2, "at least 3", NULL);
  expect_error("s: {shape: polygon, vertices: [[0,0], [1,0], [1]]}", 2, "vertex 3", NULL);
  expect_error("s: {shape: polygon, vertices: [[0,0], [1,0], [1,q]]}", 2, "deck.yaml:1:", NULL);
  expect_error("s: {shape: polygon, vertices: [[0,0], [1,0], [1,1]]}", 3, "2D", NULL);
  expect_error("s: [1, 2]", 2, "must be a mapping", NULL);
}
