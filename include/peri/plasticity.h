/* Sublayer plasticity (docs/plasticity.md; model reference section 16, Ebrahimi 2020 ch. 5):
 * a bond is n elastic-perfectly-plastic sublayers in parallel, sublayer k of weight W_k and
 * yield stretch s_yk, all at the bond's stretch. Each bond stores the plastic stretch of each
 * of its sublayers; the force is the elastic one evaluated at the elastic stretch
 *   s^e = s - sum_k W_k s^p_k.
 * The sublayers come from (W_k, s_yk) or from a uniaxial stress-strain curve (a power law or
 * a table of points) by the construction of section 16.1. */
#ifndef PERI_PLASTICITY_H
#define PERI_PLASTICITY_H
#include <stdbool.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>

#define PERI_MAX_SUBLAYERS 16

typedef struct peri_sublayers {
  int n;
  double weight[PERI_MAX_SUBLAYERS]; /* W_k, sum 1 */
  double yield[PERI_MAX_SUBLAYERS];  /* s_yk, increasing */
  /* ductile failure: the bond breaks when |sum_k W_k s^p_k| exceeds it (INFINITY: never) */
  double critical_plastic_stretch;
  /* energy failure: the bond breaks when its work w = c omega |xi| sum_k W_k phi_k reaches it
   * (J/m^6; INFINITY: never; docs/plasticity.md section 2, critical bond energy) */
  double critical_bond_work;
  /* Cowper-Symonds rate dependence (model reference 16.3): the yield stretches scale by
   * 1 + (|ds/dt| / rate_d)^(1 / rate_p) with the bond's stretch rate; rate_d = 0: none */
  double rate_d, rate_p;
  /* the yield rule (docs/plasticity.md section 8): false, every bond's sublayers yield on its
   * own stretch (yield[] are stretches); true, the deviatoric state-based rule of LPS in 3D,
   * where sublayer k of a node yields on the deviatoric energy of its whole family (von
   * Mises) and yield[] are the uniaxial deviatoric yield strains e_yk of the deviatoric curve */
  bool deviatoric;
  /* with deviatoric: the tensor rule (docs/plasticity.md section 10), the plastic deviatoric
   * stretches of a node's bonds written through one tensor per sublayer */
  bool tensor;
} peri_sublayers;

/* The bond work at which a bond breaks for the fracture energy G0, when every bond crossing a
 * unit crack area has the same work (the Silling-Askari integral with w in place of
 * c s0^2 |xi| / 2): 3D 4 G0 / (pi delta^4), 2D 3 G0 / (2 h delta^3), 1D 2 G0 / (A delta^2),
 * h the thickness and A the cross-section. */
double peri_critical_bond_work(int dim, double G0, double delta, double thickness, double cross_section);
/* The work per unit c omega |xi| that a bond's sublayers have absorbed at stretch s:
 * sum_k W_k ((s - s^p_k)^2 / 2 + s_yk |s^p_k|), the stored energy and the dissipated work
 * (exact for a bond loaded monotonically; after reversals the dissipation is a lower bound). */
static inline double peri_sublayer_work(const peri_sublayers *sl, double s, const double *sp) {
  double w = 0.0;
  for (int k = 0; k < sl->n; ++k) w += sl->weight[k] * (0.5 * (s - sp[k]) * (s - sp[k]) + sl->yield[k] * fabs(sp[k]));
  return w;
}

/* The weights sum to 1 within this (docs/plasticity.md: the printed weights of Ebrahimi
 * Table 5.2 have 4 digits, whose sum is 1 within 1e-4). */
#define PERI_SUBLAYER_WEIGHT_TOLERANCE 1e-3

/* The sublayers of a piecewise-linear uniaxial curve through the origin and the n points
 * (strain[k], stress[k]) (model reference 16.1): s_yk = strain[k], e_1 = E, e_k the slope of
 * segment k, W_k = (e_k - e_{k+1})/E with e_{n+1} = 0. The first point must lie on the
 * elastic line (stress[0] = E strain[0] within 1e-3). Returns 0, or on bad input -1 with the
 * index of the offending point in *bad and a message in why: strains not increasing, a
 * negative slope, a slope that increases (a negative weight), too many points. */
int peri_sublayers_from_curve(double E, int n, const double *strain, const double *stress, peri_sublayers *out,
                              int *bad, char *why, size_t why_size);
/* The deviatoric curve of a uniaxial stress-strain curve (docs/plasticity.md section 8): under
 * uniaxial stress sigma the axial deviatoric strain is e = eps - sigma / (9K) and the axial
 * deviatoric stress 2 sigma / 3, whose ratio on the elastic line is 2 mu. The sublayers of the
 * deviatoric rule are peri_sublayers_from_curve(2 mu, ...) of these points: with the bulk
 * response elastic, the uniaxial tangent after j sublayers is 9 K G_t / (3 K + G_t),
 * G_t = mu sum_{k>j} W_k, and the bar passes every breakpoint of the uniaxial curve. */
void peri_deviatoric_curve(double K, int n, const double *strain, const double *stress, double *dev_strain,
                           double *dev_stress);
/* Breakpoint stresses of the power-law hardening curve sigma = sigma0 (eps/eps0)^exponent
 * (eps >= eps0; Ebrahimi eq. 5.7 as corrected in the model reference, section 20) at the
 * given strains. */
void peri_power_law_stresses(double sigma0, double eps0, double exponent, int n, const double *strain,
                             double *stress);
/* Breakpoint strains of the same law at the given stresses (sigma >= sigma0, exponent > 0):
 * eps = eps0 (sigma/sigma0)^(1/exponent). Ebrahimi Table 5.2's sublayers are the chords between
 * the points of 400, 450, 480 and 495 MPa, whose strains round to its printed breakpoints. */
void peri_power_law_strains(double sigma0, double eps0, double exponent, int n, const double *stress,
                            double *strain);
/* Sublayers fitted to a 2D or 3D family under uniaxial stress (src/model/sublayer_family_fit.c,
 * docs/plasticity.md section 4): bonds at direction cosine c stretch eps (c^2 - nu (1 - c^2)),
 * nu the bar's Poisson ratio; the weights of up to PERI_MAX_SUBLAYERS sublayers on a fixed
 * ladder of yield stretches are the non-negative least-squares fit of the direction-averaged
 * response to the piecewise-linear curve (breakpoints and samples along it), sum W = 1. */
void peri_sublayers_fit_family(int dim, double nu, double E, int n, const double *strain, const double *stress,
                               peri_sublayers *out);
/* The uniaxial stress over E of a continuum 2D or 3D family of these sublayers loaded
 * monotonically from the virgin state to the bar strain eps (the fit's model). */
double peri_sublayers_family_stress(int dim, double nu, const peri_sublayers *sl, double eps);
/* Checks given sublayers: weights positive and summing to 1 within
 * PERI_SUBLAYER_WEIGHT_TOLERANCE, yield stretches positive and increasing. Returns 0, or -1
 * with the offending index in *bad (-1 for the sum) and a message. */
int peri_sublayers_check(const peri_sublayers *sl, int *bad, char *why, size_t why_size);

/* Stress of the bond curve at a monotonic uniaxial strain eps from the virgin state,
 * divided by E: sum_k W_k min(eps, s_yk). */
double peri_sublayers_monotonic(const peri_sublayers *sl, double eps);

/* Return mapping of one bond (model reference 16.2) at total mechanical stretch s: updates
 * the plastic stretches sp[0 .. n-1] of its sublayers and returns sum_k W_k sp_k, the
 * plastic part of the stretch (s^e = s - that). `scale` multiplies the yield stretches
 * (1 without rate dependence). Idempotent: a second call at the same s changes nothing. */
static inline double peri_sublayer_return(const peri_sublayers *sl, double scale, double s, double *sp) {
  double plastic = 0.0;
  for (int k = 0; k < sl->n; ++k) {
    const double sy = sl->yield[k] * scale, trial = s - sp[k];
    if (trial > sy) sp[k] = s - sy;
    else if (trial < -sy) sp[k] = s + sy;
    plastic += sl->weight[k] * sp[k];
  }
  return plastic;
}
/* The same from the committed plastic stretches base[] into sp[] (base unchanged; base may
 * be sp). */
static inline double peri_sublayer_return_from(const peri_sublayers *sl, double scale, double s, const double *base,
                                               double *sp) {
  double plastic = 0.0;
  for (int k = 0; k < sl->n; ++k) {
    const double sy = sl->yield[k] * scale, trial = s - base[k];
    sp[k] = trial > sy ? s - sy : trial < -sy ? s + sy : base[k];
    plastic += sl->weight[k] * sp[k];
  }
  return plastic;
}

/* Elastic energy of the sublayers of one bond per unit c omega |xi| beta V: sum_k W_k
 * (s - sp_k)^2 / 2. */
static inline double peri_sublayer_energy(const peri_sublayers *sl, double s, const double *sp) {
  double e = 0.0;
  for (int k = 0; k < sl->n; ++k) e += 0.5 * sl->weight[k] * (s - sp[k]) * (s - sp[k]);
  return e;
}

struct peri_sim;
/* Quasi-static solvers: the plastic state of the accepted load step becomes the one the next
 * iterations map from (nothing without plasticity or in dynamics). */
void peri_plastic_commit(struct peri_sim *s);
/* Bond k's plastic stretches, layer by layer, from `state` (s->state.plastic_stretch or
 * plastic_committed): a pointer to its plastic_layers values, which are copied to row[] (of
 * PERI_MAX_SUBLAYERS) where the deviatoric rule keeps them in slots. */
const double *peri_plastic_row(const struct peri_sim *s, const double *state, int64_t k, double *row);
/* Whether the first sublayer of each bond of node i's family has a nonzero plastic stretch, in
 * family order into yielded[] (the yield index's bonds; docs/plasticity.md section 3). */
void peri_plastic_first_layer_flags(const struct peri_sim *s, int32_t i, uint8_t *yielded);
/* The plastic state (and its committed copy) in bond rows, k L + l, for whoever writes it bond
 * by bond (a checkpoint being read); the deviatoric rule moves it back into its slots at its
 * next return. */
void peri_plastic_state_in_bond_order(struct peri_sim *s);
/* The plastic part of bond k's stretch (src/model/plastic_bonds.c). */
double peri_plastic_bond_stretch(const struct peri_sim *s, int32_t i, int64_t k);
/* The work density (J/m^3) the sublayers of node i's bonds have dissipated, into D[i] of the
 * owned nodes: sum_j k_ij beta V_j sum_l W_l s_yl |s^p_l,ij|, with k_ij s^2/2 the bond's
 * share of node i's elastic energy (PMB c omega |xi| / 2; LPS the deviatoric alpha omega
 * |xi|^2). Exact for a bond loaded monotonically (an elastic-perfectly-plastic sublayer has
 * dissipated s_y |s^p|), the deformation-theory work of the J-integral (docs/plasticity.md
 * section 5); a lower bound after reversals. 0 for elastic materials. Only the nodes with
 * wanted[i] != 0 (all when wanted is NULL); the others' D is 0. */
void peri_plastic_dissipation(const struct peri_sim *s, double *D, const uint8_t *wanted);

#endif
