/* The explicit step on an NVIDIA GPU (docs/gpu.md): the device side, behind a C interface
 * that knows nothing of peri_sim (src/solver/explicit_gpu.c fills the problem from one and
 * drives the steps). Built from src/gpu/explicit_kernels.cu when CMake finds CUDA
 * (PERI_CUDA), else src/gpu/gpu_absent.c, whose functions report that this build has no GPU.
 * Every array lives on the device for the whole run; the host copies it back only for
 * output (peri_gpu_download). */
#ifndef PERI_GPU_KERNELS_H
#define PERI_GPU_KERNELS_H
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#ifdef __cplusplus
extern "C" {
#endif

enum { PERI_GPU_PMB = 0, PERI_GPU_LPS = 1 };
enum { PERI_GPU_MAX_MATERIALS = 16 };

/* What the device needs, as host arrays and constants (read by peri_gpu_create only). */
typedef struct peri_gpu_problem {
  int model;                 /* PERI_GPU_PMB or PERI_GPU_LPS */
  int32_t n;                 /* nodes (one process: all owned) */
  int64_t n_bonds;           /* directed bonds */
  const double *x;           /* [3n] reference positions, as the bond loops take them (on a lattice its
                                exact coordinates: src/model/node_blocks.c) */
  const double *x_given;     /* [3n] the nodes' positions as given (the indenter's; NULL: x) */
  const double *volume;      /* [n] */
  const int64_t *offset;     /* [n+1] families, CSR (include/peri/bonds.h) */
  const int32_t *neighbor;   /* [n_bonds] */
  const uint8_t *broken;     /* [n_bonds] */
  const int32_t *material;   /* [n] */
  const uint8_t *no_fail;    /* [n] 1 where the node's bonds never break */
  int n_materials;
  double density[PERI_GPU_MAX_MATERIALS];
  double micromodulus[PERI_GPU_MAX_MATERIALS];           /* PMB c */
  double n_theta[PERI_GPU_MAX_MATERIALS], K_theta[PERI_GPU_MAX_MATERIALS],
      alpha_m[PERI_GPU_MAX_MATERIALS];                   /* LPS constants (models.md 3) */
  bool peer_force_state[PERI_GPU_MAX_MATERIALS];         /* LPS: P as if the family were intact */
  double s00[PERI_GPU_MAX_MATERIALS], alpha_s[PERI_GPU_MAX_MATERIALS]; /* LAMMPS form */
  double pair_s0[PERI_GPU_MAX_MATERIALS * PERI_GPU_MAX_MATERIALS];    /* [a * n_materials + b] */
  bool lammps_s0;            /* s0 per node from the previous step's smallest stretch */
  const double *wvol;        /* [n] LPS weighted volume m */
  /* the family rules (src/model/bond_kernel.h peri_family_eval): beta = min(1, beta0 - |xi| inv_dx) */
  double beta0, inv_dx, inv_delta2;
  int influence;             /* peri_influence */
  double dt, damping;
  bool breaking, break_after_force;
  bool indenter;             /* LAMMPS fix indent: k (R - r)^2 outward for r < R */
  double indenter_radius, indenter_stiffness;
  /* nodes with a prescribed component: held_mask[i] bit d for component d */
  const uint8_t *held_mask;  /* [n] */
  int32_t held_count;
  const int32_t *held_node;  /* [held_count] */
} peri_gpu_problem;

typedef struct peri_gpu peri_gpu;

/* What a step returns: the external work of the step, the kinetic energy of the half-step
 * velocities, the components that are not finite, the indenter's force. */
typedef struct peri_gpu_step_sums {
  double work, kinetic, nonfinite, indenter_force[3];
} peri_gpu_step_sums;

/* The bytes peri_gpu_create allocates on the device for n nodes, n_bonds directed bonds and
 * families of at most `width` bonds (explicit_kernels.cu create: per node 36 doubles, 39 with
 * LPS, and 18 bytes of indices and flags; 5 bytes per slot of the families' ELL layout, width
 * slots a node; 1 per bond for the flags in CSR order), and the peak during the set-up, when
 * the CSR neighbours (4 bytes per bond) are on the device too. */
static inline void peri_gpu_bytes(int64_t n, int64_t n_bonds, int64_t width, bool lps, double *bytes, double *peak) {
  *bytes = (double)n * ((lps ? 39.0 : 36.0) * 8.0 + 18.0) + 5.0 * (double)width * (double)n + (double)n_bonds;
  *peak = *bytes + 4.0 * (double)n_bonds;
}

/* Whether a GPU is present: its name (and the runtime's version) into name, or why not. */
bool peri_gpu_probe(char *name, size_t size);
/* Copies the problem to the device; NULL with the reason in err when it does not fit or
 * the device fails. */
peri_gpu *peri_gpu_create(const peri_gpu_problem *problem, char *err, size_t size);
/* The state: u, v, f ([3n]; f may be NULL: evaluated by peri_gpu_force), the loads that are
 * not the indenter's b_ext ([3n]), s0 per node (LAMMPS form, else NULL), the last step's
 * load ([3n], the work integral's left end). */
int peri_gpu_upload(peri_gpu *g, const double *u, const double *v, const double *f, const double *b_ext,
                    const double *s0_node, const double *step_load);
/* New loads b_ext ([3n]) from the next step on. */
int peri_gpu_set_loads(peri_gpu *g, const double *b_ext);
/* The start of a run: the loads b at the indenter's centre, the internal force of the present
 * state with breaking as the solver breaks (`force`; else the uploaded one stands) and the
 * step load of it (`step_load`, explicit.c external_load; else the uploaded one stands).
 * 0, or -1 when the device fails. */
int peri_gpu_start(peri_gpu *g, const double centre[3], bool force, bool step_load);
/* One velocity-Verlet step (src/solver/explicit.c): half kick and drift of the free
 * components, the prescribed components' new values (held: [held_count][6], u then v),
 * the loads at the indenter's centre, the force, the second half kick, the work and the
 * kinetic energy. 0, or -1 when the device fails (its message in err). */
int peri_gpu_step(peri_gpu *g, const double *held, const double centre[3], peri_gpu_step_sums *sums);
/* Copies the state back (any pointer may be NULL): u, v, f, b ([3n]), the broken flags in CSR
 * order ([n_bonds]), s0 per node ([n]), the step load ([3n]). */
int peri_gpu_download(peri_gpu *g, double *u, double *v, double *f, double *b, uint8_t *broken, double *s0_node,
                      double *step_load);
/* The last device error. */
const char *peri_gpu_error(const peri_gpu *g);
/* Bytes on the device: all of them, and those per directed bond. */
void peri_gpu_memory(const peri_gpu *g, double *bytes, double *per_bond);
/* Waits for the device and returns the seconds the steps took on it so far. */
double peri_gpu_step_seconds(peri_gpu *g);
void peri_gpu_free(peri_gpu *g);

#ifdef __cplusplus
}
#endif
#endif
