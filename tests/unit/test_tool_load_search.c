/* The quasi-static load search of a load-controlled tool (src/solver/tool_load_static.c,
 * docs/contact.md "Load control"): each "solve" here sets the tool's contact force from a
 * given law P_contact(q) of its offset, so the search is checked against laws whose answer
 * is known: a Hertz law, where the offset meeting the load is (P/k)^(2/3), and a law that
 * jumps across the load, where no offset meets it and the search must end at the jump. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>
#include "peri/quasistatic.h"
#include "peri/sim.h"
#include "peri/tools.h"

static const double spacing = 1.0e-3, hertz_k = 1.0e9; /* P = k q^1.5: 1 N at q = 1e-6 m */
static const double jump_at = 2.5e-4, jump_slope = 1.0e4, jump = 5.0;
static int solves;
static double (*law)(double q);

static double hertz(double q) { return q > 0.0 ? hertz_k * pow(q, 1.5) : 0.0; }
/* linear up to jump_at (2.5 N there), then 5 N more: a load of 5 N lies inside the jump */
static double jumping(double q) { return q > 0.0 ? jump_slope * q + (q >= jump_at ? jump : 0.0) : 0.0; }

static peri_qs_status law_solve(peri_sim *s) {
  ++solves;
  peri_tool *tl = &s->tools->tool[0];
  tl->normal_force = law(tl->q);
  return PERI_QS_CONVERGED;
}

/* The search for one tool under the load P along `given`, from the offset q0: the tool as
 * the search left it (its load freed), and the search's status. */
static peri_qs_status search(double (*given)(double), double P, double q0, peri_tool *tl) {
  peri_sim s;
  peri_tools tools;
  memset(&s, 0, sizeof s);
  memset(tl, 0, sizeof *tl);
  tl->name = "tip";
  tl->load = peri_expr_constant(P);
  tl->q = q0;
  tools.count = 1, tools.tool = tl;
  s.tools = &tools;
  s.disc.geom.spacing = spacing;
  law = given;
  solves = 0;
  const peri_qs_status st = peri_tools_load_equilibrium(&s, law_solve);
  peri_expr_free(tl->load);
  tl->load = NULL;
  return st;
}

Test(tool_load_search, hertz_law_meets_the_load) {
  peri_tool tl;
  for (double P = 0.5; P <= 8.0; P *= 2.0) {
    /* from a spacing before the first contact */
    cr_assert_eq(search(hertz, P, -spacing, &tl), PERI_QS_CONVERGED);
    cr_expect(fabs(tl.normal_force - P) <= 1e-3 * P, "P = %g: P_contact %g", P, tl.normal_force);
    cr_expect(fabs(tl.q - pow(P / hertz_k, 2.0 / 3.0)) <= 1e-3 * pow(P / hertz_k, 2.0 / 3.0), "P = %g: q %g", P, tl.q);
    /* ten free steps of a tenth of a spacing reach the body, then a few secant steps */
    cr_expect(solves <= 10 + 20, "P = %g: %d solves", P, solves);
  }
}

Test(tool_load_search, a_jump_across_the_load_ends_at_the_jump) {
  peri_tool tl;
  cr_assert_eq(search(jumping, 5.0, 0.0, &tl), PERI_QS_CONVERGED);
  /* the search stops within its bracket width (1e-6 spacings) of the jump, on either side */
  cr_expect(fabs(tl.q - jump_at) <= 1.0e-6 * spacing, "q %.12g against the jump at %g", tl.q, jump_at);
  cr_expect(tl.normal_force == jumping(tl.q), "the last point is a solved one");
  /* bisection from a bracket of about a tenth of a spacing: log2(1e-1 / 1e-6) = 17 halvings */
  cr_expect(solves <= 40, "%d solves", solves);
}

Test(tool_load_search, below_the_jump_the_secant_meets_the_load) {
  peri_tool tl;
  /* 2 N lies on the linear part: q = 2e-4 m, found by the secant in a few points */
  cr_assert_eq(search(jumping, 2.0, 0.0, &tl), PERI_QS_CONVERGED);
  cr_expect(fabs(tl.normal_force - 2.0) <= 2e-3, "P_contact %g", tl.normal_force);
  cr_expect(solves <= 20, "%d solves", solves);
}
