/* The optimized bond loops (compact bonds, vectorized, specialized per option) against a
 * straightforward implementation of the model equations written here from
 * docs/model_reference.md (PMB section 2, LPS section 3.3), on a damaged two-material body
 * with a random displacement field: forces agree to 1e-12 of the largest force, and
 * breaking by the optimized loops breaks exactly the bonds whose stretch exceeds their
 * critical stretch, from both ends. The loops' two paths (eight nodes at a time on node
 * blocks, one node at a time otherwise) give bit-identical forces and strain energies, also
 * after bonds break inside the loops and outside them, and after the block path drops the
 * template entries that lost every bond and the bonds come back. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "model/node_blocks.h"
#include "peri/plastic_fields.h"
#include "peri/damage.h"
#include "peri/setup.h"
#include "support.h"

#define N_SIDE 20
#define DX 1.0e-3

/* Deterministic pseudo-random numbers in [-1, 1). */
static double uniform(uint64_t *state) {
  *state = *state * 6364136223846793005ull + 1442695040888963407ull;
  return (double)(*state >> 11) / 4503599627370496.0 - 1.0;
}

static void build(peri_sim *s, int dim, const char *model, const char *influence, const char *pv) {
  char deck[2048], box[256], inclusion[256];
  const double h = 0.5 * N_SIDE * DX;
  if (dim == 2) {
    snprintf(box, sizeof box, "{shape: rectangle, min: [%g, %g], max: [%g, %g], material: a}", -h, -h, h, h);
    snprintf(inclusion, sizeof inclusion, "{shape: circle, center: [0.002, 0.001], radius: 0.004, material: b}");
  } else {
    snprintf(box, sizeof box, "{shape: box, min: [%g, %g, %g], max: [%g, %g, %g], material: a}", -h, -h, -0.3 * h,
             h, h, 0.3 * h);
    snprintf(inclusion, sizeof inclusion, "{shape: sphere, center: [0.002, 0.001, 0], radius: 0.004, material: b}");
  }
  const char *moduli_a = strcmp(model, "pmb") == 0 ? "youngs_modulus: 70.0e9" : "youngs_modulus: 70.0e9, poisson_ratio: 0.22";
  const char *moduli_b = strcmp(model, "pmb") == 0 ? "youngs_modulus: 200.0e9" : "youngs_modulus: 200.0e9, poisson_ratio: 0.3";
  snprintf(deck, sizeof deck,
           "dimension: %d\n%s"
           "materials:\n"
           "  a: {model: %s, density: 2500, %s, critical_stretch: 0.004}\n"
           "  b: {model: %s, density: 7800, %s, critical_stretch: 0.006}\n"
           "discretization:\n"
           "  spacing: %g\n"
           "  m: 3\n"
           "  influence: %s\n"
           "  partial_volume: %s\n"
           "%s"
           "  fill: [%s, %s]\n"
           "solver: {type: explicit, steps: 1}\n"
           "output: {picture: false}\n",
           dim, dim == 2 ? "plane: strain\n" : "", model, moduli_a, model, moduli_b, DX, influence, pv,
           dim == 2 ? "  thickness: 1.0e-3\n" : "", box, inclusion);
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
}

/* A random displacement field of about 0.3% strain, and every third bond pair broken
 * (both directions), chosen by a hash of the pair. */
static void damage_and_deform(peri_sim *s) {
  uint64_t state = 12345;
  for (int32_t i = 0; i < s->disc.p.n; ++i)
    for (int d = 0; d < s->disc.p.dim; ++d) s->disc.p.u[3 * i + d] = 0.003 * DX * uniform(&state);
  const peri_bonds *b = &s->disc.bonds;
  for (int32_t i = 0; i < b->n_nodes; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      const uint64_t lo = (uint64_t)(i < j ? i : j), hi = (uint64_t)(i < j ? j : i);
      b->broken[k] = ((lo * 2654435761u + hi * 40503u) % 3u) == 0;
    }
}

static double bond_vectors(const peri_sim *s, int32_t i, int32_t j, double *r0, double y[3]) {
  double xi[3];
  *r0 = peri_bond_xi(s->disc.p.x, i, j, xi);
  for (int d = 0; d < 3; ++d) y[d] = xi[d] + s->disc.p.u[3 * j + d] - s->disc.p.u[3 * i + d];
  return sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
}

/* PMB: f_i = sum_j c_ij omega beta V_j s y/|y|, c_ij = (c_i + c_j)/2, over intact bonds. */
static void reference_pmb(const peri_sim *s, double *f) {
  const peri_bonds *b = &s->disc.bonds;
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i) {
    double fi[3] = {0, 0, 0};
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double r0, y[3];
      const double r = bond_vectors(s, i, j, &r0, y);
      const double c = 0.5 * (s->mat.materials[s->disc.p.material[i]].micromodulus + s->mat.materials[s->disc.p.material[j]].micromodulus);
      const double pair = c * peri_bonds_omega(b, r0) * (r - r0) / r0;
      for (int d = 0; d < 3; ++d) fi[d] += pair * peri_bonds_beta(b, r0) * s->disc.p.volume[j] * y[d] / r;
    }
    for (int d = 0; d < 3; ++d) f[3 * i + d] = fi[d];
  }
}

/* LPS (docs/model_reference.md 3.3): theta_i = (n/m_i) sum w e |xi| W, e^d = e - theta_i |xi|/3,
 * P_i = sum w e^d |xi| W, t_ij = n (K theta_i - alpha_i P_i/3) w |xi|/m_i + alpha_i w e^d,
 * f_i = sum (t_ij + t_ji) M W, W = beta V_j, alpha_i = (alpha m)/m_i, m_i = sum w |xi|^2 W over
 * the whole reference family. */
static void reference_lps(const peri_sim *s, double *f) {
  const peri_bonds *b = &s->disc.bonds;
  const int32_t n = s->disc.p.n_owned;
  double *m = calloc((size_t)n, sizeof(double)), *theta = calloc((size_t)n, sizeof(double)),
         *P = calloc((size_t)n, sizeof(double));
  for (int32_t i = 0; i < n; ++i) {
    double we = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      double r0, y[3];
      const double r = bond_vectors(s, i, j, &r0, y);
      const double w = peri_bonds_omega(b, r0) * peri_bonds_beta(b, r0) * s->disc.p.volume[j];
      m[i] += w * r0 * r0;
      if (!b->broken[k]) we += w * (r - r0) * r0;
    }
    theta[i] = s->mat.materials[s->disc.p.material[i]].n_theta * we / m[i];
  }
  for (int32_t i = 0; i < n; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double r0, y[3];
      const double r = bond_vectors(s, i, j, &r0, y);
      const double w = peri_bonds_omega(b, r0) * peri_bonds_beta(b, r0) * s->disc.p.volume[j];
      P[i] += w * (r - r0 - theta[i] * r0 / 3.0) * r0;
    }
  for (int32_t i = 0; i < n; ++i) {
    double fi[3] = {0, 0, 0};
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double r0, y[3];
      const double r = bond_vectors(s, i, j, &r0, y), e = r - r0, omega = peri_bonds_omega(b, r0);
      double t = 0.0;
      const int32_t ends[2] = {i, j};
      for (int a = 0; a < 2; ++a) {
        const int32_t q = ends[a];
        const peri_material *mat = &s->mat.materials[s->disc.p.material[q]];
        const double alpha = mat->alpha_m / m[q];
        t += mat->n_theta * (mat->K_theta * theta[q] - alpha * P[q] / 3.0) * omega * r0 / m[q] +
             alpha * omega * (e - theta[q] * r0 / 3.0);
      }
      for (int d = 0; d < 3; ++d) fi[d] += t * peri_bonds_beta(b, r0) * s->disc.p.volume[j] * y[d] / r;
    }
    for (int d = 0; d < 3; ++d) f[3 * i + d] = fi[d];
  }
  free(m);
  free(theta);
  free(P);
}

static void check_forces(int dim, const char *model, const char *influence, const char *pv) {
  peri_sim s;
  build(&s, dim, model, influence, pv);
  damage_and_deform(&s);
  s.solver.breaking = false;
  s.mat.model->force(&s);
  const size_t n3 = 3 * (size_t)s.disc.p.n_owned;
  double *ref = calloc(n3, sizeof(double));
  if (strcmp(model, "pmb") == 0)
    reference_pmb(&s, ref);
  else
    reference_lps(&s, ref);
  double scale = 0.0, worst = 0.0;
  for (size_t a = 0; a < n3; ++a) scale = fmax(scale, fabs(ref[a]));
  for (size_t a = 0; a < n3; ++a) worst = fmax(worst, fabs(s.disc.p.f[a] - ref[a]));
  cr_log_info("%s %dD %s %s: max |f - f_ref| = %.3g of max |f| %.3g", model, dim, influence, pv, worst / scale, scale);
  cr_assert_gt(scale, 0.0);
  cr_expect_leq(worst, 1e-12 * scale, "%s %dD %s %s: forces differ by %.3g of the largest", model, dim, influence,
                pv, worst / scale);
  free(ref);
  peri_sim_free(&s);
}

Test(kernel_reference, pmb_2d) { check_forces(2, "pmb", "constant", "linear"); }
Test(kernel_reference, pmb_3d_inverse) { check_forces(3, "pmb", "inverse", "lammps"); }
Test(kernel_reference, pmb_2d_gaussian) { check_forces(2, "pmb", "gaussian", "none"); }
Test(kernel_reference, lps_2d) { check_forces(2, "lps", "constant", "linear"); }
Test(kernel_reference, lps_3d_inverse) { check_forces(3, "lps", "inverse", "linear"); }
Test(kernel_reference, lps_3d_gaussian) { check_forces(3, "lps", "gaussian", "lammps"); }

/* Breaking: after one force evaluation exactly the intact bonds with (r - |xi|)/|xi| above the
 * pair's critical stretch are broken, in both directions. */
static void check_breaking(const char *model) {
  peri_sim s;
  build(&s, 2, model, "constant", "linear");
  damage_and_deform(&s);
  for (size_t a = 0; a < 3 * (size_t)s.disc.p.n; ++a) s.disc.p.u[a] *= 1.6; /* strains around the critical stretch */
  const peri_bonds *b = &s.disc.bonds;
  uint8_t *expect = malloc((size_t)b->n_bonds);
  long n_expect = 0;
  for (int32_t i = 0; i < b->n_nodes; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      double r0, y[3];
      const double stretch = (bond_vectors(&s, i, j, &r0, y) - r0) / r0;
      const double s0 = fmin(s.mat.materials[s.disc.p.material[i]].critical_stretch, s.mat.materials[s.disc.p.material[j]].critical_stretch);
      expect[k] = b->broken[k] || stretch > s0;
      n_expect += expect[k] && !b->broken[k];
    }
  s.solver.breaking = true;
  const long n_broken = s.mat.model->force(&s);
  long wrong = 0;
  for (int64_t k = 0; k < b->n_bonds; ++k) wrong += expect[k] != b->broken[k];
  cr_log_info("%s: %ld bonds broken by one evaluation, expected %ld", model, n_broken, n_expect);
  cr_assert_gt(n_expect, 100, "the test must break bonds");
  cr_expect_eq(wrong, 0, "%s: %ld bonds differ from the exact breaking rule", model, wrong);
  cr_expect_eq(n_broken, n_expect);
  free(expect);
  peri_sim_free(&s);
}

Test(kernel_reference, pmb_breaking) { check_breaking("pmb"); }
Test(kernel_reference, lps_breaking) { check_breaking("lps"); }

/* Forces by the block path and by the one-node path (s->disc.generic_bond_loops) into a and b. */
static double forces_both_paths(peri_sim *s, double *a, double *b) {
  const size_t bytes = sizeof(double) * 3 * (size_t)s->disc.p.n_owned;
  s->disc.generic_bond_loops = false;
  s->mat.model->force(s);
  memcpy(a, s->disc.p.f, bytes);
  const double in_blocks = (double)s->disc.node_blocks->block_bonds / (double)s->disc.bonds.offset[s->disc.p.n_owned];
  s->disc.generic_bond_loops = true;
  s->mat.model->force(s);
  memcpy(b, s->disc.p.f, bytes);
  s->disc.generic_bond_loops = false;
  return in_blocks;
}

/* Strain energy densities by both paths: whether they agree bit for bit. */
static bool energies_agree(peri_sim *s) {
  const size_t n = (size_t)s->disc.p.n_owned;
  double *a = calloc(n, sizeof(double)), *b = calloc(n, sizeof(double));
  s->disc.generic_bond_loops = false;
  s->mat.model->energy(s, a);
  s->disc.generic_bond_loops = true;
  s->mat.model->energy(s, b);
  s->disc.generic_bond_loops = false;
  double largest = 0.0;
  for (size_t i = 0; i < n; ++i) largest = fmax(largest, fabs(a[i]));
  const bool same = largest > 0.0 && memcmp(a, b, sizeof(double) * n) == 0;
  free(a);
  free(b);
  return same;
}

static void check_paths(int dim, const char *model, const char *influence, const char *pv) {
  peri_sim s;
  build(&s, dim, model, influence, pv);
  damage_and_deform(&s);
  const size_t n3 = 3 * (size_t)s.disc.p.n_owned, bytes = sizeof(double) * n3;
  double *a = malloc(bytes), *b = malloc(bytes);
  /* 1. damaged before the first evaluation */
  s.solver.breaking = false;
  const double in_blocks = forces_both_paths(&s, a, b);
  cr_log_info("%s %dD %s %s: %.3f of the bonds in node blocks", model, dim, influence, pv, in_blocks);
  cr_assert_gt(in_blocks, 0.5, "the test needs node blocks");
  cr_expect(memcmp(a, b, bytes) == 0, "%s %dD %s: the block and one-node paths differ", model, dim, influence);
  cr_expect(energies_agree(&s), "%s %dD %s: the energies of the two paths differ", model, dim, influence);
  /* 2. bonds broken by the force loop: the evaluation that breaks them gives the same forces
   * and breaks the same bonds on both paths (the block path recomputes a block whose nodes
   * lost bonds as a block, the other path node by node) */
  for (size_t k = 0; k < 3 * (size_t)s.disc.p.n; ++k) s.disc.p.u[k] *= 1.6;
  peri_bonds *bonds = &s.disc.bonds;
  uint8_t *broken_before = malloc((size_t)bonds->n_bonds), *broken_generic_flags = malloc((size_t)bonds->n_bonds);
  memcpy(broken_before, bonds->broken, (size_t)bonds->n_bonds);
  s.solver.breaking = true;
  s.disc.generic_bond_loops = true;
  const long broken_generic = s.mat.model->force(&s);
  memcpy(b, s.disc.p.f, bytes);
  memcpy(broken_generic_flags, bonds->broken, (size_t)bonds->n_bonds);
  memcpy(bonds->broken, broken_before, (size_t)bonds->n_bonds);
  ++bonds->broken_edits;
  s.disc.generic_bond_loops = false;
  const long broken = s.mat.model->force(&s);
  memcpy(a, s.disc.p.f, bytes);
  s.solver.breaking = false;
  cr_assert_gt(broken, 100, "the test must break bonds");
  cr_expect_eq(broken, broken_generic);
  cr_expect(memcmp(bonds->broken, broken_generic_flags, (size_t)bonds->n_bonds) == 0,
            "%s %dD %s: the paths break different bonds", model, dim, influence);
  cr_expect(memcmp(a, b, bytes) == 0, "%s %dD %s: the paths differ in the evaluation that broke %ld bonds", model,
            dim, influence, broken);
  free(broken_before);
  free(broken_generic_flags);
  forces_both_paths(&s, a, b);
  cr_expect(memcmp(a, b, bytes) == 0, "%s %dD %s: the paths differ after the loop broke %ld bonds", model, dim,
            influence, broken);
  /* 3. bonds broken outside the loops (as by a thermal crack or a restart) */
  for (int64_t k = 0; k < bonds->n_bonds; k += 5) bonds->broken[k] = 1;
  ++bonds->broken_edits;
  forces_both_paths(&s, a, b);
  cr_expect(memcmp(a, b, bytes) == 0, "%s %dD %s: the paths differ after bonds broke outside the loops", model, dim,
            influence);
  cr_expect(energies_agree(&s), "%s %dD %s: the energies differ after bonds broke", model, dim, influence);
  /* 4. whole template entries without a bond (every bond of the nodes left of x = 0 broken):
   * the block path drops them and keeps its forces; bonds restored afterwards (a cut-back, a
   * checkpoint) bring them back */
  uint8_t *restore = malloc((size_t)bonds->n_bonds);
  memcpy(restore, bonds->broken, (size_t)bonds->n_bonds);
  for (int32_t i = 0; i < bonds->n_nodes; ++i)
    for (int64_t k = bonds->offset[i]; k < bonds->offset[i + 1]; ++k)
      if (s.disc.p.x[3 * (size_t)i] < 0.0 || s.disc.p.x[3 * (size_t)bonds->neighbor[k]] < 0.0) bonds->broken[k] = 1;
  ++bonds->broken_edits;
  s.disc.generic_bond_loops = true;
  s.mat.model->force(&s);
  memcpy(b, s.disc.p.f, bytes);
  s.disc.generic_bond_loops = false;
  s.mat.model->force(&s);
  memcpy(a, s.disc.p.f, bytes);
  const peri_node_blocks *nb = s.disc.node_blocks;
  int64_t live = 0;
  for (int32_t item = 0; item < nb->n_items; ++item) live += peri_item_entries(nb, item);
  cr_log_info("%s %dD %s: %lld of %lld template entries kept", model, dim, influence, (long long)live,
              (long long)nb->tpl_entries);
  cr_expect(live < nb->tpl_entries * 3 / 4, "%s %dD %s: the entries without bonds were not dropped", model, dim,
            influence);
  cr_expect(memcmp(a, b, bytes) == 0, "%s %dD %s: the paths differ after entries were dropped", model, dim,
            influence);
  memcpy(bonds->broken, restore, (size_t)bonds->n_bonds);
  ++bonds->broken_edits;
  s.mat.model->force(&s);
  memcpy(a, s.disc.p.f, bytes);
  s.disc.generic_bond_loops = true;
  s.mat.model->force(&s);
  memcpy(b, s.disc.p.f, bytes);
  s.disc.generic_bond_loops = false;
  cr_expect(memcmp(a, b, bytes) == 0, "%s %dD %s: the paths differ after the bonds came back", model, dim, influence);
  free(restore);
  free(a);
  free(b);
  peri_sim_free(&s);
}

Test(kernel_paths, pmb_2d) { check_paths(2, "pmb", "constant", "linear"); }
Test(kernel_paths, pmb_3d_inverse) { check_paths(3, "pmb", "inverse", "lammps"); }
Test(kernel_paths, pmb_3d_gaussian) { check_paths(3, "pmb", "gaussian", "none"); }
Test(kernel_paths, lps_2d) { check_paths(2, "lps", "constant", "linear"); }
Test(kernel_paths, lps_3d_inverse) { check_paths(3, "lps", "inverse", "linear"); }
Test(kernel_paths, lps_3d_gaussian) { check_paths(3, "lps", "gaussian", "lammps"); }

/* The deviatoric yield rule (docs/plasticity.md section 8): a 3D LPS block sheared past its
 * first yield, with broken bonds. Its force runs a block of nodes that all have a plastic state
 * on the block's template and the other nodes one by one: both paths agree bit for bit (the
 * return maps in place and is idempotent at a fixed displacement, so the second evaluation
 * sees the state of the first). */
/* The sheared 3D LPS block of the deviatoric cases below: the deviatoric rule with the
 * hardening curve `curve`, the influence `influence`, broken bonds and a random field. */
static void rule_block(peri_sim *s, const char *curve, const char *influence, const char *rule) {
  const double h = 0.5 * N_SIDE * DX;
  char deck[1024];
  snprintf(deck, sizeof deck,
           "dimension: 3\n"
           "materials:\n"
           "  steel: {model: lps, density: 7800, youngs_modulus: 200e9, poisson_ratio: 0.25,\n"
           "          plasticity: {%s, yield_rule: %s}}\n"
           "discretization: {spacing: %g, m: 3, influence: %s,\n"
           "                 fill: [{shape: box, min: [%g, %g, %g], max: [%g, %g, %g]}]}\n"
           "solver: {type: explicit, steps: 1, breaking: false}\n"
           "output: {picture: false}\n",
           curve, rule, DX, influence, -h, -h, -0.3 * h, h, h, 0.3 * h);
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
  damage_and_deform(s);
}
static void deviatoric_block(peri_sim *s, const char *curve, const char *influence) {
  rule_block(s, curve, influence, "deviatoric");
}

Test(kernel_paths, lps_3d_deviatoric) {
  peri_sim s;
  deviatoric_block(&s, "strains: [0.002, 0.0065], stresses: [400e6, 450e6]", "constant");
  /* a shear of 3 first-yield strains on top of the random field: every node yields */
  for (int32_t i = 0; i < s.disc.p.n; ++i) s.disc.p.u[3 * (size_t)i] += 0.006 * s.disc.p.x[3 * (size_t)i + 1];
  const size_t bytes = sizeof(double) * 3 * (size_t)s.disc.p.n_owned;
  double *a = malloc(bytes), *b = malloc(bytes);
  s.mat.model->force(&s); /* (the first evaluation yields) */
  const double in_blocks = forces_both_paths(&s, a, b);
  int32_t yielded = 0;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i) yielded += s.state.plastic_nodes[i] != 0;
  cr_log_info("lps 3D deviatoric: %.3f of the bonds in node blocks, %d of %d nodes yielded", in_blocks, yielded,
              s.disc.p.n_owned);
  cr_assert_gt(in_blocks, 0.5, "the test needs node blocks");
  cr_assert_gt(yielded, s.disc.p.n_owned / 2, "the test needs yielded nodes");
  cr_expect(memcmp(a, b, bytes) == 0, "lps 3D deviatoric: the block and one-node paths differ");
  free(a);
  free(b);
  peri_sim_free(&s);
}

/* The tensor yield rule (docs/plasticity.md section 10) on the same sheared block, with broken
 * bonds: pass 1's tensor sums and the force with the neighbours' plastic terms by a block of
 * eight nodes on its template and node by node agree bit for bit (the second evaluation maps
 * from the first's state at the same displacement, on the yield surface: no flow), and a
 * yielded node's term is nonzero. */
static void check_tensor_paths(const char *influence) {
  peri_sim s;
  rule_block(&s, "strains: [0.002, 0.0065], stresses: [400e6, 450e6]", influence, "deviatoric_tensor");
  for (int32_t i = 0; i < s.disc.p.n; ++i) s.disc.p.u[3 * (size_t)i] += 0.006 * s.disc.p.x[3 * (size_t)i + 1];
  const size_t bytes = sizeof(double) * 3 * (size_t)s.disc.p.n_owned;
  double *a = malloc(bytes), *b = malloc(bytes), *psi = malloc(sizeof(double) * (size_t)s.disc.p.n_owned);
  s.mat.model->force(&s); /* (the first evaluation yields) */
  const double in_blocks = forces_both_paths(&s, a, b);
  peri_yield_index(&s, psi);
  int32_t yielded = 0;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i) yielded += psi[i] > 0.0;
  cr_log_info("lps 3D tensor %s: %.3f of the bonds in node blocks, %d of %d nodes yielded", influence, in_blocks,
              yielded, s.disc.p.n_owned);
  cr_assert_gt(in_blocks, 0.5, "the test needs node blocks");
  cr_assert_gt(yielded, s.disc.p.n_owned / 2, "the test needs yielded nodes");
  cr_expect(memcmp(a, b, bytes) == 0, "lps 3D tensor %s: the block and one-node paths differ", influence);
  free(a), free(b), free(psi);
  peri_sim_free(&s);
}
Test(kernel_paths, lps_3d_tensor) { check_tensor_paths("constant"); }
Test(kernel_paths, lps_3d_tensor_inverse) { check_tensor_paths("inverse"); }

/* The deviatoric rule's return on both paths from the same state: a block of eight nodes runs
 * it on its template, the other nodes one by one, and the two map the plastic state, the
 * bonds' plastic terms and the yield flags bit for bit, from the state before the first yield
 * and from a yielded one further sheared (the same block, with broken bonds, as above); with the
 * weights evaluated by the kernels (constant and inverse influence) and stored (Gaussian). */
static void check_deviatoric_return(const char *influence) {
  peri_sim s;
  deviatoric_block(&s,
                   "strains: [0.002, 0.0065, 0.0124, 0.0168], power_law: {yield_stress: 400e6, yield_strain: 0.002, "
                   "exponent: 0.1}",
                   influence);
  const size_t n3 = 3 * (size_t)s.disc.p.n;
  double *u = malloc(sizeof(double) * n3);
  memcpy(u, s.disc.p.u, sizeof(double) * n3);
  /* (an evaluation at rest first: the flags and the node blocks exist, nothing yields) */
  memset(s.disc.p.u, 0, sizeof(double) * n3);
  s.mat.model->force(&s);
  memcpy(s.disc.p.u, u, sizeof(double) * n3);
  const size_t n_bonds = (size_t)s.disc.bonds.offset[s.disc.p.n_owned], owned = (size_t)s.disc.p.n_owned;
  const size_t state_bytes = sizeof(double) * n_bonds * (size_t)s.state.plastic_layers,
               term_bytes = sizeof(double) * n_bonds, f_bytes = sizeof(double) * 3 * owned,
               energy_bytes = sizeof(double) * owned;
  char *start = malloc(state_bytes + owned),
       *block = malloc(state_bytes + term_bytes + owned + f_bytes + energy_bytes),
       *node = malloc(state_bytes + term_bytes + owned + f_bytes + energy_bytes);
  for (int round = 0; round < 2; ++round) {
    /* round 0: a shear of 3 first-yield strains; round 1: 2 more, from the yielded state */
    for (int32_t i = 0; i < s.disc.p.n; ++i)
      s.disc.p.u[3 * (size_t)i] += (round ? 0.004 : 0.006) * s.disc.p.x[3 * (size_t)i + 1];
    peri_plastic_state_in_bond_order(&s); /* (the two paths keep it in slots of their own) */
    memcpy(start, s.state.plastic_stretch, state_bytes);
    memcpy(start + state_bytes, s.state.plastic_nodes, owned);
    for (int path = 0; path < 2; ++path) {
      char *out = path ? node : block;
      memcpy(s.state.plastic_stretch, start, state_bytes);
      /* (the terms are not restored: every evaluation writes those of the nodes with a plastic
       * state, and the others' are 0; the two paths keep them in slots of their own) */
      memcpy(s.state.plastic_nodes, start + state_bytes, owned);
      s.disc.generic_bond_loops = path == 1;
      s.mat.model->force(&s);
      /* the energy density of each node, the state still in the slots (a block's own
       * eight-lane loops) */
      s.mat.model->energy(&s, (double *)(out + state_bytes + term_bytes + owned + f_bytes));
      double *terms = (double *)(out + state_bytes); /* bond by bond */
      for (size_t k = 0; k < n_bonds; ++k) terms[k] = s.state.plastic_bond_term[s.state.plastic_slots.bond_slot[k]];
      peri_plastic_state_in_bond_order(&s);
      memcpy(out, s.state.plastic_stretch, state_bytes);
      memcpy(out + state_bytes + term_bytes, s.state.plastic_nodes, owned);
      memcpy(out + state_bytes + term_bytes + owned, s.disc.p.f, f_bytes);
      if (path == 0)
        cr_assert_gt((double)s.disc.node_blocks->block_bonds / (double)n_bonds, 0.5, "the test needs node blocks");
    }
    s.disc.generic_bond_loops = false;
    int32_t yielded = 0;
    for (size_t i = 0; i < owned; ++i) yielded += s.state.plastic_nodes[i] != 0;
    cr_log_info("lps 3D deviatoric return, %s influence, round %d: %d of %zu nodes yielded", influence, round, yielded,
                owned);
    cr_assert_gt(yielded, (int32_t)(owned / 2), "the test needs yielded nodes");
    cr_expect(memcmp(block, node, state_bytes) == 0, "round %d: the plastic states of the two paths differ", round);
    cr_expect(memcmp(block + state_bytes, node + state_bytes, term_bytes) == 0,
              "round %d: the plastic terms of the two paths differ", round);
    cr_expect(memcmp(block + state_bytes + term_bytes, node + state_bytes + term_bytes, owned) == 0,
              "round %d: the yield flags of the two paths differ", round);
    cr_expect(memcmp(block + state_bytes + term_bytes + owned, node + state_bytes + term_bytes + owned, f_bytes) == 0,
              "round %d: the forces of the two paths differ", round);
    const size_t at = state_bytes + term_bytes + owned + f_bytes;
    double largest = 0.0;
    for (size_t i = 0; i < owned; ++i) largest = fmax(largest, ((const double *)(block + at))[i]);
    cr_assert_gt(largest, 0.0, "the test needs strain energy");
    cr_expect(memcmp(block + at, node + at, energy_bytes) == 0, "round %d: the energies of the two paths differ",
              round);
  }
  free(u);
  free(start);
  free(block);
  free(node);
  peri_sim_free(&s);
}

Test(kernel_paths, lps_3d_deviatoric_return) { check_deviatoric_return("constant"); }
Test(kernel_paths, lps_3d_deviatoric_return_inverse) { check_deviatoric_return("inverse"); }
Test(kernel_paths, lps_3d_deviatoric_return_gaussian) { check_deviatoric_return("gaussian"); }
