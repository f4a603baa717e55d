/* A horizon that varies over the body (docs/variable_horizon.md): each node keeps its own
 * delta_i, and the nodes of the partial-stress coupling region (docs/model_reference.md 15)
 * are marked. NULL in a simulation whose horizon is one number. */
#ifndef PERI_HORIZON_FIELD_H
#define PERI_HORIZON_FIELD_H
#include <stdbool.h>
#include <stdint.h>
#include "peri/bonds.h"
#include "peri/expr.h"
#include "peri/particles.h"

/* the default factor of the zero-energy mode control of the partial-stress force
 * (src/model/partial_stress.c), measured on the 1D pulse of tests/verification/
 * test_horizon_pulse.c: without the control the energy grows a thousandfold in 2 x 10^4
 * steps; with 0.25 or 1 it stays within 0.02% over 4 x 10^4 steps, and the reflection figures
 * of docs/variable_horizon.md are those of 1 */
#define PERI_PARTIAL_STRESS_STABILIZATION 1.0
/* in 2D and 3D: the smallest factor at which the assembled operator of a plate with a circular
 * transition inside it has only real, positive eigenvalues (1 and 4 leave complex pairs that
 * grow; docs/variable_horizon.md "Zero-energy mode control"), and with which the explicit runs
 * of tests/verification/test_horizon_pulse.c stay bounded over 10^4 steps */
#define PERI_PARTIAL_STRESS_STABILIZATION_2D3D 8.0

/* the lattice correction of the partial stress (src/model/partial_stress.c, docs/variable_horizon.md
 * "The lattice correction"): the unit strain of its fourth-order central-difference probe of a
 * node's discrete elasticity D_i, whose truncation error (order 1e-12 relative) and rounding
 * (eps |x| / (1e-3 |xi|), 1e-11 for |x| / |xi| = 50) stay below the patch test's 1e-10 */
#define PERI_LATTICE_PROBE_STRAIN 1.0e-3
/* a node whose D_i is not at least this fraction of C_iso in every strain keeps its own nu0
 * (its correction would amplify nu0 by more than the inverse) */
#define PERI_LATTICE_MIN_STIFFNESS 0.1

/* the quadratic fit's basis: d linear and d(d+1)/2 quadratic terms, 9 in 3D */
#define PERI_FIT_BASIS 9

typedef struct peri_horizon_field {
  int32_t n;              /* nodes */
  double *delta;          /* [n] the horizon of each node */
  double min, max;        /* over the nodes */
  double *s0_scale;       /* [n] critical stretch of a node's bonds over that of the table (which is
                             resolved at `max`): sqrt(max / delta_i) for a failure given as an energy
                             or a toughness, 1 for a critical stretch given as a number */
  uint8_t *coupled;       /* [n] 1: the node's force is the divergence of the partial stress */
  int32_t n_coupled;
  /* the model's per-node constants and work arrays (src/model/variable_horizon.c) */
  double *node_constant;  /* PMB: micromodulus c_i; LPS: weighted volume m_i */
  double *theta, *pstate; /* LPS: dilatation and P_i of the last force evaluation */
  double *state;          /* [n_bonds] scalar force state t_i<xi> of directed bond k (omega and the
                             partial volume of i's horizon included) */
  int64_t *reverse;       /* [n_bonds] bond j -> i of bond k = i -> j */
  /* PMB without a coupling region (one pass over the bonds, src/model/variable_horizon.c) */
  double *bond_length;    /* [n_bonds] |xi| of directed bond k */
  double *bond_pair_state; /* [n_bonds] (t_i<xi_ij> + t_j<xi_ji>) / e of bond k, t_i / e = c_i omega beta_i / (2 |xi|) */
  double *bond_pair;      /* [n_bonds] (t_ij + t_ji) V_j / e of bond k */
  double *bond_critical;  /* [n_bonds] the critical elongation s0 |xi| of bond k (INFINITY: never breaks) */
  double *partial_stress; /* [9 n] nu0_i = sum_j T_i<xi_ij> (x) xi_ij V_j, row-major */
  /* the least-squares gradient stencil of each coupled node (src/model/partial_stress.c) */
  int64_t *stencil_offset;/* [n + 1] */
  int32_t *stencil_node;
  double *stencil_weight; /* [3 per stencil entry] (sum w xi xi^T)^-1 w xi */
  double *stencil_bond;   /* [per stencil entry] w: V_j times the bond stiffness of i's state */
  double *stencil_fit;    /* [PERI_FIT_BASIS per stencil entry] the rows of the quadratic fit of
                             u_j - u_i (zero-energy mode control, src/model/partial_stress.c) */
  double *stiffness;      /* [n] the bond stiffness factor of the control: PMB c_i, LPS alpha_m/m_i */
  double stabilization;   /* the control's factor (discretization.partial_stress_stabilization) */
  double *entry_reaction; /* [3 per stencil entry] scratch: the reaction of each entry on its node */
  int64_t *target_offset; /* [n + 1] the stencil entries whose node is j: target_entry[target_offset[j] ..] */
  int64_t *target_entry;  /* (in the entries' order, so that each node sums its reactions in one order
                             whatever the threads) */
  uint8_t *needs_stress;  /* [n] coupled nodes and the nodes of their stencils */
  int32_t *lattice_index; /* [n] row of node i in lattice_correction; -1: none (a local node, a node
                             outside the stencils, a node whose family is too weak) */
  double *lattice_correction; /* [V^2 per row, V = 1, 3, 6 in 1D, 2D, 3D] R_i = C_iso D_i^-1 in Voigt
                             form: nu0 <- nu0 + (R_i - I) : sym nu0 (src/model/partial_stress.c) */
  long ps_would_break;    /* bonds of coupled nodes beyond their critical stretch (kept intact) */
  /* the local region (docs/variable_horizon.md "A vanishing horizon"): nodes whose horizon is 0
   * carry no force state; their partial stress is the Cauchy stress of the strain of their
   * least-squares gradient over the nodes within local_radius, which is their delta_i */
  uint8_t *local;         /* [n] 1: a local node; NULL when there is none */
  uint8_t *variational;   /* [n] 1: a local node that no peridynamic node's stencil reaches, whose
                             force is -dU/du of the local nodes' energy (src/model/partial_stress.c) */
  int32_t n_local;
  double local_radius;
} peri_horizon_field;

/* Evaluates the horizon expression at every node of p (reference positions). Returns the
 * field, or NULL with *bad set to the first node where the value is negative or not finite
 * (0 marks a local node: peri_horizon_field_mark_local). */
peri_horizon_field *peri_horizon_field_evaluate(const peri_particles *p, peri_expr *horizon, int32_t *bad);
/* The field of the given horizons, each positive and finite (a graded grid's m dx_i). */
peri_horizon_field *peri_horizon_field_from_values(int32_t n, const double *delta);
/* Marks the default coupling region: every node whose family holds a node with a different
 * horizon or volume (relative difference above 1e-12), and where volumes differ (a graded
 * grid) also every node whose family holds such a node. */
void peri_horizon_field_mark_transition(peri_horizon_field *h, const peri_bonds *b, const double *volume);
/* Makes every node whose horizon is 0 a local node whose gradient stencil reaches `radius`
 * (delta_i = radius, so that the bonds within it exist), and updates min and max. */
void peri_horizon_field_mark_local(peri_horizon_field *h, double radius);
/* Adds to the coupling region every local node and every node whose family holds one (a
 * full peridynamic node reads the force state at both ends of its bonds, and a local node has
 * none). */
void peri_horizon_field_couple_local(peri_horizon_field *h, const peri_bonds *b);
/* Bond j -> i of every bond i -> j (both directions exist: the families are symmetric). */
void peri_horizon_field_reverse_bonds(peri_horizon_field *h, const peri_bonds *b);
void peri_horizon_field_free(peri_horizon_field *h);

/* The zero-energy mode control adds to a node it reaches at most twice kappa times its bond
 * stiffness: the factor 1 + 2 kappa on that node's stiffness bound (the stable time step, ADR's
 * fictitious density; docs/variable_horizon.md "Zero-energy mode control"). */
static inline double peri_horizon_control_factor(const peri_horizon_field *h) { return 1.0 + 2.0 * h->stabilization; }

#endif
