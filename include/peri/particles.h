/* Particles: structure of arrays. Vectors are stored with stride 3 in every dimension
 * (unused components are zero), so kernels are the same in 1D, 2D and 3D.
 * The first n_owned particles are owned by this process; ghosts (MPI) follow. */
#ifndef PERI_PARTICLES_H
#define PERI_PARTICLES_H
#include <stdbool.h>
#include <stdint.h>

/* Per-node flags. */
enum {
  PERI_NODE_NO_FAIL = 1u << 0, /* bonds with this end never break */
  PERI_NODE_FICTITIOUS = 1u << 1, /* a fictitious boundary layer node: prescribed, never damaged, out of
                                     output (docs/deck.md section 10) */
};

typedef struct peri_particles {
  int dim;          /* 1, 2 or 3 */
  int32_t n;        /* owned + ghosts */
  int32_t n_owned;
  int32_t capacity;
  double *x;        /* reference position [3n] */
  double *u;        /* displacement [3n] */
  double *v;        /* velocity [3n] */
  double *f;        /* internal + external force density [3n] (N/m^3) */
  double *b;        /* prescribed body force density [3n] */
  double *volume;   /* [n] */
  int32_t *material;/* [n] material index */
  int32_t *block;   /* [n] block id from a node file (or the fill shape index) */
  uint8_t *flags;   /* [n] PERI_NODE_* */
  double *damage;   /* [n] */
  /* model work arrays (allocated by the model that needs them, else NULL) */
  double *theta;    /* dilatation */
  double *wvol;     /* weighted volume m */
  double *pstate;   /* 2D LPS: P_i = (w e^d).x */
  double *energy;   /* strain energy density W_i */
  double *smin;     /* LAMMPS-style critical stretch: min stretch of the previous step */
  double *coef;     /* per-node coefficients a model's bond loop reads for neighbours
                       (PMB: micromodulus; LPS: two per node) */
  double *s0_bound; /* a lower bound of the critical stretch of every bond of the node
                       (INFINITY: never breaks), screening the bond loops for breaking */
  bool s0_bound_uniform; /* every entry of s0_bound (owned and ghosts) is the same number */
} peri_particles;

void peri_particles_init(peri_particles *p, int dim);
/* Appends a node; grows the arrays. Returns its index. */
int32_t peri_particles_add(peri_particles *p, const double x[3], double volume,
                           int32_t material, int32_t block);
/* Allocates the state arrays (u, v, f, b, damage) for the current n, zeroed. */
void peri_particles_alloc_state(peri_particles *p);
/* Reorders all per-node arrays by perm (new index k holds old node perm[k]). */
void peri_particles_permute(peri_particles *p, const int32_t *perm);
void peri_particles_free(peri_particles *p);

#endif
