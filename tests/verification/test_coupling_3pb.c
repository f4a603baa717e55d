/* Quasi-static crack growth in the PD-FEM coupled model with adaptive FEM->PD switching: the
 * three-point bending test of Ongaro 2022 §2.7.1 (examples/coupling_three_point_bending.yaml,
 * docs/coupling.md) on a coarse grid, dx = 0.25 m, m = 3 (2,560 nodes), 21 load steps to 8.4 mm,
 * the load applied by a platen one horizon deep (the nodes within dx of the midline and delta of
 * the top face, 2 x 3 nodes) in every run, so that the all-PD beam's loaded nodes do not indent
 * where the coupled beam's elements do (docs/coupling.md "Loading the same way"): switching
 * scheme 1 (r = 1), scheme 2 (r = 2), and all PD (pd_region all: every row a bond row, the same
 * bonds, critical stretch and solver; gamma auto: the PD material with the elements' E) up to
 * the coupled peak. Checked:
 *  - the crack grows through the specimen: in every row of nodes from the notch tip to 3/4 of
 *    the height a node next to the midline has lost at least 30% of its family (a node dx/2 from
 *    a straight crack loses 39% of it at m = 3);
 *  - the switching rule holds at the end: every node within r delta of a node with a broken
 *    bond is a PD node (brute force over all pairs), the PD zone grew from the notch patch, and
 *    most nodes are still FEM nodes;
 *  - the reaction-displacement curve of both coupled runs agrees with the all-PD one within 5%
 *    (the target's bound) at every load step up to the coupled peak, crack initiation included;
 *  - the all-PD model is in balance (e_r at round-off) and the coupled ones are not (e_r > 1e-6:
 *    a beam in bending has a cubic displacement across the interface, eq. 2.70);
 *  - scheme 2 on a graded FEM mesh (coupling.graded_mesh: lattice cells in a band 8 m wide
 *    about the crack's path and 2.5 m squares at the supports, squares up to 8 dx elsewhere;
 *    docs/coupling.md "Graded meshes"): fewer nodes than the lattice (the left-out ones
 *    accounted for), the same crack and switching checks, and its curve within 5% of the
 *    all-PD one up to its peak. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/coupling.h"
#include "peri/damage_index.h"
#include "peri/energies.h"
#include "peri/quasistatic.h"
#include "peri/setup.h"

enum { MAX_STEPS = 64, STEPS = 21 };

typedef struct run {
  int load;
  int steps, stop_after; /* stop_after > 0: stop after that many load steps */
  double reaction[MAX_STEPS], e_r[MAX_STEPS];
  long broken[MAX_STEPS];
} run;

static int record(peri_sim *s, void *ctx) {
  run *r = ctx;
  double f[3], net[3], ratio[4];
  peri_region_reaction(s, r->load, f);
  peri_coupling_balance(s, net, ratio);
  if (r->steps < MAX_STEPS) {
    r->reaction[r->steps] = -f[1]; /* the load pushes down */
    r->e_r[r->steps] = ratio[1];
    r->broken[r->steps] = s->solver.qs.broken_in_run;
    r->steps++;
  }
  return r->stop_after > 0 && r->steps >= r->stop_after;
}

/* The example coarsened: the supports and the load keep one and two nodes. */
static const char *const coarse[] = {"discretization.spacing=0.25",
                                     "regions.left_support.max=[0.25, 0.25]",
                                     "regions.right_support.min=[19.75, 0]",
                                     "regions.right_support.max=[20, 0.25]",
                                     "regions.load.min=[9.74, 7.75]",
                                     "regions.load.max=[10.26, 8.1]",
                                     "solver.load_steps=21",
                                     "boundary_conditions.2.y=-8.4e-3*t"};
enum { N_COARSE = sizeof coarse / sizeof *coarse };

/* The load on a platen one horizon (3 dx) deep: the two columns of nodes next to the midline. */
static const char platen[] = "regions.load.min=[9.74, 7.24]";

static void load_3pb(peri_sim *s, const char *extra, const char *more) {
  const char *sets[N_COARSE + 3];
  int n = 0;
  for (int k = 0; k < N_COARSE; ++k) sets[n++] = coarse[k];
  sets[n++] = platen, sets[n++] = extra;
  if (more) sets[n++] = more;
  cr_assert_eq(peri_sim_from_deck_with(s, "examples/coupling_three_point_bending.yaml", n, sets), 0);
  s->out.quiet = true;
}

static void run_3pb(peri_sim *s, run *r, const char *extra, const char *more, int stop_after) {
  load_3pb(s, extra, more);
  memset(r, 0, sizeof *r);
  r->load = -1;
  r->stop_after = stop_after;
  for (int k = 1; k < s->cond.n_regions; ++k)
    if (!strcmp(s->cond.regions[k].name, "load")) r->load = k;
  cr_assert(r->load > 0 && s->cond.regions[r->load].count == 6, "load: the platen of 2 x 3 nodes at mid-span");
  peri_apply_initial_conditions(s);
  cr_assert_eq(peri_solve_quasi_static(s, record, r), 0, "the run (%s) did not finish", extra);
  cr_assert_eq(r->steps, stop_after > 0 ? stop_after : STEPS);
}

/* The crack crosses the rows from the notch tip (y = 1) to 3/4 of the height (y = 6). */
static void check_crack(const peri_sim *s, const char *what) {
  const peri_particles *p = &s->disc.p;
  double *phi = malloc(sizeof(double) * (size_t)p->n);
  peri_damage_index(s, phi);
  const double dx = s->disc.geom.spacing;
  for (double y = 1.0 + 0.5 * dx; y < 6.0; y += dx) {
    double most = 0.0;
    for (int32_t i = 0; i < p->n; ++i)
      if (fabs(p->x[3 * i + 1] - y) < 0.25 * dx && fabs(p->x[3 * i] - 10.0) < dx) most = fmax(most, phi[i]);
    cr_expect_geq(most, 0.3, "%s: the crack does not reach y = %g (damage %g next to the midline)", what, y, most);
  }
  free(phi);
}

/* Every node within r delta of a node that lost a bond after the start (the pre-crack's bonds,
 * `cut`, are the notch patch's: its cut nodes and the nodes within r delta of its tip) is a PD
 * node. */
static void check_switching(const peri_sim *s, double r, int32_t pd_at_start, const uint8_t *cut) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int32_t *type = s->coupling->node_type;
  const double reach = r * s->disc.geom.horizon * (1.0 + 1e-9);
  int32_t pd = 0;
  for (int32_t i = 0; i < p->n; ++i) {
    pd += type[i];
    bool lost = false;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) lost |= b->broken[k] && !cut[k];
    if (!lost) continue;
    cr_assert_eq(type[i], 1, "node %d has a broken bond and is not a PD node", (int)i);
    for (int32_t j = 0; j < p->n; ++j) {
      const double dxj = p->x[3 * j] - p->x[3 * i], dyj = p->x[3 * j + 1] - p->x[3 * i + 1];
      if (dxj * dxj + dyj * dyj <= reach * reach)
        cr_assert_eq(type[j], 1, "node %d lies within %g delta of node %d, which lost a bond, and is FEM", (int)j, r,
                     (int)i);
    }
  }
  cr_assert_eq(pd, s->coupling->n_pd);
  cr_expect_gt(pd, pd_at_start + 100, "the PD zone did not follow the crack: %d PD nodes, %d at the start", pd,
               pd_at_start);
  const int32_t lattice = p->n + s->coupling->removed_nodes; /* the specimen's lattice nodes, graded mesh or not */
  cr_expect_lt(pd, lattice / 3, "%d of %d lattice nodes are PD nodes: the switching spread too far", pd, lattice);
}

/* The notch patch: the nodes the pre-crack cut and the nodes within r delta of its tip
 * (10, 1), exactly (brute force); its other end lies below the beam. */
static void check_patch(const peri_sim *s, double r) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double reach = r * s->disc.geom.horizon;
  for (int32_t i = 0; i < p->n; ++i) {
    bool cut = false;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) cut |= b->broken[k] != 0;
    const double to_tip = hypot(p->x[3 * i] - 10.0, p->x[3 * i + 1] - 1.0);
    const bool pd = cut || to_tip <= reach * (1.0 + 1e-9);
    cr_assert_eq(s->coupling->node_type[i], pd, "r %g: node %d at (%g, %g) is %s (cut: %d, %g from the tip)", r, (int)i,
                 p->x[3 * i], p->x[3 * i + 1], pd ? "FEM" : "PD", cut, to_tip);
  }
}

/* The last load step before the reaction falls below 90% of the largest so far. */
static int peak_step(const run *r) {
  int peak = 0;
  for (int n = 1; n < r->steps && r->reaction[n] >= 0.9 * r->reaction[peak]; ++n)
    if (r->reaction[n] > r->reaction[peak]) peak = n;
  return peak;
}

/* The graded mesh: the lattice's cells about the crack's path and at the point supports (a
 * coarse mesh under a point support is too stiff: the support's local compliance grows with
 * the mesh's size there), squares of 2, 4 and 8 dx elsewhere. */
static const char graded[] = "coupling.graded_mesh={levels: 3, fine: [{shape: rectangle, min: [6, -1], max: [14, 9]}, "
                             "{shape: rectangle, min: [-1, -1], max: [1.5, 1.5]}, "
                             "{shape: rectangle, min: [18.5, -1], max: [21, 1.5]}]}";

Test(coupling_3pb, switching_crack_and_all_pd_curve) {
  static peri_sim s1, s2, sg, sp;
  static run r1, r2, rg, rp;
  run_3pb(&s1, &r1, "coupling.switch_radius=1", NULL, 0);
  run_3pb(&s2, &r2, "coupling.switch_radius=2", NULL, 0);
  run_3pb(&sg, &rg, graded, NULL, 0);
  check_crack(&s1, "scheme 1");
  check_crack(&s2, "scheme 2");
  check_crack(&sg, "scheme 2, graded mesh");
  cr_assert(sg.coupling->removed_nodes > 0 && sg.disc.p.n + sg.coupling->removed_nodes == s2.disc.p.n,
            "graded mesh: %d nodes and %d left out of the lattice's %d", sg.disc.p.n, sg.coupling->removed_nodes,
            s2.disc.p.n);

  /* the notch patches: nodes cut by the pre-crack and those within r delta of them */
  peri_sim fresh;
  uint8_t *cut1, *cut2, *cutg;
  load_3pb(&fresh, "coupling.switch_radius=1", NULL);
  const int32_t patch1 = fresh.coupling->n_pd;
  check_patch(&fresh, 1.0);
  cut1 = malloc((size_t)fresh.disc.bonds.n_bonds), memcpy(cut1, fresh.disc.bonds.broken, (size_t)fresh.disc.bonds.n_bonds);
  peri_sim_free(&fresh);
  load_3pb(&fresh, "coupling.switch_radius=2", NULL);
  const int32_t patch2 = fresh.coupling->n_pd;
  check_patch(&fresh, 2.0);
  cut2 = malloc((size_t)fresh.disc.bonds.n_bonds), memcpy(cut2, fresh.disc.bonds.broken, (size_t)fresh.disc.bonds.n_bonds);
  peri_sim_free(&fresh);
  load_3pb(&fresh, graded, NULL);
  const int32_t patchg = fresh.coupling->n_pd;
  cutg = malloc((size_t)fresh.disc.bonds.n_bonds), memcpy(cutg, fresh.disc.bonds.broken, (size_t)fresh.disc.bonds.n_bonds);
  peri_sim_free(&fresh);
  cr_assert(patch1 > 0 && patch2 > patch1 && patchg == patch2, "notch patches of %d, %d and %d nodes", patch1, patch2,
            patchg);
  check_switching(&s1, 1.0, patch1, cut1);
  check_switching(&s2, 2.0, patch2, cut2);
  check_switching(&sg, 2.0, patchg, cutg);
  free(cut1), free(cut2), free(cutg);

  /* the curves up to the coupled peak: the all-PD run (the expensive one) stops there */
  const int peak1 = peak_step(&r1), peak2 = peak_step(&r2), peakg = peak_step(&rg);
  const int last = peak1 > peak2 ? (peak1 > peakg ? peak1 : peakg) : (peak2 > peakg ? peak2 : peakg);
  cr_assert(peak1 > 2 && last < STEPS - 1, "coupled peaks at steps %d and %d of %d: not inside the run", peak1 + 1,
            peak2 + 1, STEPS);
  cr_assert_gt(r1.broken[peak1], r1.broken[0], "no bond broke up to the scheme-1 peak: the crack did not start");
  run_3pb(&sp, &rp, "coupling.pd_region=all", "coupling.gamma=auto", last + 1);
  for (int n = 0; n <= last; ++n) {
    if (n <= peak2)
      cr_expect_leq(fabs(r2.reaction[n] - rp.reaction[n]), 0.05 * rp.reaction[n],
                    "step %d: scheme 2 reaction %g against all-PD %g", n + 1, r2.reaction[n], rp.reaction[n]);
    if (n <= peak1)
      cr_expect_leq(fabs(r1.reaction[n] - rp.reaction[n]), 0.05 * rp.reaction[n],
                    "step %d: scheme 1 reaction %g against all-PD %g", n + 1, r1.reaction[n], rp.reaction[n]);
    if (n <= peakg)
      cr_expect_leq(fabs(rg.reaction[n] - rp.reaction[n]), 0.05 * rp.reaction[n],
                    "step %d: scheme 2 on the graded mesh: reaction %g against all-PD %g", n + 1, rg.reaction[n],
                    rp.reaction[n]);
  }
  /* balance: all PD at round-off; the coupled interfaces in the beam's cubic field are not */
  for (int n = 0; n <= last; ++n) {
    cr_expect_lt(rp.e_r[n], 1e-10, "step %d: all-PD e_r %g", n + 1, rp.e_r[n]);
    if (n <= peak1) cr_expect_gt(r1.e_r[n], 1e-6, "step %d: scheme-1 e_r %g", n + 1, r1.e_r[n]);
    if (n <= peak2) cr_expect_gt(r2.e_r[n], 1e-6, "step %d: scheme-2 e_r %g", n + 1, r2.e_r[n]);
  }
  peri_sim_free(&s1);
  peri_sim_free(&s2);
  peri_sim_free(&sg);
  peri_sim_free(&sp);
}

/* One elastic load step of 1 mm (the crack starts near 7 mm) with the given coupling settings. */
static void elastic_3pb(peri_sim *s, const char *a, const char *b, double *reaction, double *e_r) {
  const char *sets[N_COARSE + 4];
  for (int k = 0; k < N_COARSE; ++k) sets[k] = coarse[k];
  sets[N_COARSE] = "solver.load_steps=1", sets[N_COARSE + 1] = "boundary_conditions.2.y=-1e-3*t";
  sets[N_COARSE + 2] = a, sets[N_COARSE + 3] = b;
  cr_assert_eq(peri_sim_from_deck_with(s, "examples/coupling_three_point_bending.yaml", N_COARSE + 4, sets), 0);
  s->out.quiet = true;
  run r;
  memset(&r, 0, sizeof r);
  for (int k = 1; k < s->cond.n_regions; ++k)
    if (!strcmp(s->cond.regions[k].name, "load")) r.load = k;
  peri_apply_initial_conditions(s);
  cr_assert_eq(peri_solve_quasi_static(s, record, &r), 0);
  cr_assert_eq(r.broken[0], 0, "a bond broke at 1 mm");
  *reaction = r.reaction[0];
  if (e_r) *e_r = r.e_r[0];
}

/* The largest difference of the displacements of two runs over the largest displacement. */
static double u_difference(const peri_sim *a, const peri_sim *b) {
  double most = 0.0, largest = 0.0;
  for (size_t c = 0; c < 3 * (size_t)a->disc.p.n; ++c) {
    most = fmax(most, fabs(a->disc.p.u[c] - b->disc.p.u[c]));
    largest = fmax(largest, fabs(a->disc.p.u[c]));
  }
  return most / largest;
}

/* A uniform gamma scales every PD row; where no PD node is loaded or held (the supports and the
 * load are FEM nodes here) each PD row is a homogeneous equation, so the coupled displacements
 * and reactions do not change (docs/coupling.md, "gamma for the discrete family"), while in the
 * all-PD beam the displacements stay and the reactions scale by gamma exactly. gamma auto is
 * Remark A.2's for the linear ramp at m = 3, below 1 (the discrete side is stiffer). */
Test(coupling_3pb, gamma_drops_out_of_the_coupled_solution) {
  peri_sim a, b;
  double ra, rb;
  elastic_3pb(&a, "coupling.switch_radius=1", "coupling.gamma=1", &ra, NULL);
  elastic_3pb(&b, "coupling.switch_radius=1", "coupling.gamma=auto", &rb, NULL);
  const double gamma = b.coupling->gamma;
  cr_assert(gamma < 0.99 && gamma > 0.9, "gamma auto %g", gamma);
  cr_expect_lt(u_difference(&a, &b), 1e-9, "coupled: gamma moved the displacements by %g", u_difference(&a, &b));
  cr_expect_lt(fabs(rb - ra), 1e-9 * ra, "coupled: load reaction %.12g with gamma 1, %.12g with gamma %g", ra, rb, gamma);
  peri_sim_free(&a);
  peri_sim_free(&b);
  elastic_3pb(&a, "coupling.pd_region=all", "coupling.gamma=1", &ra, NULL);
  elastic_3pb(&b, "coupling.pd_region=all", "coupling.gamma=auto", &rb, NULL);
  cr_expect_lt(u_difference(&a, &b), 1e-9, "all PD: gamma moved the displacements by %g", u_difference(&a, &b));
  cr_expect_lt(fabs(rb - gamma * ra), 1e-9 * ra, "all PD: load reaction %.12g, gamma times %.12g", rb, ra);
  peri_sim_free(&a);
  peri_sim_free(&b);
}

/* Scheme 2 out of balance less than scheme 1 (Ongaro 2022 §2.7.1, Fig. 2.25: its interface lies
 * further from the crack tip, where the field is closer to linear): e_r of eq. 2.114 (the
 * vertical reactions; after a solve the sum over all nodes) on the elastic beam with a crack
 * up the midline to height a and its notch patch (the cut nodes and the nodes within r delta of
 * the tip) as the PD zone, for a = 3, 4 and 5 m. (For a crack of 1 m, shorter than 2 delta
 * here, scheme 2's patch reaches the stressed bottom face and the order is reversed:
 * docs/coupling.md.) */
Test(coupling_3pb, scheme_2_out_of_balance_below_scheme_1) {
  for (int a = 3; a <= 5; ++a) {
    char tip[64];
    snprintf(tip, sizeof tip, "precracks.0.to=[10, %d]", a);
    peri_sim s;
    double reaction, e1, e2;
    elastic_3pb(&s, "coupling.switch_radius=1", tip, &reaction, &e1);
    peri_sim_free(&s);
    elastic_3pb(&s, "coupling.switch_radius=2", tip, &reaction, &e2);
    peri_sim_free(&s);
    cr_expect_lt(e2, e1, "crack to %d m: e_r %.3e with scheme 2, %.3e with scheme 1", a, e2, e1);
  }
}
