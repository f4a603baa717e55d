/* Materials: elastic constants, density, failure, and the constants the models derive. */
#ifndef PERI_MATERIAL_H
#define PERI_MATERIAL_H
#include <stdbool.h>
#include "peri/discretize.h"
#include "peri/plasticity.h"

typedef enum { PERI_PLANE_NONE = 0, PERI_PLANE_STRESS = 1, PERI_PLANE_STRAIN = 2 } peri_plane;

/* Geometry of the problem that every constant depends on. */
typedef struct peri_geometry {
  int dim;             /* 1, 2, 3 */
  peri_plane plane;    /* 2D only */
  double horizon;      /* delta */
  double spacing;      /* dx */
  double thickness;    /* 2D: h */
  double cross_section;/* 1D: A */
  /* the nodes of a uniform fill grid: its axes, whose exact coordinates the bond loops read
   * (node_blocks.h); lattice false for node files, meshes and graded grids */
  bool lattice;
  peri_exact_axis lattice_axis[3];
} peri_geometry;

typedef struct peri_material {
  char *name;
  int model;              /* index in the model table */
  double density;
  double E, nu, K, mu;    /* resolved elastic constants (3D K and mu) */
  bool micromodulus_given;
  double micromodulus;    /* PMB c for a constant influence function */
  /* failure */
  double critical_stretch;/* s0; INFINITY when the material never fails */
  bool lammps_s0;         /* s0_i = s00 - alpha * min stretch of the previous step */
  double s00, alpha_s;
  /* LPS constants (model reference section 3.3) */
  double n_theta, K_theta, alpha_m;
  /* LPS force state (docs/models.md 3.5): false the variational form with the P term (the
   * default), true the Peridigm/LAMMPS form whose P term is that of the intact family */
  bool peer_force_state;
  /* the PMB micromodulus of equal P-wave modulus, for the stable time step (section 13.2) */
  double c_stable;
  /* heat conduction (docs/heat.md); NaN when not given */
  double conductivity;    /* kappa (W/(m K)) */
  double specific_heat;   /* c (J/(kg K)) */
  double thermal_expansion; /* alpha_T (1/K), 0 when not given */
  /* sublayer plasticity (docs/plasticity.md), NULL for an elastic material */
  peri_sublayers *sublayers;
} peri_material;

/* Resolves E, nu, K, mu from whichever two were given (NaN = not given). For models with a
 * fixed Poisson ratio (PMB) pass fixed_nu (else NaN) to complete a single given modulus.
 * 2D moduli are the 3D ones (plane stress/strain enter the model constants). Returns 0,
 * or PERI_ERR_INPUT with a message in `why` (size n) when inconsistent/missing. */
int peri_elastic_resolve(double E, double nu, double K, double mu, double fixed_nu,
                         double *E_out, double *nu_out, double *K_out, double *mu_out,
                         char *why, int n);
/* The Poisson ratio a bond-based model represents: 1/4 in 1D, 3D and plane strain, 1/3 in
 * plane stress. */
double peri_pmb_poisson(const peri_geometry *g);

#endif
