/* Position-aware surface correction (docs/models.md 4.1): every node gets its own influence
 * factors on its own bonds, chosen so that its energy under every uniform strain is the
 * classical one (Mitchell, Silling and Littlewood 2015, "A position-aware linear solid
 * constitutive model for peridynamics", J. Mech. Mater. Struct. 10(5), 539-557).
 *
 * For a uniform strain eps the bond extension is |xi| n.eps.n (n = xi/|xi|), so a node's energy
 * is a quadratic form in eps whose coefficients are moments of its family. Of all factors that
 * make those moments the classical ones, the ones closest to 1 (least squares, weighted by the
 * bond's own weight q) are 1 + sum_r lambda_r phi_r(n), phi_r the products of the moments'
 * functions; lambda solves the Gram system A lambda = T - sum q phi (A = sum q phi phi^T).
 * A is singular where the functions are dependent on the sphere (2D: 6 products span 5
 * functions; 3D LPS: 21 products of deviatoric modes span 15), so the system is solved by
 * a pseudo-inverse (symmetric Jacobi eigenvalues). No factor is negative: see fit_solve.
 *
 * PMB: W_i = 1/2 sum_j q g_i(n) s^2, q = c omega |xi| beta V_j / 2; target the bond-based
 *   isotropic tensor C_abcd = (M/3)(d_ab d_cd + d_ac d_bd + d_ad d_bc) (M the P-wave modulus).
 *   The bond factor is G_ij = (g_i(n) + g_j(n))/2, the gradient of sum_i V_i W_i.
 * LPS: first the dilatation, D_i(n) = 1 + mu_i : n n with sum_j D omega |xi|^2 w n n = (m_i/dim) I,
 *   so that theta_i = (n_theta/dim) tr eps for every uniform strain; then the deviatoric
 *   factor s_i(n) with (alpha_i/2) sum_j s omega (e^d)^2 w = W_cl - K_theta theta^2/2. The force
 *   state is the gradient of W_i = K_theta theta_i^2/2 + (alpha_i/2) sum_j s_i omega (e^d)^2 w:
 *     t_ij = (n_theta/m_i)(K_theta theta_i - alpha_i P_i/3) D_i omega |xi| + alpha_i s_i omega e^d_ij,
 *     P_i  = sum_j s_i omega e^d |xi| w,
 *   each end with its own factors (t_ji with j's). The factors are frozen as bonds break. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/constants.h"
#include "peri/error.h"
#include "bond_chunk.h"
#include "bond_kernel.h"
#include "surface_correction.h"

enum { MAX_MODES = 6, MAX_PRODUCTS = 21 };
/* The smallest factor: a bond keeps at least this share of its bulk stiffness. */
static const double FACTOR_FLOOR = 0.0;
/* A ridge on the Gram system, this share of its mean diagonal: it bounds the factors of a node
 * whose family cannot meet the moments (the corner line of the 3D bar of docs/verification.md
 * case 17: largest factor 16 with it, 412 without), and leaves the others' energies exact to about this share. */
static const double RIDGE = 1e-3;

/* The unit strains of a dim-dimensional body: the normal ones, then the shears (eps_ab =
 * eps_ba = 1/2). Returns their number, dim(dim+1)/2. */
static int strain_modes(int dim, double eps[MAX_MODES][3][3]) {
  memset(eps, 0, sizeof(double) * MAX_MODES * 9);
  int count = 0;
  for (int a = 0; a < dim; ++a) eps[count++][a][a] = 1.0;
  for (int a = 0; a < dim; ++a)
    for (int c = a + 1; c < dim; ++c) eps[count][a][c] = eps[count][c][a] = 0.5, ++count;
  return count;
}

static double contract(const double e[3][3], const double n[3]) {
  double s = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) s += n[a] * e[a][c] * n[c];
  return s;
}

static double trace(const double e[3][3]) { return e[0][0] + e[1][1] + e[2][2]; }

static double double_dot(const double a[3][3], const double c[3][3]) {
  double s = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s += a[i][j] * c[i][j];
  return s;
}

/* The products phi_r = f_p f_q (p <= q) of the mode values f. */
static int products(const double *f, int modes, double *phi) {
  int r = 0;
  for (int p = 0; p < modes; ++p)
    for (int q = p; q < modes; ++q) phi[r++] = f[p] * f[q];
  return r;
}

/* x = A^+ b for a symmetric A (n <= MAX_PRODUCTS, overwritten): cyclic Jacobi rotations to the
 * eigenvalues, then the eigenvalues below 1e-10 of the largest left out. */
static void pseudo_inverse_solve(int n, double *A, const double *b, double *x) {
  double V[MAX_PRODUCTS * MAX_PRODUCTS];
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) V[i * n + j] = i == j;
  for (int sweep = 0; sweep < 100; ++sweep) {
    double off = 0.0, diag = 0.0;
    for (int i = 0; i < n; ++i) {
      diag += A[i * n + i] * A[i * n + i];
      for (int j = i + 1; j < n; ++j) off += A[i * n + j] * A[i * n + j];
    }
    if (off <= 1e-30 * diag) break;
    for (int p = 0; p < n; ++p)
      for (int q = p + 1; q < n; ++q) {
        const double apq = A[p * n + q];
        if (fabs(apq) < 1e-300) continue;
        const double tau = (A[q * n + q] - A[p * n + p]) / (2.0 * apq);
        const double t = (tau >= 0.0 ? 1.0 : -1.0) / (fabs(tau) + sqrt(1.0 + tau * tau));
        const double c = 1.0 / sqrt(1.0 + t * t), s = t * c;
        for (int k = 0; k < n; ++k) { /* columns p, q */
          const double akp = A[k * n + p], akq = A[k * n + q];
          A[k * n + p] = c * akp - s * akq, A[k * n + q] = s * akp + c * akq;
        }
        for (int k = 0; k < n; ++k) { /* rows p, q */
          const double apk = A[p * n + k], aqk = A[q * n + k];
          A[p * n + k] = c * apk - s * aqk, A[q * n + k] = s * apk + c * aqk;
        }
        for (int k = 0; k < n; ++k) {
          const double vkp = V[k * n + p], vkq = V[k * n + q];
          V[k * n + p] = c * vkp - s * vkq, V[k * n + q] = s * vkp + c * vkq;
        }
      }
  }
  double largest = 0.0;
  for (int i = 0; i < n; ++i) largest = fmax(largest, fabs(A[i * n + i]));
  for (int i = 0; i < n; ++i) x[i] = 0.0;
  for (int e = 0; e < n; ++e) {
    const double lambda = A[e * n + e];
    if (!(fabs(lambda) > 1e-10 * largest)) continue;
    double proj = 0.0;
    for (int i = 0; i < n; ++i) proj += V[i * n + e] * b[i];
    for (int i = 0; i < n; ++i) x[i] += V[i * n + e] * proj / lambda;
  }
}

/* The per-node problem: the bonds' weights q and functions phi, then lambda. The factors are
 * bounded below, g = max(FACTOR_FLOOR, 1 + lambda.phi) (the KKT form of the bounded least
 * squares), by active-set iterations: the Gram system over the bonds above the floor, the
 * bonds at the floor counted with the floor, until the set stops changing. Where no such
 * factors meet the moments (the corner of a box: a quarter family cannot have the isotropic
 * odd moments with positive factors) the pseudo-inverse gives the nearest. */
typedef struct fit {
  int n, bonds, capacity;
  double *q, *phi; /* [bonds], [bonds * n] */
} fit;

static void fit_add(fit *f, double q, const double *phi) {
  if (f->bonds == f->capacity) {
    f->capacity = f->capacity ? 2 * f->capacity : 64;
    f->q = peri_realloc(f->q, sizeof(double) * (size_t)f->capacity);
    f->phi = peri_realloc(f->phi, sizeof(double) * (size_t)f->capacity * (size_t)f->n);
  }
  f->q[f->bonds] = q;
  memcpy(&f->phi[(size_t)f->bonds * f->n], phi, sizeof(double) * (size_t)f->n);
  f->bonds++;
}

static double factor_at(const double *lambda, const double *phi, int count) {
  double g = 1.0;
  for (int r = 0; r < count; ++r) g += lambda[r] * phi[r];
  return g > FACTOR_FLOOR ? g : FACTOR_FLOOR;
}

static void fit_solve(fit *f, const double *target, double *lambda) {
  const int n = f->n;
  for (int r = 0; r < n; ++r) lambda[r] = 0.0;
  for (int iteration = 0; iteration < 50; ++iteration) {
    double A[MAX_PRODUCTS * MAX_PRODUCTS] = {0}, rhs[MAX_PRODUCTS];
    for (int r = 0; r < n; ++r) rhs[r] = target[r];
    for (int k = 0; k < f->bonds; ++k) {
      const double *phi = &f->phi[(size_t)k * n], q = f->q[k];
      double g = 1.0;
      for (int r = 0; r < n; ++r) g += lambda[r] * phi[r];
      const bool floor = iteration > 0 && g < FACTOR_FLOOR;
      for (int r = 0; r < n; ++r) {
        rhs[r] -= q * (floor ? FACTOR_FLOOR : 1.0) * phi[r];
        if (!floor)
          for (int c = 0; c < n; ++c) A[r * n + c] += q * phi[r] * phi[c];
      }
    }
    double next[MAX_PRODUCTS], mean = 0.0;
    for (int r = 0; r < n; ++r) mean += A[r * n + r] / n;
    for (int r = 0; r < n; ++r) A[r * n + r] += RIDGE * mean;
    pseudo_inverse_solve(n, A, rhs, next);
    bool same = true; /* the same bonds at the floor as the last iteration */
    for (int k = 0; k < f->bonds && same; ++k) {
      const double *phi = &f->phi[(size_t)k * n];
      double g_old = 1.0, g_new = 1.0;
      for (int r = 0; r < n; ++r) g_old += lambda[r] * phi[r], g_new += next[r] * phi[r];
      same = iteration > 0 && (g_old < FACTOR_FLOOR) == (g_new < FACTOR_FLOOR);
    }
    memcpy(lambda, next, sizeof(double) * (size_t)n);
    if (same) break;
  }
  free(f->q);
  free(f->phi);
  f->q = f->phi = NULL;
  f->bonds = f->capacity = 0;
}

/* The deviatoric mode values of a bond direction: n.eps_p.n - theta_p/3 (LPS), or n.eps_p.n
 * (PMB, theta_p = 0), theta_p = (n_theta/dim) tr eps_p. */
static void mode_values(double eps[MAX_MODES][3][3], int modes, double n_theta, int dim, const double n[3],
                        double *f) {
  for (int p = 0; p < modes; ++p) f[p] = contract(eps[p], n) - (n_theta / dim) * trace(eps[p]) / 3.0;
}

/* Node i's own factors on the direction n (unit), from its coefficients c (the dilatation's
 * `modes` values, then the deviatoric or bond `prod` values): *D and *G. */
static void own_factors(const double *c, double eps[MAX_MODES][3][3], int modes, int prod, double n_theta, int dim,
                        bool lps, const double n[3], double *D, double *G) {
  double f[MAX_MODES], phi[MAX_PRODUCTS], nn[MAX_MODES];
  if (lps) {
    for (int p = 0; p < modes; ++p) nn[p] = contract(eps[p], n);
    *D = factor_at(c, nn, modes);
  } else {
    *D = 1.0;
  }
  mode_values(eps, modes, lps ? n_theta : 0.0, dim, n, f);
  products(f, modes, phi);
  *G = factor_at(c + modes, phi, prod);
}

int peri_position_aware_factors(peri_sim *s, bool lps) {
  peri_particles *p = &s->disc.p;
  peri_bonds *b = &s->disc.bonds;
  const int dim = s->disc.geom.dim;
  double eps[MAX_MODES][3][3];
  const int modes = strain_modes(dim, eps), prod = modes * (modes + 1) / 2, stride = modes + prod;
  if (lps) peri_sim_exchange(s, p->wvol, 1);
  double *coef = peri_calloc((size_t)p->n * stride + 1, sizeof(double));
  const size_t nb = (size_t)(b->n_bonds > 0 ? b->n_bonds : 1);
  b->surface_G = peri_malloc(sizeof(double) * nb);
  b->surface_D = peri_malloc(sizeof(double) * nb);
  if (lps) {
    b->surface_G_rev = peri_malloc(sizeof(double) * nb);
    b->surface_D_rev = peri_malloc(sizeof(double) * nb);
  }
#pragma omp parallel for schedule(dynamic, 64)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *mat = &s->mat.materials[p->material[i]];
    const double M = peri_pwave_modulus(&s->disc.geom, mat->E, mat->nu, mat->K, mat->mu);
    const double n_theta = lps ? mat->n_theta : 0.0;
    double *c = &coef[(size_t)i * stride];
    /* LPS dilatation: sum D omega |xi|^2 w n n = (m_i/dim) I */
    if (lps && n_theta > 0.0) {
      fit dil = {.n = modes};
      for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
        const int32_t j = b->neighbor[k];
        double n[3] = {0.0, 0.0, 0.0}, nn[MAX_MODES];
        const double L = peri_bond_xi(p->x, i, j, n);
        for (int a = 0; a < 3; ++a) n[a] /= L;
        for (int q = 0; q < modes; ++q) nn[q] = contract(eps[q], n);
        fit_add(&dil, peri_bonds_omega(b, L) * L * L * peri_bonds_beta(b, L) * p->volume[j], nn);
      }
      double target[MAX_MODES]; /* (m_i/dim) eps_q : I, i.e. the moment's component of mode q */
      for (int q = 0; q < modes; ++q) target[q] = p->wvol[i] / dim * trace(eps[q]);
      fit_solve(&dil, target, c);
    }
    /* the energy: PMB bond factor, or LPS deviatoric factor */
    fit en = {.n = prod};
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      double n[3] = {0.0, 0.0, 0.0}, f[MAX_MODES], phi[MAX_PRODUCTS];
      const double L = peri_bond_xi(p->x, i, j, n);
      for (int a = 0; a < 3; ++a) n[a] /= L;
      mode_values(eps, modes, n_theta, dim, n, f);
      products(f, modes, phi);
      const double w = peri_bonds_omega(b, L) * peri_bonds_beta(b, L) * p->volume[j];
      const double q = lps ? (mat->alpha_m / p->wvol[i]) * w * L * L
                           : 0.5 * 0.5 * (mat->micromodulus + s->mat.materials[p->material[j]].micromodulus) * w * L;
      fit_add(&en, q, phi);
    }
    /* the classical bilinear form of the mode pairs, less the dilatation's part (LPS) */
    double target[MAX_PRODUCTS];
    int r = 0;
    for (int a = 0; a < modes; ++a)
      for (int q = a; q < modes; ++q, ++r) {
        const double ta = trace(eps[a]), tq = trace(eps[q]), dd = double_dot(eps[a], eps[q]);
        if (!lps) {
          target[r] = (M / 3.0) * (ta * tq + 2.0 * dd);
        } else {
          const double classical = dim == 1 ? M * ta * tq : (M - 2.0 * mat->mu) * ta * tq + 2.0 * mat->mu * dd;
          target[r] = classical - mat->K_theta * (n_theta / dim) * ta * (n_theta / dim) * tq;
        }
      }
    fit_solve(&en, target, c + modes);
  }
  peri_sim_exchange(s, coef, stride);
  double lowest = INFINITY;
#pragma omp parallel for schedule(dynamic, 256) reduction(min : lowest)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const double nt_i = lps ? s->mat.materials[p->material[i]].n_theta : 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      const double nt_j = lps ? s->mat.materials[p->material[j]].n_theta : 0.0;
      double n[3] = {0.0, 0.0, 0.0}, Di, Gi, Dj, Gj;
      const double L = peri_bond_xi(p->x, i, j, n);
      for (int a = 0; a < 3; ++a) n[a] /= L;
      own_factors(&coef[(size_t)i * stride], eps, modes, prod, nt_i, dim, lps, n, &Di, &Gi);
      own_factors(&coef[(size_t)j * stride], eps, modes, prod, nt_j, dim, lps, n, &Dj, &Gj);
      if (lps) {
        b->surface_D[k] = Di, b->surface_G[k] = Gi, b->surface_D_rev[k] = Dj, b->surface_G_rev[k] = Gj;
        lowest = fmin(lowest, fmin(Gi, Di));
      } else {
        b->surface_G[k] = 0.5 * (Gi + Gj), b->surface_D[k] = Gi; /* the bond's, and i's own (energy) */
        lowest = fmin(lowest, b->surface_G[k]);
      }
    }
  }
  free(coef);
  b->surface_lowest = lowest;
  return PERI_OK;
}

/* LPS: theta_i (with D) and P_i (with s) of every owned node, exchanged to the ghosts. */
static void pals_lps_sums(peri_sim *s) {
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain;
#pragma omp parallel
  {
    peri_bond_chunk *c = peri_malloc(sizeof *c);
#pragma omp for schedule(dynamic, 256)
    for (int32_t i = 0; i < p->n_owned; ++i) {
      const peri_material *mat = &s->mat.materials[p->material[i]];
      double dil = 0.0, dev_e = 0.0, dev_r = 0.0; /* sum D w e |xi|, sum s w e |xi|, sum s w |xi|^2 */
      for (int64_t k0 = b->offset[i]; k0 < b->offset[i + 1]; k0 += PERI_BOND_CHUNK) {
        const int n = peri_bond_chunk_size(b, i, k0);
        peri_bond_chunk_fill(s, i, k0, n, c);
        for (int a = 0; a < n; ++a) {
          const int64_t k = k0 + a;
          if (b->broken[k]) continue;
          const double L = c->L[a];
          const double e = c->r[a] - L - (eth ? eth[i] : 0.0) * L;
          const double w = c->omega[a] * L * c->beta[a] * p->volume[b->neighbor[k]];
          dil += b->surface_D[k] * w * e;
          dev_e += b->surface_G[k] * w * e;
          dev_r += b->surface_G[k] * w * L;
        }
      }
      const double theta = mat->n_theta * dil / p->wvol[i];
      p->theta[i] = theta;
      p->pstate[i] = dev_e - theta * dev_r / 3.0;
    }
    free(c);
  }
  peri_sim_exchange(s, p->theta, 1);
  peri_sim_exchange(s, p->pstate, 1);
}

/* Node a's half of the pair force on its bond to the other end, with a's factors D and G. */
static double pals_half(const peri_sim *s, int32_t a, double D, double G, double L, double e_total) {
  const peri_particles *p = &s->disc.p;
  const peri_material *mat = &s->mat.materials[p->material[a]];
  const double m = p->wvol[a], alpha = mat->alpha_m / m, omega = peri_bonds_omega(&s->disc.bonds, L);
  const double theta = p->theta[a];
  const double e = e_total - (s->state.thermal_strain ? s->state.thermal_strain[a] : 0.0) * L;
  return (mat->n_theta / m) * (mat->K_theta * theta - alpha * p->pstate[a] / 3.0) * D * omega * L +
         alpha * G * omega * (e - theta * L / 3.0);
}

double peri_position_aware_lps_pair(const peri_sim *s, int32_t i, int64_t k, double r) {
  const peri_bonds *b = &s->disc.bonds;
  const int32_t j = b->neighbor[k];
  const double L = peri_bond_length(s->disc.p.x, i, j);
  return pals_half(s, i, b->surface_D[k], b->surface_G[k], L, r - L) +
         pals_half(s, j, b->surface_D_rev[k], b->surface_G_rev[k], L, r - L);
}

double peri_position_aware_lps_own(const peri_sim *s, int32_t i, int64_t k, double r) {
  const peri_bonds *b = &s->disc.bonds;
  const double L = peri_bond_length(s->disc.p.x, i, b->neighbor[k]);
  return pals_half(s, i, b->surface_D[k], b->surface_G[k], L, r - L);
}

long peri_position_aware_lps_force(peri_sim *s, bool update_s0) {
  const long broken = peri_corrected_break(s, update_s0);
  pals_lps_sums(s);
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain;
  /* pals_half's node factors, once a node (owned and ghosts): the same numbers */
  double *node_c = peri_malloc(sizeof(double) * 2 * (size_t)(p->n > 0 ? p->n : 1)), *node_alpha = node_c + p->n;
#pragma omp parallel for schedule(static)
  for (int32_t a = 0; a < p->n; ++a) {
    const peri_material *mat = &s->mat.materials[p->material[a]];
    const double m = p->wvol[a], alpha = mat->alpha_m / m;
    node_alpha[a] = alpha;
    node_c[a] = (mat->n_theta / m) * (mat->K_theta * p->theta[a] - alpha * p->pstate[a] / 3.0);
  }
#pragma omp parallel
  {
    peri_bond_chunk *c = peri_malloc(sizeof *c);
    double g0[PERI_BOND_CHUNK], g1[PERI_BOND_CHUNK], g2[PERI_BOND_CHUNK];
#pragma omp for schedule(dynamic, 256)
    for (int32_t i = 0; i < p->n_owned; ++i) {
      double f[3] = {0.0, 0.0, 0.0};
      const double c_i = node_c[i], alpha_i = node_alpha[i], theta_i = p->theta[i], eth_i = eth ? eth[i] : 0.0;
      for (int64_t k0 = b->offset[i]; k0 < b->offset[i + 1]; k0 += PERI_BOND_CHUNK) {
        const int n = peri_bond_chunk_size(b, i, k0);
        peri_bond_chunk_fill(s, i, k0, n, c);
        const int32_t *restrict nbr = b->neighbor + k0;
        const double *restrict D = b->surface_D + k0, *restrict G = b->surface_G + k0,
                               *restrict D_rev = b->surface_D_rev + k0, *restrict G_rev = b->surface_G_rev + k0;
        /* t = pals_half(i) + pals_half(j) and the bond's force density t beta V_j y / r, bond by
         * bond in a vector loop; their sums in family order */
#pragma omp simd
        for (int a = 0; a < n; ++a) {
          const int32_t j = nbr[a];
          const double L = c->L[a], omega = c->omega[a], r = c->r[a], e_total = r - L;
          const double e_i = e_total - eth_i * L, e_j = e_total - (eth ? eth[j] : 0.0) * L;
          const double t =
              (c_i * D[a] * omega * L + alpha_i * G[a] * omega * (e_i - theta_i * L / 3.0)) +
              (node_c[j] * D_rev[a] * omega * L + node_alpha[j] * G_rev[a] * omega * (e_j - p->theta[j] * L / 3.0));
          const double bV = c->beta[a] * p->volume[j];
          g0[a] = t * bV * c->y0[a] / r, g1[a] = t * bV * c->y1[a] / r, g2[a] = t * bV * c->y2[a] / r;
        }
        for (int a = 0; a < n; ++a) {
          if (b->broken[k0 + a] || !(c->r[a] > 0.0)) continue;
          f[0] += g0[a], f[1] += g1[a], f[2] += g2[a];
        }
      }
      for (int d = 0; d < 3; ++d) p->f[3 * (size_t)i + d] = f[d];
    }
    free(c);
  }
  free(node_c);
  return broken;
}

/* The energy's dilatation and P_i: the deviatoric sum is the corrected LPS energy's
 * (surface_correction.c) with this correction's factors. */
void peri_position_aware_lps_dilatation(peri_sim *s) { pals_lps_sums(s); }
