/* The tensor yield rule of LPS in 3D (docs/plasticity.md section 10,
 * src/model/tensor_plasticity.c): the deviatoric rule with the plastic deviatoric stretch of
 * every bond of a node's family written through one tensor per node and sublayer,
 *   s^dp_l,ij = n_ij . P_l,i . n_ij,   n_ij = xi / |xi|,
 * so that the state is 6 numbers per node and sublayer instead of one per bond and sublayer.
 * Sublayer l of node i yields on the deviatoric energy of the affine part of its family's
 * stretches: D_i, the symmetric tensor whose n . D . n fits s^d_ij = e_ij/|xi| - eth_i -
 * theta_i/3 in least squares with the weights omega beta V |xi|^2, gives
 *   S_l = (D_i - P_l) : K_i : (D_i - P_l),   K_i = sum_j omega beta V |xi|^2 d d^T,
 * with the bound and the radial return of the per-bond deviatoric rule. Under a homogeneous
 * deformation the two rules give the same numbers. */
#ifndef PERI_TENSOR_PLASTICITY_H
#define PERI_TENSOR_PLASTICITY_H
#include <stdbool.h>
#include <stdint.h>
#include "peri/sim.h"

/* A symmetric tensor as a vector: xx, yy, zz, xy, xz, yz. With d(n) = (n0^2, n1^2, n2^2, 2 n0
 * n1, 2 n0 n2, 2 n1 n2), n . T . n = d . T. */
#define PERI_TENSOR_COMPONENTS 6
/* A node's moments: K (the 21 entries of its upper triangle, row by row), K^-1 (the same) and
 * H = sum_j omega beta V |xi|^2 d (6), over its intact bonds. */
#define PERI_TENSOR_MOMENTS 48

typedef struct peri_tensor_plasticity {
  int layers;      /* L: the most sublayers of a plastic material */
  int32_t n_owned; /* the owned nodes of the arrays below; 0 until the first force evaluation */
  int32_t n_local; /* owned nodes and ghosts (the stride of term) */
  /* [L][6][n_owned]: component c of sublayer l's plastic tensor P_l of node i at
   * (l * 6 + c) * n_owned + i */
  double *state;
  double *committed; /* quasi-static solvers: the accepted load step's state; NULL in dynamics */
  /* [6][n_local]: alpha_i sum_l W_l P_l,i, the force pass's plastic tensor of node i
   * (component c at c * n_local + i; ghosts' from their owners) */
  double *term;
  double *moments;        /* [PERI_TENSOR_MOMENTS][n_owned] (a node whose K is singular: K^-1 0) */
  int32_t *moment_bonds;  /* [n_owned] the intact bonds the moments were summed over */
  uint64_t broken_edits;  /* the bonds' broken_edits when the moments were last checked */
  bool any_plastic;       /* some owned node or ghost has a nonzero term */
  bool quasi_static;      /* load steps map from `committed` */
} peri_tensor_plasticity;

/* Whether some material is plastic (either kind of state). */
static inline bool peri_has_plasticity(const peri_sim *s) {
  return s->state.plastic_stretch != NULL || s->state.plastic_tensor != NULL;
}
/* Whether the run's plastic materials take the tensor rule. */
bool peri_tensor_rule(const peri_sim *s);
/* The rule's record (its arrays come with the first force evaluation, after the split among
 * MPI ranks); PERI_OK. */
int peri_tensor_init(peri_sim *s);
/* The arrays for the owned nodes, the state zero and the moments from the intact bonds
 * (idempotent). */
void peri_tensor_ready(peri_sim *s);
/* Quasi-static load steps: the state of the accepted step becomes the one to map from. */
void peri_tensor_commit(peri_sim *s);
/* After the dilatation pass (theta and alpha = B of every owned node): the radial return of
 * every owned node's sublayers from N[c * n_owned + i] = sum_j w q x_a x_b / |xi|^2 (pass 1's
 * tensor sums, ab the component c; w = omega |xi| beta V, q = e - eth |xi|), then the terms
 * of the ghosts; bonds_broke: the pass broke bonds (the moments of the nodes that lost bonds
 * are rebuilt, as after any change of peri_bonds.broken_edits). */
void peri_tensor_return(peri_sim *s, const double *N, bool bonds_broke);
/* n . (A_i + A_j) . n of bond i -> j, A the nodes' terms alpha sum_l W_l P_l: the pair force
 * t_ij + t_ji loses omega |xi| times it. */
double peri_tensor_pair_term(const peri_sim *s, int32_t i, int32_t j);
/* The plastic tensors' part of the strain energy densities, added to W (the owned nodes'
 * elastic LPS energies at this displacement): with N and theta of pass 1's sums at this
 * displacement (as for peri_tensor_return), sum_j w (s^d - d . P)^2 = sum_j w (s^d)^2 - 2 P . M +
 * P . K P, so W_i gains (alpha_m / 2 m_i) sum_l W_l (P_l . K P_l - 2 P_l . M). */
void peri_tensor_energy(peri_sim *s, const double *N, const double *theta, double *W);
/* The yield index of each owned node: 1 when its first sublayer has flowed (every bond of the
 * family at once), else 0. */
void peri_tensor_yield_index(const peri_sim *s, double *psi);
/* The largest |sum_l W_l n . P_l . n| over each owned node's intact bonds. */
void peri_tensor_plastic_stretch(const peri_sim *s, double *out);
/* The owned nodes' state as rows of 6 L (sublayer by sublayer), allocated (zeros before the
 * first force evaluation): what a checkpoint holds. */
double *peri_tensor_state_rows(const peri_sim *s);
/* The state of the owned nodes from rows of the global node order (global_id[i] the row of
 * owned node i, NULL in one process), the committed state too: a checkpoint being read. */
void peri_tensor_set_state_rows(peri_sim *s, const double *rows, const int32_t *global_id);
/* Bytes per node of the rule's arrays (peri check). */
double peri_tensor_bytes_per_node(const peri_sim *s);
void peri_tensor_free(peri_tensor_plasticity *t);

#endif
