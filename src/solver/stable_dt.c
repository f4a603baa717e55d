/* Stable time step estimate (docs/model_reference.md 13.2; Ongaro 2022 eqs. 1.105-1.108). */
#include <math.h>
#include "peri/coupling.h"
#include "peri/comm.h"
#include "peri/constants.h"
#include "peri/horizon_field.h"
#include "peri/solver.h"
#include "model/bond_kernel.h"

double peri_node_stiffness_bound(const peri_sim *s, int32_t i) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  /* bond-based models carry the influence function in the pair force; state-based ones
   * are bounded by the equivalent PMB micromodulus alone */
  const bool bond_based = s->mat.model->fixed_poisson;
  const peri_family_eval fam = peri_family_eval_of(b);
  const peri_influence influence = bond_based ? fam.influence : PERI_INFLUENCE_CONSTANT;
  const double ci = s->mat.materials[p->material[i]].c_stable;
  const double *restrict x = p->x, *restrict V = p->volume;
  const int32_t *restrict neighbor = b->neighbor;
  const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
  const int64_t k0 = b->offset[i], k1 = b->offset[i + 1];
  if (s->mat.n_materials > 1 || b->surface_G) { /* c per pair: a scalar loop */
    double stiffness = 0.0;
    for (int64_t k = k0; k < k1; ++k) {
      const int32_t j = neighbor[k];
      const double r0 = peri_bond_length(x, i, j);
      double c = 0.5 * (ci + s->mat.materials[p->material[j]].c_stable);
      if (b->surface_G) c *= peri_bond_surface_factor(b, k); /* the corrected bond's stiffness */
      stiffness += peri_eval_beta(&fam, r0) * V[j] * c * peri_eval_omega(&fam, influence, r0) / r0;
    }
    return stiffness;
  }
  double stiffness = 0.0;
#pragma omp simd reduction(+ : stiffness)
  for (int64_t k = k0; k < k1; ++k) {
    const int32_t j = neighbor[k];
    const double d0 = x[3 * j] - xi0, d1 = x[3 * j + 1] - xi1, d2 = x[3 * j + 2] - xi2;
    const double r0 = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
    stiffness += peri_eval_beta(&fam, r0) * V[j] * peri_eval_omega(&fam, influence, r0) / r0;
  }
  return ci * stiffness;
}

/* The partial stress's zero-energy mode control (src/model/partial_stress.c) adds to the nodes it
 * reaches a stiffness of kappa times their bond stiffness at most twice over (the largest
 * eigenvalue of the assembled operator, measured in 2D and 3D, is below (1 + 2 kappa) times
 * that of full peridynamics; docs/variable_horizon.md "Zero-energy mode control"). */
static double control_factor(const peri_sim *s, int32_t i) {
  const peri_horizon_field *h = s->disc.horizon_field;
  if (!h || h->n_coupled == 0 || !h->needs_stress || !h->needs_stress[i]) return 1.0;
  return peri_horizon_control_factor(h);
}

/* PD-FEM coupling (docs/coupling.md, "Explicit dynamics"): the rows of the coupled stiffness, in
 * force densities, are the rows of rho^-1 K times rho, so by Gershgorin's theorem the largest
 * eigenvalue w^2 of rho^-1 K is at most max_i R_i / rho_i with R_i node i's largest absolute row
 * sum, and velocity-Verlet is stable for dt < 2 / w. FEM rows bring their elements (a bar:
 * R = 4E/dx^2, dt = dx / c, the CFL step of the element), PD rows their bonds (R = 2 sum_j
 * lambda beta V_j: the bond bound above). */
typedef struct row_bound {
  const peri_sim *s;
  double dt; /* the smallest step of the rows so far (peri_coupling_rows adds one row at a time) */
} row_bound;

static void row_dt(void *ctx, int32_t i, int32_t count, const int32_t *cols, const double *blocks) {
  (void)cols;
  row_bound *rb = ctx;
  const int dim = rb->s->disc.geom.dim;
  double R = 0.0;
  for (int r = 0; r < dim; ++r) {
    double sum = 0.0;
    for (int32_t k = 0; k < count; ++k)
      for (int q = 0; q < dim; ++q) sum += fabs(blocks[9 * (size_t)k + 3 * r + q]);
    R = fmax(R, sum);
  }
  const double rho = rb->s->mat.materials[rb->s->disc.p.material[i]].density;
  if (R > 0.0) rb->dt = fmin(rb->dt, 2.0 * sqrt(rho / R));
}

static double coupled_stable_dt(const peri_sim *s) {
  row_bound rb = {s, INFINITY};
  /* a run that switches FEM nodes to PD: the step must hold after any switch (bonds that
   * break later only lower a PD row's sum) */
  if (s->solver.breaking && s->coupling->switch_radius > 0.0) peri_coupling_switchable_rows(s, row_dt, &rb);
  else peri_coupling_rows(s, row_dt, &rb);
  return rb.dt;
}

double peri_stable_dt(const peri_sim *s) {
  if (s->coupling) { /* on MPI ranks the rows of owned nodes: the minimum over the ranks (below) */
    const double dt = coupled_stable_dt(s);
    return s->par.dd ? peri_comm_min(dt) : dt;
  }
  const peri_particles *p = &s->disc.p;
  double dt_bond = INFINITY;
#pragma omp parallel for schedule(static) reduction(min : dt_bond)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *mi = &s->mat.materials[p->material[i]];
    const double stiffness = peri_node_stiffness_bound(s, i) * control_factor(s, i);
    if (stiffness > 0.0) dt_bond = fmin(dt_bond, sqrt(2.0 * mi->density / stiffness));
  }
  double dt_cfl = INFINITY;
  for (int m = 0; m < s->mat.n_materials; ++m) {
    const peri_material *mat = &s->mat.materials[m];
    double M = peri_pwave_modulus(&s->disc.geom, mat->E, mat->nu, mat->K, mat->mu);
    dt_cfl = fmin(dt_cfl, s->disc.geom.spacing / sqrt(M / mat->density));
  }
  /* On MPI ranks each rank sees only its owned nodes: the minimum over every rank is the
   * single-process value (each node's bound is computed from its family in the global order,
   * and a minimum is exact), and every rank must step with the same dt (a dynamic phase
   * decides its arrest from the step count: different counts leave ranks in different
   * collectives). Before the decomposition every rank holds the whole problem. */
  const double dt = fmin(dt_bond, dt_cfl);
  return s->par.dd ? peri_comm_min(dt) : dt;
}
