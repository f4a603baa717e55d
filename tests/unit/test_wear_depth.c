/* Wear depth of a scratch (src/post/wear_depth.c; Ebrahimi 2020 section 3.3.2, MODELS.md
 * 17.3): the mean displacement along the tool's direction of the nodes with 0 < D < 1 that
 * lie along the scratch at least two horizons from both ends. A hand-made state: the
 * expected value is the mean of the two nodes the definition keeps. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include "peri/tools.h"
#include "peri/wear_depth.h"
#include "support.h"

/* 30 x 5 mm at 1 mm spacing, m = 3: delta = 3 mm, so the ends' margins are 6 mm. */
static const char *deck =
    "dimension: 2\n"
    "materials: {m: {model: pmb, density: 1000, youngs_modulus: 1e9}}\n"
    "discretization: {spacing: 0.001, m: 3, fill: [{shape: rectangle, min: [0, 0], max: [0.030, 0.005]}]}\n"
    "tools:\n"
    "  - {name: tip, shape: sphere, radius: 0.001, direction: [0, -1], position: [\"t\", 0.010], stiffness: 1e20}\n"
    "solver: {type: explicit, steps: 1}\n"
    "output: {picture: false}\n";

/* The node nearest to (x, y). */
static int32_t node_at(const peri_sim *s, double x, double y) {
  int32_t best = -1;
  double d2 = INFINITY;
  for (int32_t i = 0; i < s->disc.p.n; ++i) {
    const double dx = s->disc.p.x[3 * i] - x, dy = s->disc.p.x[3 * i + 1] - y;
    if (dx * dx + dy * dy < d2) d2 = dx * dx + dy * dy, best = i;
  }
  return best;
}

Test(wear_depth, mean_of_partly_damaged_nodes_away_from_the_ends) {
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  peri_tool *tl = &s.tools->tool[0];
  const double start[3] = {0.0, 0.010, 0.0}, end[3] = {0.030, 0.010, 0.0};
  for (int d = 0; d < 3; ++d) tl->start[d] = start[d], tl->at[d] = end[d];
  const int32_t n = s.disc.p.n;
  double *phi = calloc((size_t)n, sizeof(double));
  struct {
    double x, y, phi, uy;
    bool kept;
  } cases[] = {
      {0.0155, 0.0045, 0.5, -2.0e-6, true},    /* mid-scratch, partly damaged: 2 um deep */
      {0.0105, 0.0045, 0.25, -4.0e-6, true},   /* 4 um deep */
      {0.0025, 0.0045, 0.5, -100e-6, false},   /* within 6 mm of the start */
      {0.0275, 0.0045, 0.5, -100e-6, false},   /* within 6 mm of the end */
      {0.0155, 0.0035, 1.0, -100e-6, false},   /* D = 1: left out */
      {0.0125, 0.0045, 0.0, -50e-6, false},    /* intact */
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
    const int32_t i = node_at(&s, cases[k].x, cases[k].y);
    phi[i] = cases[k].phi;
    s.disc.p.u[3 * i + 1] = cases[k].uy;
  }
  /* the direction presses down (-y): a node pushed down by 2 um is 2 um deep */
  cr_expect_float_eq(peri_tool_wear_depth(&s, tl, phi), 3.0e-6, 1e-18);
  /* a scratch shorter than the two margins has no node far from both ends */
  tl->at[0] = 0.011;
  cr_expect_eq(peri_tool_wear_depth(&s, tl, phi), 0.0);
  free(phi);
  peri_sim_free(&s);
}
