/* The partial-stress force L0 = div nu0 (docs/model_reference.md 15.3, docs/variable_horizon.md).
 * nu0_i = sum_j T_i<xi_ij> (x) xi_ij V_j is the stress that node i's own force state carries;
 * under u = a + Hx with T_delta = delta^-(d+1) Z<xi/delta> it does not depend on delta
 * (Silling, Littlewood and Seleson 2013, "Partial stress field"), so its divergence passes
 * the patch test where the full peridynamic force, which reads T at both ends of a bond,
 * does not. The divergence is the least-squares gradient over the nearest neighbours: for
 * node i, grad g = A^-1 sum_j (g_j - g_i) xi_ij with A = sum_j xi_ij xi_ij^T, exact for a
 * linear g, with the weights w_ij = V_j d t_i / d e_ij of node i's own bonds over its horizon.
 * (The central difference of the source, and the nearest-neighbour least-squares gradient,
 * make the product of two odd difference operators whose symbol changes sign: modes with
 * k dx near 1 then have a negative stiffness and an explicit pulse run diverges. With the
 * bond weights the divergence is, in a uniform region, the adjoint of u -> nu0 up to a positive
 * factor, so the product is negative semi-definite.) Its null space, and the transition where
 * the operator is not symmetric, need one more term: the zero-energy mode control, the
 * energy kappa/2 sum_i k_i sum_j w_ij |z_ij|^2,  z_ij = u_j - u_i - (F xi + xi^T Q xi / 2),
 * where F and Q are the weighted least-squares fit of u_j - u_i over i's bonds. Its force is
 * kappa k_i sum_j w_ij z_ij on i and the reaction -kappa k_i w_ij z_ij on each j (the fit's
 * residual is a projector symmetric in the weights): a symmetric, positive semi-definite
 * stiffness, without which the 2D/3D operator keeps complex eigenvalue pairs whatever kappa.
 * z vanishes for every quadratic field, so the control changes neither the patch test nor
 * the long-wave modulus (the force of a field with k delta small changes at order
 * (k delta)^4), and gives every other mode, the checkerboard included, a positive stiffness.
 * On a lattice nu0 is D_i : eps with D_i the node's discrete (anisotropic) elasticity, so each
 * peridynamic stencil node's nu0 is mapped onto the isotropic C_iso (lattice_correction below). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/horizon_field.h"
#include "bond_kernel.h"
#include "partial_stress.h"
#include "peri/small_matrix.h"

/* Inverse of the leading dim x dim block of a (3x3 row-major); false when singular
 * relative to the block's scale. */
static bool invert_block(const double a[9], int dim, double inv[9]) {
  double scale = 0.0;
  for (int k = 0; k < 9; ++k) scale = fmax(scale, fabs(a[k]));
  return peri_invert_block3(a, dim, 1e-12 * pow(scale, dim), inv);
}

/* The weight of bond i-j in node i's gradient: V_j times the bond stiffness of i's force state,
 * d t_i / d e (PMB omega beta_i / |xi|, LPS omega beta_i), so that in a uniform region the
 * divergence is the adjoint of the map u -> nu0 and their product is negative semi-definite. */
/* The fit's basis at xi / delta: its d linear terms, then xi_a xi_b / 2 for a <= b. */
static int fit_basis(int dim, const double xi[3], double delta, double phi[PERI_FIT_BASIS]) {
  double y[3] = {xi[0] / delta, xi[1] / delta, xi[2] / delta};
  int n = 0;
  for (int a = 0; a < dim; ++a) phi[n++] = y[a];
  for (int a = 0; a < dim; ++a)
    for (int b = a; b < dim; ++b) phi[n++] = (a == b ? 0.5 : 1.0) * y[a] * y[b];
  return n;
}

/* In-place inverse of the n x n matrix m (row-major, n <= PERI_FIT_BASIS) by Gauss-Jordan with
 * partial pivoting; false when a pivot falls below 1e-12 of the matrix's largest entry. */
static bool invert_small(double *m, int n) {
  double inv[PERI_FIT_BASIS * PERI_FIT_BASIS] = {0}, scale = 0.0;
  for (int k = 0; k < n * n; ++k) scale = fmax(scale, fabs(m[k]));
  for (int k = 0; k < n; ++k) inv[k * n + k] = 1.0;
  for (int c = 0; c < n; ++c) {
    int pivot = c;
    for (int r = c + 1; r < n; ++r)
      if (fabs(m[r * n + c]) > fabs(m[pivot * n + c])) pivot = r;
    if (!(fabs(m[pivot * n + c]) > 1e-12 * scale)) return false;
    for (int k = 0; k < n; ++k) {
      double t = m[c * n + k];
      m[c * n + k] = m[pivot * n + k], m[pivot * n + k] = t;
      t = inv[c * n + k];
      inv[c * n + k] = inv[pivot * n + k], inv[pivot * n + k] = t;
    }
    const double d = m[c * n + c];
    for (int k = 0; k < n; ++k) m[c * n + k] /= d, inv[c * n + k] /= d;
    for (int r = 0; r < n; ++r) {
      if (r == c) continue;
      const double factor = m[r * n + c];
      for (int k = 0; k < n; ++k) m[r * n + k] -= factor * m[c * n + k], inv[r * n + k] -= factor * inv[c * n + k];
    }
  }
  memcpy(m, inv, sizeof(double) * (size_t)(n * n));
  return true;
}

static double gradient_weight(const peri_sim *s, int32_t i, int32_t j, double r0) {
  const peri_family_params *f = &s->disc.bonds.family;
  const double delta = s->disc.horizon_field->delta[i];
  const double w = peri_partial_volume_factor(f->rule, r0, delta, f->spacing) * peri_influence_value(f->influence, r0, delta);
  return w * s->disc.p.volume[j] / (s->mat.model->fixed_poisson ? r0 : 1.0);
}

/* The local nodes whose force is variational: those that no peridynamic coupled node's stencil
 * reaches. Their force is -dU/du of the local energy U = sum_i V_i sigma_i : G_i / 2, which holds
 * the traction condition at a free or loaded surface in the weak sense (the collocated divergence
 * has none: a uniform stretch of a free local end costs no force, and a reaction at a held local
 * end vanishes under a uniform stress). In a uniform interior the two forces are equal (the
 * stencil is odd: w_ij = -w_ji and sum_k w_jk = 0), and every stencil that reaches such a node is
 * a local one, so the patch test holds; a local node that a peridynamic stencil reaches keeps the
 * divergence, which the peridynamic nodes' nu0 enter. */
static void mark_variational(peri_horizon_field *h, const peri_particles *p) {
  free(h->variational);
  h->variational = NULL;
  if (!h->local) return;
  h->variational = peri_calloc((size_t)(p->n > 0 ? p->n : 1), 1);
  for (int32_t i = 0; i < p->n_owned; ++i) h->variational[i] = h->local[i];
  for (int32_t i = 0; i < p->n_owned; ++i)
    if (h->coupled[i] && !h->local[i])
      for (int64_t t = h->stencil_offset[i]; t < h->stencil_offset[i + 1]; ++t) h->variational[h->stencil_node[t]] = 0;
}

/* The isotropic moduli of the material's own E and nu (for PMB its fixed Poisson ratio), the
 * delta -> 0 limit of nu0 (Silling, Littlewood and Seleson 2013, "Local-nonlocal coupling
 * idea"): plane stress lambda' = E nu / (1 - nu^2); plane strain and 3D lambda = E nu / ((1 + nu)(1 - 2 nu));
 * mu = E / (2 (1 + nu)). (1D: sigma = E eps.) */
static void isotropic_moduli(const peri_sim *s, int32_t i, double *lambda, double *mu) {
  const peri_material *mat = &s->mat.materials[s->disc.p.material[i]];
  const double E = mat->E, nu = mat->nu;
  *mu = E / (2.0 * (1.0 + nu));
  *lambda = s->disc.p.dim == 2 && s->disc.geom.plane == PERI_PLANE_STRESS ? E * nu / (1.0 - nu * nu)
                                                                          : E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
}

/* Voigt order of the symmetric tensors: 1D xx; 2D xx yy xy; 3D xx yy zz yz xz xy. */
static const int voigt_row[3][6] = {{0}, {0, 1, 0}, {0, 1, 2, 1, 0, 0}};
static const int voigt_col[3][6] = {{0}, {0, 1, 1}, {0, 1, 2, 2, 2, 1}};
static int voigt_size(int dim) { return dim == 1 ? 1 : dim == 2 ? 3 : 6; }

/* C_iso in Voigt form (stress from the engineering strain), the elasticity of the local nodes. */
static void isotropic_voigt(const peri_sim *s, int32_t i, double C[36]) {
  const int dim = s->disc.p.dim, n = voigt_size(dim);
  memset(C, 0, 36 * sizeof(double));
  if (dim == 1) {
    C[0] = s->mat.materials[s->disc.p.material[i]].E;
    return;
  }
  double lambda, mu;
  isotropic_moduli(s, i, &lambda, &mu);
  for (int r = 0; r < dim; ++r)
    for (int c = 0; c < dim; ++c) C[n * r + c] = lambda + (r == c ? 2.0 * mu : 0.0);
  for (int r = dim; r < n; ++r) C[n * r + r] = mu;
}

/* nu0_i = sum_j t_i<xi> (y_j - y_i)/|y_j - y_i| (x) xi V_j over the intact bonds, from h->state */
static void node_partial_stress(const peri_sim *s, int32_t i, double nu[9]) {
  const peri_horizon_field *h = s->disc.horizon_field;
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  memset(nu, 0, 9 * sizeof(double));
  for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
    if (b->broken[k]) continue;
    const int32_t j = b->neighbor[k];
    double xi[3], dy[3];
    peri_bond_xi(p->x, i, j, xi);
    const double r = peri_deformed_bond(p->x, p->u, i, j, dy);
    if (!(r > 0.0)) continue;
    const double g = h->state[k] * p->volume[j] / r;
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) nu[3 * a + c] += g * dy[a] * xi[c];
  }
}

/* True when the symmetric part of the n x n matrix m is positive definite (Cholesky). */
static bool positive_definite(const double *m, int n) {
  double l[36] = {0};
  for (int r = 0; r < n; ++r)
    for (int c = 0; c <= r; ++c) {
      double sum = 0.5 * (m[n * r + c] + m[n * c + r]);
      for (int k = 0; k < c; ++k) sum -= l[n * r + k] * l[n * c + k];
      if (r == c) {
        if (!(sum > 0.0)) return false;
        l[n * r + r] = sqrt(sum);
      } else {
        l[n * r + c] = sum / l[n * c + c];
      }
    }
  return true;
}

/* The lattice correction (docs/variable_horizon.md "The lattice correction"). Under u = a + Hx a
 * peridynamic node's nu0 is D_i : eps to first order, with D_i the elasticity of its own discrete
 * family: on a square or cubic lattice its fourth moment is not isotropic and depends on
 * delta_i / dx (the shear stiffness of a full PMB family is 0.927, 0.951, 0.988, 0.995 of the
 * isotropic one at delta = 2, 3, 4, 5 dx), and at a free surface the family is truncated, so
 * nu0 differs from node to node under a shear and the divergence leaves a force. Each
 * peridynamic node of a stencil therefore takes nu0 <- nu0 + (C_iso D_i^-1 - I) : sym nu0, which
 * makes nu0 = C_iso : eps on every node, whatever its horizon, under any H (the local nodes'
 * sigma already is). D_i is probed at set-up through the run's own state computation: its
 * columns are the symmetric part of nu0 under the unit strains, by the fourth-order central
 * difference (8 (nu(e) - nu(-e)) - (nu(2e) - nu(-2e))) / 12e at e = PERI_LATTICE_PROBE_STRAIN,
 * whose truncation (order e^4) and rounding (eps |x| / (e |xi|)) are far below the patch test's
 * 1e-10, on the bonds as built (a precrack or a broken bond is damage, which the correction
 * must not undo; it is not refreshed when bonds break). A node whose D_i is not at least
 * PERI_LATTICE_MIN_STIFFNESS times C_iso (D_i - tau C_iso not positive definite) keeps its nu0
 * and is counted: its correction would amplify nu0 by more than 1 / tau. */
static int lattice_correction(peri_sim *s, void (*compute_states)(peri_sim *)) {
  peri_horizon_field *h = s->disc.horizon_field;
  peri_particles *p = &s->disc.p;
  peri_bonds *b = &s->disc.bonds;
  const int dim = p->dim, nv = voigt_size(dim);
  free(h->lattice_index), free(h->lattice_correction);
  h->lattice_index = peri_malloc(sizeof(int32_t) * (size_t)(p->n > 0 ? p->n : 1));
  int32_t rows = 0;
  for (int32_t i = 0; i < p->n; ++i)
    h->lattice_index[i] = i < p->n_owned && h->needs_stress[i] && !(h->local && h->local[i]) ? rows++ : -1;
  const size_t block = (size_t)nv * (size_t)nv, n3 = 3 * (size_t)(p->n > 0 ? p->n : 1);
  double *D = peri_calloc(block * (size_t)(rows > 0 ? rows : 1), sizeof(double));
  double *u_saved = peri_malloc(n3 * sizeof(double));
  uint8_t *broken_saved = peri_malloc((size_t)(b->n_bonds > 0 ? b->n_bonds : 1));
  memcpy(u_saved, p->u, n3 * sizeof(double));
  memcpy(broken_saved, b->broken, (size_t)b->n_bonds);
  memset(b->broken, 0, (size_t)b->n_bonds);
  static const double factor[4] = {1.0, -1.0, 2.0, -2.0}, weight[4] = {8.0, -8.0, -1.0, 1.0};
  const double e = PERI_LATTICE_PROBE_STRAIN;
  for (int k = 0; k < nv; ++k) {
    const int ka = voigt_row[dim - 1][k], kb = voigt_col[dim - 1][k];
    for (int q = 0; q < 4; ++q) {
      /* u = e_q E_k x, E_k the unit engineering strain k (shear: 1/2 in each of ab and ba) */
      const double amount = factor[q] * e * (ka == kb ? 1.0 : 0.5);
      memset(p->u, 0, n3 * sizeof(double));
      for (int32_t j = 0; j < p->n; ++j) {
        p->u[3 * (size_t)j + ka] += amount * p->x[3 * (size_t)j + kb];
        if (ka != kb) p->u[3 * (size_t)j + kb] += amount * p->x[3 * (size_t)j + ka];
      }
      compute_states(s);
#pragma omp parallel for schedule(dynamic, 64)
      for (int32_t i = 0; i < p->n_owned; ++i) {
        if (h->lattice_index[i] < 0) continue;
        double nu[9];
        node_partial_stress(s, i, nu);
        double *column = D + block * (size_t)h->lattice_index[i];
        for (int r = 0; r < nv; ++r) {
          const int a = voigt_row[dim - 1][r], c = voigt_col[dim - 1][r];
          column[nv * r + k] += weight[q] * 0.5 * (nu[3 * a + c] + nu[3 * c + a]) / (12.0 * e);
        }
      }
    }
  }
  memcpy(p->u, u_saved, n3 * sizeof(double));
  memcpy(b->broken, broken_saved, (size_t)b->n_bonds);
  compute_states(s); /* those of the restored displacement */
  free(u_saved), free(broken_saved);
  /* R_i = C_iso D_i^-1 */
  h->lattice_correction = peri_malloc(block * sizeof(double) * (size_t)(rows > 0 ? rows : 1));
  int32_t weak = 0, first_weak = -1;
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (h->lattice_index[i] < 0) continue;
    double *Di = D + block * (size_t)h->lattice_index[i], C[36], shifted[36];
    isotropic_voigt(s, i, C);
    for (size_t t = 0; t < block; ++t) shifted[t] = Di[t] - PERI_LATTICE_MIN_STIFFNESS * C[t];
    if (!positive_definite(shifted, nv) || !invert_small(Di, nv)) {
      if (first_weak < 0) first_weak = i;
      weak++;
      h->lattice_index[i] = -1;
      continue;
    }
    double *R = h->lattice_correction + block * (size_t)(h->lattice_index[i]);
    for (int r = 0; r < nv; ++r)
      for (int c = 0; c < nv; ++c) {
        double sum = 0.0;
        for (int t = 0; t < nv; ++t) sum += C[nv * r + t] * Di[nv * t + c];
        R[nv * r + c] = sum;
      }
  }
  free(D);
  if (weak > 0) {
    const double *x = p->x + 3 * (size_t)first_weak;
    peri_warning("partial stress: %d nodes (first at (%g, %g, %g)) have a discrete elasticity below %g of the "
                 "isotropic one in some strain (a family cut by free surfaces); they keep their own partial stress "
                 "without the lattice correction (docs/variable_horizon.md)",
                 (int)weak, x[0], x[1], x[2], PERI_LATTICE_MIN_STIFFNESS);
  }
  return PERI_OK;
}

/* nu0 <- nu0 + (R_i - I) : sym nu0 (lattice_correction) */
static void correct_lattice(const peri_horizon_field *h, int dim, int32_t i, double nu[9]) {
  const int32_t row = h->lattice_index[i];
  if (row < 0) return;
  const int nv = voigt_size(dim);
  const double *R = h->lattice_correction + (size_t)nv * (size_t)nv * (size_t)row;
  double v[6];
  for (int r = 0; r < nv; ++r) {
    const int a = voigt_row[dim - 1][r], c = voigt_col[dim - 1][r];
    v[r] = 0.5 * (nu[3 * a + c] + nu[3 * c + a]);
  }
  for (int r = 0; r < nv; ++r) {
    double change = -v[r];
    for (int q = 0; q < nv; ++q) change += R[nv * r + q] * v[q];
    const int a = voigt_row[dim - 1][r], c = voigt_col[dim - 1][r];
    nu[3 * a + c] += change;
    if (a != c) nu[3 * c + a] += change;
  }
}

int peri_partial_stress_prepare(peri_sim *s, void (*compute_states)(peri_sim *s)) {
  peri_horizon_field *h = s->disc.horizon_field;
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int dim = p->dim;
  free(h->stencil_offset), free(h->stencil_node), free(h->stencil_weight), free(h->needs_stress);
  h->stencil_offset = peri_calloc((size_t)p->n_owned + 1, sizeof(int64_t));
  h->needs_stress = peri_calloc((size_t)(p->n > 0 ? p->n : 1), 1);
  for (int32_t i = 0; i < p->n_owned; ++i) {
    int64_t count = 0;
    if (h->coupled[i])
      for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k)
        count += gradient_weight(s, i, b->neighbor[k], peri_bond_length(p->x, i, b->neighbor[k])) > 0.0;
    h->stencil_offset[i + 1] = h->stencil_offset[i] + count;
  }
  const int64_t total = h->stencil_offset[p->n_owned];
  h->stencil_node = peri_malloc(sizeof(int32_t) * (size_t)(total > 0 ? total : 1));
  h->stencil_weight = peri_malloc(3 * sizeof(double) * (size_t)(total > 0 ? total : 1));
  free(h->stencil_bond), free(h->stencil_fit), free(h->stiffness);
  h->stencil_bond = peri_malloc(sizeof(double) * (size_t)(total > 0 ? total : 1));
  h->stencil_fit = peri_calloc(PERI_FIT_BASIS * (size_t)(total > 0 ? total : 1), sizeof(double));
  h->stiffness = peri_calloc((size_t)(p->n > 0 ? p->n : 1), sizeof(double));
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (!h->coupled[i]) continue;
    const peri_material *mat = &s->mat.materials[p->material[i]];
    h->stiffness[i] = s->mat.model->fixed_poisson ? h->node_constant[i] : mat->alpha_m / h->node_constant[i];
    h->needs_stress[i] = 1;
    int64_t e = h->stencil_offset[i];
    double a[9] = {0};
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      double xi[3];
      const double w = gradient_weight(s, i, j, peri_bond_xi(p->x, i, j, xi));
      if (!(w > 0.0)) continue;
      h->stencil_node[e] = j;
      h->stencil_bond[e] = w;
      for (int r = 0; r < 3; ++r) h->stencil_weight[3 * e + r] = w * xi[r];
      ++e;
      h->needs_stress[j] = 1;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) a[3 * r + c] += w * xi[r] * xi[c];
    }
    double inv[9];
    if (!invert_block(a, dim, inv)) {
      const double *x = p->x + 3 * (size_t)i;
      peri_error("partial stress: the bonds of the node at (%g, %g, %g) do not span %d dimensions, so it has no "
                 "gradient; keep the coupling region away from isolated nodes", x[0], x[1], x[2], dim);
      return PERI_ERR_INPUT;
    }
    /* the quadratic fit: rows w_j M^-1 phi_j with M = sum_j w_j phi_j phi_j^T */
    double fit[PERI_FIT_BASIS * PERI_FIT_BASIS] = {0}, phi[PERI_FIT_BASIS];
    int nb = 0;
    for (int64_t t = h->stencil_offset[i]; t < e; ++t) {
      double xi[3];
      peri_bond_xi(p->x, i, h->stencil_node[t], xi);
      nb = fit_basis(dim, xi, h->delta[i], phi);
      for (int r = 0; r < nb; ++r)
        for (int c = 0; c < nb; ++c) fit[r * nb + c] += h->stencil_bond[t] * phi[r] * phi[c];
    }
    if (!invert_small(fit, nb)) {
      const double *x = p->x + 3 * (size_t)i;
      peri_error("partial stress: the bonds of the node at (%g, %g, %g) do not determine a quadratic fit (too few "
                 "neighbours in its horizon); keep the coupling region away from isolated nodes", x[0], x[1], x[2]);
      return PERI_ERR_INPUT;
    }
    for (int64_t t = h->stencil_offset[i]; t < e; ++t) {
      double xi[3];
      peri_bond_xi(p->x, i, h->stencil_node[t], xi);
      fit_basis(dim, xi, h->delta[i], phi);
      for (int r = 0; r < nb; ++r) {
        double row = 0.0;
        for (int c = 0; c < nb; ++c) row += fit[r * nb + c] * phi[c];
        h->stencil_fit[PERI_FIT_BASIS * t + r] = h->stencil_bond[t] * row;
      }
    }
    for (int64_t t = h->stencil_offset[i]; t < e; ++t) {
      const double wx[3] = {h->stencil_weight[3 * t], h->stencil_weight[3 * t + 1], h->stencil_weight[3 * t + 2]};
      for (int r = 0; r < 3; ++r) h->stencil_weight[3 * t + r] = inv[3 * r] * wx[0] + inv[3 * r + 1] * wx[1] + inv[3 * r + 2] * wx[2];
    }
  }
  mark_variational(h, p);
  free(h->partial_stress);
  h->partial_stress = peri_calloc(9 * (size_t)(p->n > 0 ? p->n : 1), sizeof(double));
  /* each node's stencil entries, for a sum of their reactions in one order (a sum by atomic
   * additions took the threads' order: results changed with their number at round-off) */
  free(h->entry_reaction), free(h->target_offset), free(h->target_entry);
  h->entry_reaction = peri_calloc(3 * (size_t)(total > 0 ? total : 1), sizeof(double));
  h->target_offset = peri_calloc((size_t)p->n + 1, sizeof(int64_t));
  h->target_entry = peri_malloc(sizeof(int64_t) * (size_t)(total > 0 ? total : 1));
  for (int64_t t = 0; t < total; ++t) ++h->target_offset[h->stencil_node[t] + 1];
  for (int32_t j = 0; j < p->n; ++j) h->target_offset[j + 1] += h->target_offset[j];
  int64_t *next = peri_malloc(sizeof(int64_t) * (size_t)(p->n > 0 ? p->n : 1));
  memcpy(next, h->target_offset, sizeof(int64_t) * (size_t)p->n);
  for (int64_t t = 0; t < total; ++t) h->target_entry[next[h->stencil_node[t]]++] = t;
  free(next);
  return lattice_correction(s, compute_states);
}

/* The displacement gradient G_ac = d u_a / d x_c of a coupled node from its least-squares stencil. */
static void displacement_gradient(const peri_sim *s, int32_t i, double G[9]) {
  const peri_horizon_field *h = s->disc.horizon_field;
  const double *u = s->disc.p.u, *ui = u + 3 * (size_t)i;
  memset(G, 0, 9 * sizeof(double));
  for (int64_t t = h->stencil_offset[i]; t < h->stencil_offset[i + 1]; ++t) {
    const double *uj = u + 3 * (size_t)h->stencil_node[t], *w = h->stencil_weight + 3 * t;
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) G[3 * a + c] += (uj[a] - ui[a]) * w[c];
  }
}

/* The Cauchy stress of the small strain eps = sym G with the material's isotropic moduli (above). */
static void cauchy_stress(const peri_sim *s, int32_t i, const double G[9], double sigma[9]) {
  const int dim = s->disc.p.dim;
  memset(sigma, 0, 9 * sizeof(double));
  if (dim == 1) {
    sigma[0] = s->mat.materials[s->disc.p.material[i]].E * G[0];
    return;
  }
  double lambda, mu, trace = 0.0;
  isotropic_moduli(s, i, &lambda, &mu);
  for (int a = 0; a < dim; ++a) trace += G[4 * a];
  for (int a = 0; a < dim; ++a)
    for (int c = 0; c < dim; ++c) sigma[3 * a + c] = mu * (G[3 * a + c] + G[3 * c + a]) + (a == c ? lambda * trace : 0.0);
}

double peri_partial_stress_local_energy(const peri_sim *s, int32_t i) {
  double G[9], sigma[9], W = 0.0;
  displacement_gradient(s, i, G);
  cauchy_stress(s, i, G, sigma);
  for (int k = 0; k < 9; ++k) W += 0.5 * sigma[k] * G[k]; /* sigma symmetric: sigma : G = sigma : eps */
  return W;
}

void peri_partial_stress_force(peri_sim *s) {
  peri_horizon_field *h = s->disc.horizon_field;
  peri_particles *p = &s->disc.p;
  double *nu = h->partial_stress, *entry_reaction = h->entry_reaction;
  /* nu0_i of every node of a stencil, with the lattice correction */
#pragma omp parallel for schedule(dynamic, 64)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (!h->needs_stress[i]) continue;
    if (h->local && h->local[i]) { /* the delta -> 0 limit: the Cauchy stress of the local strain */
      double G[9];
      displacement_gradient(s, i, G);
      cauchy_stress(s, i, G, nu + 9 * (size_t)i);
      continue;
    }
    node_partial_stress(s, i, nu + 9 * (size_t)i);
    correct_lattice(h, p->dim, i, nu + 9 * (size_t)i);
  }
  /* f_a = sum_b d nu_ab / d x_b */
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (!h->coupled[i]) continue;
    double f[3] = {0, 0, 0};
    const double *nu_i = nu + 9 * (size_t)i;
    const bool variational = h->variational && h->variational[i];
    for (int64_t t = h->stencil_offset[i]; t < h->stencil_offset[i + 1]; ++t) {
      const int32_t j = h->stencil_node[t];
      const double *nu_j = nu + 9 * (size_t)j, *w = h->stencil_weight + 3 * t;
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) f[a] += (variational ? nu_i[3 * a + c] : nu_j[3 * a + c] - nu_i[3 * a + c]) * w[c];
      for (int a = 0; a < 3; ++a) entry_reaction[3 * t + a] = 0.0;
      if (h->variational && h->local[i] && h->variational[j]) { /* -V_i sigma_i . dG_i/du_j / V_j on a variational node j */
        const double ratio = p->volume[i] / p->volume[j];
        for (int a = 0; a < 3; ++a) {
          double share = 0.0;
          for (int c = 0; c < 3; ++c) share += nu_i[3 * a + c] * w[c];
          entry_reaction[3 * t + a] = ratio * share;
        }
      }
    }
    /* zero-energy mode control: the part of u_j - u_i that the quadratic fit leaves */
    double coef[PERI_FIT_BASIS][3] = {{0}}, phi[PERI_FIT_BASIS];
    const double *ui = p->u + 3 * (size_t)i;
    int nb = 0;
    for (int64_t t = h->stencil_offset[i]; t < h->stencil_offset[i + 1]; ++t) {
      const double *uj = p->u + 3 * (size_t)h->stencil_node[t], *q = h->stencil_fit + PERI_FIT_BASIS * t;
      for (int l = 0; l < PERI_FIT_BASIS; ++l)
        for (int a = 0; a < 3; ++a) coef[l][a] += q[l] * (uj[a] - ui[a]);
    }
    const double kappa = h->stabilization * h->stiffness[i];
    double control[3] = {0, 0, 0};
    for (int64_t t = h->stencil_offset[i]; t < h->stencil_offset[i + 1]; ++t) {
      const int32_t j = h->stencil_node[t];
      double xi[3];
      peri_bond_xi(p->x, i, j, xi);
      nb = fit_basis(p->dim, xi, h->delta[i], phi);
      for (int a = 0; a < 3; ++a) {
        double z = p->u[3 * (size_t)j + a] - ui[a];
        for (int l = 0; l < nb; ++l) z -= phi[l] * coef[l][a];
        control[a] += h->stencil_bond[t] * z;
        entry_reaction[3 * t + a] += kappa * h->stencil_bond[t] * z;
      }
    }
    for (int a = 0; a < 3; ++a) p->f[3 * (size_t)i + a] = f[a] + kappa * control[a];
  }
  /* the reactions, added once every coupled node has its force: each node's in its entries'
   * order */
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i)
    for (int a = 0; a < 3; ++a) {
      double reaction = 0.0;
      for (int64_t e = h->target_offset[i]; e < h->target_offset[i + 1]; ++e)
        reaction -= entry_reaction[3 * h->target_entry[e] + a];
      p->f[3 * (size_t)i + a] += reaction;
    }
}
