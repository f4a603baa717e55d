/* Quasi-static fracture to complete failure: the notched beam in three-point bending
 * (examples/notched_beam_3pb.yaml, docs/solvers.md section 4) on a coarse grid, dx = 2.5 mm,
 * m = 3 (440 nodes), with the example's pin and roller supports, loads, solver and dynamic
 * switch. Checked against theory:
 *  - the peak load is the LEFM one within 15%: P = K_Ic B W^1.5 / (S f(a/W)), K_Ic = sqrt(E G0)
 *    (plane stress), f the ASTM E399 geometry factor for S/W = 4 (the coarse horizon, 7.5 mm,
 *    is longer than the 5 mm notch, hence the wide band);
 *  - the beam fails completely: the final reaction is below 1% of the peak;
 *  - the crack crosses the ligament: in every row of nodes from the notch tip to the row under
 *    the loading nodes, a node next to the midline has lost at least 30% of its family (a node
 *    dx/2 from a straight crack through the body loses the 39% of its family on the far side,
 *    m = 3). The top row is the hinge about which the two halves turn: the loading nodes of
 *    the halves press on each other and their bonds, in compression, stay intact;
 *  - the unstable growth at the peak ran in a dynamic phase. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/damage.h"
#include "peri/damage_index.h"
#include "peri/energies.h"
#include "peri/quasistatic.h"
#include "peri/setup.h"

typedef struct curve {
  int load;                     /* region index of the loading nodes */
  double peak, last;            /* |reaction| of the load: largest, and at the last load step */
  long rows, dynamic_rows;
} curve;

static int record(peri_sim *s, void *ctx) {
  curve *c = ctx;
  double r[3];
  peri_region_reaction(s, c->load, r);
  if (s->solver.qs.phase == PERI_QS_PHASE_DYNAMIC) {
    c->dynamic_rows++;
    return 0;
  }
  c->peak = fmax(c->peak, fabs(r[1]));
  c->last = fabs(r[1]);
  c->rows++;
  return 0;
}

/* ASTM E399 geometry factor of the single-edge notched bend specimen, S/W = 4. */
static double astm_f(double a) {
  return 3.0 * sqrt(a) * (1.99 - a * (1.0 - a) * (2.15 - 3.93 * a + 2.7 * a * a)) /
         (2.0 * (1.0 + 2.0 * a) * pow(1.0 - a, 1.5));
}

Test(notched_beam, complete_failure) {
  const double dx = 2.5e-3;
  /* the example coarsened: the support and load regions hold one and two nodes as in the example */
  const char *sets[] = {"discretization.spacing=2.5e-3",
                        "regions.left_support.min=[-0.0495, -1]", "regions.left_support.max=[-0.048, 0.0014]",
                        "regions.right_support.min=[0.048, -1]", "regions.right_support.max=[0.0495, 0.0014]",
                        "regions.load.min=[-0.0013, 0.023]", "regions.load.max=[0.0013, 1]",
                        /* the hinge under the load opens later on the coarse grid (delta = 7.5 mm) */
                        "boundary_conditions.2.y=-3.0e-3*t", "solver.load_steps=60",
                        /* fewer bonds per crack length than at dx = 1 mm */
                        "solver.dynamic_switch.when_broken_exceeds=40"};
  peri_sim s;
  cr_assert_eq(peri_sim_from_deck_with(&s, "examples/notched_beam_3pb.yaml", sizeof sets / sizeof *sets, sets), 0);
  s.out.quiet = true;
  curve c = {.load = -1};
  int left = -1, right = -1;
  for (int r = 1; r < s.cond.n_regions; ++r) {
    if (!strcmp(s.cond.regions[r].name, "load")) c.load = r;
    if (!strcmp(s.cond.regions[r].name, "left_support")) left = r;
    if (!strcmp(s.cond.regions[r].name, "right_support")) right = r;
  }
  cr_assert(c.load > 0 && left > 0 && right > 0, "the example's regions are load, left_support, right_support");
  cr_assert_eq(s.cond.regions[left].count, 1, "pin: one node");
  cr_assert_eq(s.cond.regions[right].count, 1, "roller: one node");
  cr_assert_eq(s.cond.regions[c.load].count, 2, "load: the two top nodes next to the midline");
  peri_apply_initial_conditions(&s);
  cr_assert_eq(peri_solve_quasi_static(&s, record, &c), 0, "the run did not finish");

  /* LEFM peak: span between the support nodes, W = 25 mm, a = 5 mm, B = 5 mm, E = 3 GPa, G0 = 300 J/m^2 */
  const double span = s.disc.p.x[3 * s.cond.regions[right].nodes[0]] - s.disc.p.x[3 * s.cond.regions[left].nodes[0]];
  const double W = 0.025, a = 0.005, B = 5e-3, K = sqrt(3.0e9 * 300.0);
  const double lefm = K * B * pow(W, 1.5) / (span * astm_f(a / W));

  /* damage next to the midline, row by row above the notch */
  double *phi = malloc(sizeof(double) * (size_t)s.disc.p.n);
  peri_damage_index(&s, phi);
  const int rows = (int)lround(W / dx);
  double weakest = 1.0, weakest_y = 0.0;
  for (int row = 0; row < rows - 1; ++row) { /* up to the row under the loading nodes */
    const double y = (row + 0.5) * dx;
    if (y < a) continue; /* the notch */
    double most = 0.0;
    for (int32_t i = 0; i < s.disc.p.n; ++i)
      if (fabs(fabs(s.disc.p.x[3 * i]) - 0.5 * dx) < 1e-9 && fabs(s.disc.p.x[3 * i + 1] - y) < 1e-9) most = fmax(most, phi[i]);
    if (most < weakest) weakest = most, weakest_y = y;
  }
  free(phi);
  cr_log_info("notched beam (dx 2.5 mm): peak %.2f N (LEFM %.2f N, span %.1f mm), final %.4f N (%.3f%% of the "
              "peak), weakest midline damage %.3f at y = %.2f mm, %ld dynamic phases (%ld steps, %ld rows)",
              c.peak, lefm, span * 1e3, c.last, 100 * c.last / c.peak, weakest, weakest_y * 1e3,
              s.solver.qs.dynamic_phases, s.solver.qs.dynamic_steps, c.dynamic_rows);
  cr_expect(fabs(c.peak / lefm - 1.0) < 0.15, "peak %g N, LEFM %g N", c.peak, lefm);
  cr_expect(c.last < 0.01 * c.peak, "final reaction %g N is not below 1%% of the peak %g N", c.last, c.peak);
  cr_expect(weakest >= 0.3, "the crack does not cross the row y = %g mm: midline damage %g", weakest_y * 1e3,
            weakest);
  cr_expect(s.solver.qs.dynamic_phases >= 1 && c.dynamic_rows >= 1, "no dynamic phase (%ld)", s.solver.qs.dynamic_phases);
  peri_sim_free(&s);
}
