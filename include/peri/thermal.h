/* Peridynamic heat conduction (Bobaru & Duangpanya 2012, Bobaru & Duangpanya 2012; docs/model_reference.md 11) and its
 * coupling to the mechanics through thermal strain (docs/model_reference.md 9).
 *
 * Discrete equation of node i (per unit volume):
 *   rho_i c_i dT_i/dt = sum_p chi_ip H_ip (T_p - T_i) + w_i,
 *   H_ip = k(|xi|) beta_ip A_p / |xi|^2    (A_p = V_p / h in 2D, V_p / A in 1D, V_p in 3D)
 * with the micro-conductivity k calibrated so that the flux of a linear temperature field
 * equals kappa grad T (docs/model_reference.md 11.2). chi_ip = 0 for a cut bond (pre-crack, broken
 * mechanical bond, growing crack), or the crack conductance fraction. */
#ifndef PERI_THERMAL_H
#define PERI_THERMAL_H
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include "peri/expr.h"

typedef struct peri_sim peri_sim;
typedef struct peri_model_ops peri_model_ops;

typedef enum { PERI_TKERNEL_CONICAL = 0, PERI_TKERNEL_CONSTANT = 1 } peri_thermal_kernel;
/* bonds: the bonds' partial-volume factor beta, kernel at |xi|, node volumes.
 * bobaru2012: Bobaru & Duangpanya 2012 Algorithm 1 (shifted kernel argument, docs/model_reference.md 5(b)) on a
 * vertex-centred grid whose boundary nodes carry half (edge) and quarter (corner) areas. */
typedef enum { PERI_TQUAD_BONDS = 0, PERI_TQUAD_BOBARU2012 = 1 } peri_thermal_quadrature;
/* Own-cell term: none; cell (the midpoint-consistent own-cell integral k(0) A / (2 d dx^2)
 * on the 2d axial neighbours); bobaru2012 (Bobaru & Duangpanya 2012 sec. 3: average over the 3^d - 1
 * nearest nodes with k at half the distance). */
typedef enum { PERI_TSELF_NONE = 0, PERI_TSELF_CELL = 1, PERI_TSELF_BOBARU2012 = 2 } peri_thermal_self;
typedef enum { PERI_TBOND_LOWER = 0, PERI_TBOND_HARMONIC = 1 } peri_thermal_bond_rule;
typedef enum { PERI_TINT_RK4 = 0, PERI_TINT_EULER = 1 } peri_thermal_integrator;
typedef enum { PERI_COUPLING_TWO_WAY = 0, PERI_COUPLING_ONE_WAY = 1 } peri_thermal_coupling;
typedef enum { PERI_TINSULATION_NATURAL = 0, PERI_TINSULATION_ALGEBRAIC = 1 } peri_thermal_insulation;

typedef enum {
  PERI_TBC_TEMPERATURE,   /* prescribed T(x,y,z,t) on the region's nodes (not integrated) */
  PERI_TBC_HEAT_FLUX,     /* flux into the body q (W/m^2): source q/layer, or the algebraic rule */
  PERI_TBC_CONVECTION,    /* h (T_ambient - T) / layer */
  PERI_TBC_HEAT_SOURCE,   /* volumetric source w (W/m^3) */
  PERI_TBC_INITIAL,       /* initial temperature on the region */
} peri_thermal_bc_kind;

typedef struct peri_thermal_bc {
  peri_thermal_bc_kind kind;
  int region;
  peri_expr *value;       /* T, q, w, or h */
  peri_expr *ambient;     /* convection: ambient temperature */
  double layer;           /* heat_flux (source form), convection: layer depth */
  int normal_axis;        /* heat_flux, algebraic rule: axis 0..2 or -1 (inferred) */
  int normal_sign;        /* +1 / -1: outward normal along the axis (0: inferred) */
} peri_thermal_bc;

/* A crack growing along a segment from `from` towards `to` at `speed` from `start`. */
typedef struct peri_growing_crack {
  double from[3], to[3], speed, start;
} peri_growing_crack;

typedef struct peri_thermal {
  peri_thermal_kernel kernel;
  peri_thermal_quadrature quadrature;
  peri_thermal_self self_term;
  peri_thermal_bond_rule bond_rule;
  peri_thermal_integrator integrator;
  peri_thermal_coupling coupling;
  peri_thermal_insulation insulation;
  double crack_conductance; /* fraction of conduction kept by a cut bond (0: insulating) */
  double safety_factor;
  double dt;                /* heat time step in use */
  double dt_stable;         /* stability bound of the integrator (no safety factor) */
  double max_row_sum;       /* max_i sum_p H_ip / (rho c)_i (1/s) */
  long every;               /* coupled runs: heat advanced every this many mechanical steps */
  long substeps;            /* coupled runs: heat sub-steps per advance */
  double time;              /* time of the temperature field */
  int32_t n;                /* owned nodes */
  double *T;                /* temperature [n] */
  double *T_ref;            /* reference temperature of the thermal strain [n] */
  double *rhoc;             /* rho c [n] */
  double *area;             /* A_i: node measure used by the conduction sums [n] */
  double *H;                /* per directed bond: H_ip (W/(m^3 K)), self term included */
  uint8_t *cut;             /* per directed bond: cut flags used for conduction */
  bool own_cut;             /* cut is a private copy (heat-only, one-way) */
  double *source;           /* [n] volumetric source of the current stage (W/m^3) */
  double *sink;             /* [n] linear sink coefficient (convection h/layer) */
  uint8_t *fixed;           /* [n] 1: prescribed temperature; 2: algebraic flux node */
  int8_t *alg_axis;         /* [n] algebraic node: signed axis +-(1 + axis) of the outward normal */
  int32_t *alg_bc;          /* [n] algebraic node: index of its heat_flux condition, -1: q = 0 */
  double *Hs;               /* per directed bond: the self-term part of H (0 beyond the nearest shell) */
  int n_bcs;
  peri_thermal_bc *bcs;
  int n_growing;
  peri_growing_crack *growing;
  int64_t n_growing_bonds;  /* bonds crossing a growing crack, sorted by cut time */
  int64_t *growing_bond;
  double *growing_time;
  int64_t growing_next;
  double *flux;             /* [3n] heat flux output buffer */
  double *work[6];          /* integrator buffers [n] */
} peri_thermal;

#endif
