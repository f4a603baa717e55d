/* Element stiffness matrices (src/fem/bar2.c, quad4.c, quad4_incompatible.c, tri3.c, hex8.c,
 * docs/coupling.md):
 * closed-form entries of the square and the cube (2x2 / 2x2x2 Gauss points integrate a
 * parallelogram exactly, so the entries agree to round-off, 1e-12 relative), symmetry, the
 * rigid-body modes in the null space, and the patch test: on a patch of distorted elements
 * whose boundary nodes follow u = a + H x, the assembled force on the interior node vanishes
 * (a complete linear field is represented exactly; 1e-12 of the largest nodal force), and
 * inverted elements are rejected. The constant-strain triangle: its closed-form entry, rigid
 * modes, and the nodal forces of a constant stress (the patch test of one element). The Q4
 * with incompatible modes (QM6): the energy of pure bending on a square equals the exact
 * (2/3) E kappa^2 h to round-off where the plain Q4's exceeds it by its shear locking, and the
 * patch test on the distorted patch. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>
#include "peri/error.h"
#include "peri/fem.h"

#define RTOL 1e-12

Test(fem_bar2, stiffness_and_rigid_translation) {
  const double x[2] = {2.0, 2.5};
  double K[4];
  cr_assert_eq(peri_fem_bar2_stiffness(x, 3.0, 0.2, K), PERI_OK);
  const double k = 3.0 * 0.2 / 0.5; /* EA/L */
  cr_expect(fabs(K[0] - k) <= RTOL * k && fabs(K[1] + k) <= RTOL * k && fabs(K[2] + k) <= RTOL * k &&
            fabs(K[3] - k) <= RTOL * k);
  cr_expect(fabs(K[0] * 1.0 + K[1] * 1.0) <= RTOL * k, "a translation stretches nothing");
  const double reversed[2] = {2.5, 2.0};
  cr_expect_eq(peri_fem_bar2_stiffness(reversed, 3.0, 0.2, K), PERI_ERR_INPUT);
}

/* K u for a dense n x n K */
static void multiply(int n, const double *K, const double *u, double *f) {
  for (int r = 0; r < n; ++r) {
    f[r] = 0.0;
    for (int c = 0; c < n; ++c) f[r] += K[n * r + c] * u[c];
  }
}

static double max_abs(int n, const double *v) {
  double m = 0.0;
  for (int k = 0; k < n; ++k) m = fmax(m, fabs(v[k]));
  return m;
}

Test(fem_quad4, square_entries_plane_stress_and_strain) {
  /* unit square, E = 2, nu = 0.3, h = 0.5 */
  const double xy[8] = {0, 0, 1, 0, 1, 1, 0, 1};
  const double E = 2.0, nu = 0.3, h = 0.5;
  double K[64];
  cr_assert_eq(peri_fem_quad4_stiffness(xy, E, nu, PERI_PLANE_STRESS, h, K), PERI_OK);
  /* K_11 = E h/(1-nu^2) (3-nu)/6, K_12 = E h/(1-nu^2) (1+nu)/8 (int N1,x^2 = int N1,y^2 = 1/3,
   * int N1,x N1,y = 1/4) */
  const double f = E * h / (1.0 - nu * nu);
  cr_expect(fabs(K[0] - f * (3.0 - nu) / 6.0) <= RTOL * f, "K11 %.17g", K[0]);
  cr_expect(fabs(K[1] - f * (1.0 + nu) / 8.0) <= RTOL * f, "K12 %.17g", K[1]);
  cr_assert_eq(peri_fem_quad4_stiffness(xy, E, nu, PERI_PLANE_STRAIN, h, K), PERI_OK);
  /* plane strain: D11 = E(1-nu)/((1+nu)(1-2nu)), D33 = E/(2(1+nu)); K11 = h (D11 + D33)/3 */
  const double D11 = E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)), D33 = E / (2.0 * (1.0 + nu));
  cr_expect(fabs(K[0] - h * (D11 + D33) / 3.0) <= RTOL * D11, "plane strain K11 %.17g", K[0]);
}

Test(fem_quad4, symmetric_with_three_rigid_modes) {
  const double xy[8] = {0.1, -0.2, 1.3, 0.1, 1.1, 0.9, -0.1, 1.2}; /* a general convex quadrilateral */
  double K[64];
  cr_assert_eq(peri_fem_quad4_stiffness(xy, 1.0, 0.25, PERI_PLANE_STRESS, 1.0, K), PERI_OK);
  const double scale = max_abs(64, K);
  for (int r = 0; r < 8; ++r)
    for (int c = 0; c < 8; ++c) cr_expect(fabs(K[8 * r + c] - K[8 * c + r]) <= RTOL * scale);
  double modes[3][8], f[8];
  for (int a = 0; a < 4; ++a) {
    modes[0][2 * a] = 1, modes[0][2 * a + 1] = 0;
    modes[1][2 * a] = 0, modes[1][2 * a + 1] = 1;
    modes[2][2 * a] = -xy[2 * a + 1], modes[2][2 * a + 1] = xy[2 * a]; /* infinitesimal rotation */
  }
  for (int m = 0; m < 3; ++m) {
    multiply(8, K, modes[m], f);
    cr_expect(max_abs(8, f) <= RTOL * scale, "rigid mode %d: force %g", m, max_abs(8, f));
  }
  /* a stretch is not a rigid mode: the check above can fail */
  double stretch[8];
  for (int a = 0; a < 4; ++a) stretch[2 * a] = xy[2 * a], stretch[2 * a + 1] = 0.0;
  multiply(8, K, stretch, f);
  cr_expect(max_abs(8, f) > 0.1 * scale);
}

Test(fem_quad4, patch_test_on_distorted_mesh) {
  /* 3x3 nodes on [0,2]^2 with the centre node moved; u = a + H x on the boundary nodes */
  double X[9][2];
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) X[3 * j + i][0] = i, X[3 * j + i][1] = j;
  X[4][0] = 1.17, X[4][1] = 0.86;
  const double a[2] = {0.3, -0.1}, H[2][2] = {{0.02, -0.013}, {0.007, -0.031}};
  double u[18], F[18] = {0};
  for (int n = 0; n < 9; ++n)
    for (int d = 0; d < 2; ++d) u[2 * n + d] = a[d] + H[d][0] * X[n][0] + H[d][1] * X[n][1];
  double scale = 0.0;
  for (int ej = 0; ej < 2; ++ej)
    for (int ei = 0; ei < 2; ++ei) {
      const int nodes[4] = {3 * ej + ei, 3 * ej + ei + 1, 3 * (ej + 1) + ei + 1, 3 * (ej + 1) + ei};
      double xy[8], K[64], ue[8], fe[8];
      for (int k = 0; k < 4; ++k)
        for (int d = 0; d < 2; ++d) xy[2 * k + d] = X[nodes[k]][d], ue[2 * k + d] = u[2 * nodes[k] + d];
      cr_assert_eq(peri_fem_quad4_stiffness(xy, 1.0, 1.0 / 3.0, PERI_PLANE_STRESS, 1.0, K), PERI_OK);
      multiply(8, K, ue, fe);
      for (int k = 0; k < 4; ++k)
        for (int d = 0; d < 2; ++d) F[2 * nodes[k] + d] += fe[2 * k + d];
    }
  scale = max_abs(18, F);
  cr_assert(scale > 0.0);
  cr_expect(fabs(F[8]) <= RTOL * scale && fabs(F[9]) <= RTOL * scale, "interior node force %g %g (scale %g)",
            F[8], F[9], scale);
}

Test(fem_quad4, inverted_element_rejected) {
  const double clockwise[8] = {0, 0, 0, 1, 1, 1, 1, 0};
  const double bowtie[8] = {0, 0, 1, 1, 1, 0, 0, 1};
  double K[64];
  cr_expect_eq(peri_fem_quad4_stiffness(clockwise, 1.0, 0.3, PERI_PLANE_STRESS, 1.0, K), PERI_ERR_INPUT);
  cr_expect_eq(peri_fem_quad4_stiffness(bowtie, 1.0, 0.3, PERI_PLANE_STRESS, 1.0, K), PERI_ERR_INPUT);
}

Test(fem_tri3, entry_rigid_modes_constant_stress) {
  /* the right triangle (0,0), (1,0), (0,1), plane stress, E = 2, nu = 0.3, h = 0.5:
   * b1 = c1 = -1 over 2A = 1, so K11 = A h (D11 b1^2 + D33 c1^2) = h/2 E/(1-nu^2) (1 + (1-nu)/2) */
  const double xy[6] = {0, 0, 1, 0, 0, 1}, E = 2.0, nu = 0.3, h = 0.5;
  double K[36], f[6];
  cr_assert_eq(peri_fem_tri3_stiffness(xy, E, nu, PERI_PLANE_STRESS, h, K), PERI_OK);
  const double D11 = E / (1.0 - nu * nu);
  cr_expect(fabs(K[0] - 0.5 * h * D11 * (1.0 + 0.5 * (1.0 - nu))) <= RTOL * D11, "K11 %.17g", K[0]);
  const double scale = max_abs(36, K);
  double modes[3][6];
  for (int a = 0; a < 3; ++a) {
    modes[0][2 * a] = 1, modes[0][2 * a + 1] = 0;
    modes[1][2 * a] = 0, modes[1][2 * a + 1] = 1;
    modes[2][2 * a] = -xy[2 * a + 1], modes[2][2 * a + 1] = xy[2 * a];
  }
  for (int m = 0; m < 3; ++m) {
    multiply(6, K, modes[m], f);
    cr_expect(max_abs(6, f) <= RTOL * scale, "rigid mode %d: force %g", m, max_abs(6, f));
  }
  /* u = x e_x: sigma_xx = D11, sigma_yy = nu D11; each edge (length L, normal n) gives
   * h L/2 sigma n to each of its ends: node 2 gets h/2 (D11, nu D11) from the edge x + y = 1 and
   * h/2 (0, -nu D11) from the edge y = 0, so (h D11/2, 0) */
  double u[6];
  for (int a = 0; a < 3; ++a) u[2 * a] = xy[2 * a], u[2 * a + 1] = 0.0;
  multiply(6, K, u, f);
  cr_expect(fabs(f[2] - 0.5 * h * D11) <= RTOL * D11 && fabs(f[3]) <= RTOL * D11,
            "node 2 force (%g, %g)", f[2], f[3]);
  const double clockwise[6] = {0, 0, 0, 1, 1, 0};
  cr_expect_eq(peri_fem_tri3_stiffness(clockwise, E, nu, PERI_PLANE_STRESS, h, K), PERI_ERR_INPUT);
}

Test(fem_quad4_incompatible, pure_bending_and_patch_test) {
  /* the square [-1, 1]^2, plane stress: u = kappa x y, v = -kappa (x^2 + nu y^2)/2 is pure
   * bending, sigma_xx = E kappa y, energy (1/2) int E kappa^2 y^2 h dA = (2/3) E kappa^2 h; its
   * nodal values are the bilinear part (v equal at the corners: a translation) */
  const double xy[8] = {-1, -1, 1, -1, 1, 1, -1, 1}, E = 3.0, nu = 0.25, h = 0.5, kappa = 0.01;
  double u[8], K[64], f[8];
  for (int a = 0; a < 4; ++a) {
    const double x = xy[2 * a], y = xy[2 * a + 1];
    u[2 * a] = kappa * x * y, u[2 * a + 1] = -0.5 * kappa * (x * x + nu * y * y);
  }
  const double exact = 2.0 / 3.0 * E * kappa * kappa * h;
  double energy[2];
  for (int k = 0; k < 2; ++k) {
    cr_assert_eq((k ? peri_fem_quad4_stiffness : peri_fem_quad4_incompatible_stiffness)(xy, E, nu, PERI_PLANE_STRESS,
                                                                                       h, K), PERI_OK);
    multiply(8, K, u, f);
    energy[k] = 0.0;
    for (int r = 0; r < 8; ++r) energy[k] += 0.5 * u[r] * f[r];
  }
  cr_expect(fabs(energy[0] - exact) <= RTOL * exact, "QM6 bending energy %.17g, exact %.17g", energy[0], exact);
  cr_expect_gt(energy[1], 1.1 * exact, "the plain Q4 locks: energy %g against %g", energy[1], exact);
  /* the patch test on the distorted 2 x 2 patch of fem_quad4 */
  double X[9][2];
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) X[3 * j + i][0] = i, X[3 * j + i][1] = j;
  X[4][0] = 1.17, X[4][1] = 0.86;
  const double a0[2] = {0.3, -0.1}, H[2][2] = {{0.02, -0.013}, {0.007, -0.031}};
  double U[18], F[18] = {0};
  for (int n = 0; n < 9; ++n)
    for (int d = 0; d < 2; ++d) U[2 * n + d] = a0[d] + H[d][0] * X[n][0] + H[d][1] * X[n][1];
  for (int ej = 0; ej < 2; ++ej)
    for (int ei = 0; ei < 2; ++ei) {
      const int nodes[4] = {3 * ej + ei, 3 * ej + ei + 1, 3 * (ej + 1) + ei + 1, 3 * (ej + 1) + ei};
      double exy[8], ue[8], fe[8];
      for (int k = 0; k < 4; ++k)
        for (int d = 0; d < 2; ++d) exy[2 * k + d] = X[nodes[k]][d], ue[2 * k + d] = U[2 * nodes[k] + d];
      cr_assert_eq(peri_fem_quad4_incompatible_stiffness(exy, 1.0, 1.0 / 3.0, PERI_PLANE_STRESS, 1.0, K), PERI_OK);
      multiply(8, K, ue, fe);
      for (int k = 0; k < 4; ++k)
        for (int d = 0; d < 2; ++d) F[2 * nodes[k] + d] += fe[2 * k + d];
    }
  const double scale = max_abs(18, F);
  cr_expect(fabs(F[8]) <= RTOL * scale && fabs(F[9]) <= RTOL * scale, "interior node force %g %g (scale %g)", F[8],
            F[9], scale);
}

static void cube(double x0, double y0, double z0, double L, double xyz[24]) {
  static const int ca[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (int a = 0; a < 8; ++a) {
    xyz[3 * a] = x0 + L * ca[a][0];
    xyz[3 * a + 1] = y0 + L * ca[a][1];
    xyz[3 * a + 2] = z0 + L * ca[a][2];
  }
}

Test(fem_hex8, cube_entry_symmetry_rigid_modes) {
  double xyz[24], K[576];
  const double L = 0.5, E = 3.0, nu = 0.25;
  cube(1.0, 2.0, 3.0, L, xyz);
  cr_assert_eq(peri_fem_hex8_stiffness(xyz, E, nu, K), PERI_OK);
  /* K_11 = L (lambda + 2 mu)/9 + 2 L mu/9: int (N1,x)^2 dV = L/9 on a cube of side L */
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  cr_expect(fabs(K[0] - L * (lambda + 4.0 * mu) / 9.0) <= RTOL * K[0], "K11 %.17g", K[0]);
  /* a general hexahedron: corners perturbed */
  static const double noise[24] = {0.03, -0.02, 0.01, -0.04, 0.02, 0.0,  0.05, 0.01,  -0.03, 0.0,  -0.02, 0.04,
                                   0.02, 0.03,  -0.05, 0.01, -0.01, 0.02, -0.03, 0.04, 0.0,  0.02, -0.04, -0.01};
  for (int k = 0; k < 24; ++k) xyz[k] += noise[k] * L;
  cr_assert_eq(peri_fem_hex8_stiffness(xyz, E, nu, K), PERI_OK);
  const double scale = max_abs(576, K);
  for (int r = 0; r < 24; ++r)
    for (int c = 0; c < 24; ++c) cr_expect(fabs(K[24 * r + c] - K[24 * c + r]) <= RTOL * scale);
  double f[24];
  for (int m = 0; m < 6; ++m) {
    double mode[24];
    for (int a = 0; a < 8; ++a) {
      const double *x = &xyz[3 * a];
      double v[3] = {0, 0, 0};
      if (m < 3) v[m] = 1.0;
      else { /* rotation about axis m - 3: omega x x */
        const double w[3] = {m == 3, m == 4, m == 5};
        v[0] = w[1] * x[2] - w[2] * x[1], v[1] = w[2] * x[0] - w[0] * x[2], v[2] = w[0] * x[1] - w[1] * x[0];
      }
      for (int d = 0; d < 3; ++d) mode[3 * a + d] = v[d];
    }
    multiply(24, K, mode, f);
    cr_expect(max_abs(24, f) <= 1e-11 * scale, "rigid mode %d: force %g", m, max_abs(24, f));
  }
}

Test(fem_hex8, patch_test_on_distorted_mesh) {
  /* 3x3x3 nodes on [0,2]^3 with the centre node moved */
  double X[27][3];
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) X[9 * k + 3 * j + i][0] = i, X[9 * k + 3 * j + i][1] = j, X[9 * k + 3 * j + i][2] = k;
  X[13][0] = 0.88, X[13][1] = 1.12, X[13][2] = 1.07;
  const double a[3] = {0.1, 0.2, -0.3};
  const double H[3][3] = {{0.01, 0.02, -0.005}, {-0.011, 0.03, 0.004}, {0.006, -0.008, -0.02}};
  double u[81], F[81] = {0};
  for (int n = 0; n < 27; ++n)
    for (int d = 0; d < 3; ++d) u[3 * n + d] = a[d] + H[d][0] * X[n][0] + H[d][1] * X[n][1] + H[d][2] * X[n][2];
  static const int ca[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (int ek = 0; ek < 2; ++ek)
    for (int ej = 0; ej < 2; ++ej)
      for (int ei = 0; ei < 2; ++ei) {
        int nodes[8];
        double xyz[24], ue[24], fe[24], K[576];
        for (int c = 0; c < 8; ++c) {
          nodes[c] = 9 * (ek + ca[c][2]) + 3 * (ej + ca[c][1]) + ei + ca[c][0];
          for (int d = 0; d < 3; ++d) xyz[3 * c + d] = X[nodes[c]][d], ue[3 * c + d] = u[3 * nodes[c] + d];
        }
        cr_assert_eq(peri_fem_hex8_stiffness(xyz, 1.0, 0.25, K), PERI_OK);
        multiply(24, K, ue, fe);
        for (int c = 0; c < 8; ++c)
          for (int d = 0; d < 3; ++d) F[3 * nodes[c] + d] += fe[3 * c + d];
      }
  const double scale = max_abs(81, F);
  cr_assert(scale > 0.0);
  for (int d = 0; d < 3; ++d)
    cr_expect(fabs(F[39 + d]) <= RTOL * scale, "interior node force %g (scale %g)", F[39 + d], scale);
}

Test(fem_hex8, inverted_element_rejected) {
  double xyz[24], K[576];
  cube(0, 0, 0, 1.0, xyz);
  for (int a = 0; a < 4; ++a) xyz[3 * a + 2] = 2.0; /* bottom face above the top */
  cr_expect_eq(peri_fem_hex8_stiffness(xyz, 1.0, 0.25, K), PERI_ERR_INPUT);
}
