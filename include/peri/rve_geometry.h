/* Nanocomposite representative volume elements (Ongaro 2022, 002_b20c318388227af9.txt §3.3.1;
 * model reference section 8, "Bond-based classes"): a square periodic grid of matrix nodes
 * with curved, randomly placed, overlapping platelets of filler, four bond classes, and the
 * homogenized moduli of peri/rve.h. This header: the inputs and the random geometry.
 * docs/microstructures.md section 7. */
#ifndef PERI_RVE_GEOMETRY_H
#define PERI_RVE_GEOMETRY_H
#include <stdint.h>

typedef struct peri_rve_params {
  double side;            /* L = Lx = Ly (m) */
  double spacing;         /* grid spacing dx (m) */
  int m;                  /* horizon delta = m dx */
  double E_matrix;        /* E_m (Pa) */
  double E_filler;        /* E_nf (Pa) */
  double rho_matrix;      /* rho_m (kg/m^3), eq. 3.2 */
  double rho_filler;      /* rho_nf (kg/m^3), eq. 3.2 */
  double weight_fraction; /* wt (0..1), eq. 3.2 */
  double kappa;           /* interphase factor: E_intph = kappa E_m */
  double aspect_mean;     /* AR_mean: platelet length / thickness, Gaussian */
  double aspect_std;      /* AR_std */
  double thickness;       /* platelet thickness t (m): length = AR t */
  double max_turn;        /* largest turning angle of a platelet arc (rad), uniform in +-max_turn */
  double strain;          /* imposed average strain of each load case */
  uint64_t seed;          /* realization k draws from (seed, k) */
} peri_rve_params;

/* The Table 3.1 inputs of 002_b20c318388227af9.txt at L = 1.5 um (platelet thickness 1 nm and
 * max_turn pi/4 are this code's choices: the seed gives neither). */
peri_rve_params peri_rve_params_default(void);

/* Checks the parameters; returns 0, or -1 after peri_error naming the bad one. */
int peri_rve_params_check(const peri_rve_params *p);

/* Filler volume fraction from the weight fraction, eq. 3.2. */
double peri_rve_volume_fraction(double wt, double rho_filler, double rho_matrix);

/* One realization: n x n nodes (n = side/spacing), platelet[i + n j] = -1 for matrix, else the
 * index of the first platelet that covers node (i, j). */
typedef struct peri_rve_geometry {
  int n;
  int32_t *platelet;
  int platelets;     /* number of platelets placed */
  long filler_nodes; /* nodes covered by at least one platelet */
} peri_rve_geometry;

/* Draws realization `realization` of p: the same (p, realization) gives the same geometry,
 * bit for bit. Returns 0, or -1 (out of memory). */
int peri_rve_generate(const peri_rve_params *p, uint64_t realization, peri_rve_geometry *g);
void peri_rve_geometry_free(peri_rve_geometry *g);

#endif
