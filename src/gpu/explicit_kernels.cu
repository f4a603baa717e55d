/* The explicit step on an NVIDIA GPU (gpu_kernels.h, docs/gpu.md): one thread per node
 * gathers its family, as the seed's GPU port does (Ebrahimi 2020 section 7.2.8: structure of
 * arrays, one thread per particle, no atomics in the force), so every node's sums run in its
 * family's order and the results do not depend on the launch.
 *
 * Layout: the families in ELL order (column a of node i at a * n + i, up to the longest
 * family), so that the 32 threads of a warp, 32 consecutive nodes, read their a-th
 * neighbour's index and broken flag from 32 consecutive words; the nodes are in the
 * space-filling-curve order of the set-up (src/core/sfc_order.c), so the neighbours a warp
 * gathers lie close together. Positions, displacements and the other per-node fields are
 * separate arrays of doubles (structure of arrays).
 *
 * Arithmetic: the file is compiled without contraction of multiplications and additions
 * into fused operations (-fmad=false); the fused ones are written as fma() where the CPU
 * kernels write them, with the CPU's operations in the CPU's order, and square roots and
 * divisions are IEEE-rounded. So a bond's stretch is the CPU's exact test's number to the
 * bit (src/model/node_blocks.c bond_stretch) and the same bonds break; the forces differ from
 * the CPU's vector kernels at round-off (their lengths come from other instructions).
 *
 * Compiled with -DPERI_GPU_EMULATE by a host C++ compiler, the same code runs every "kernel"
 * as a loop on the host over host memory: a check of the logic without a GPU
 * (tests/gpu/README.md). */
#include "gpu_kernels.h"
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifdef PERI_GPU_EMULATE
#define HD
typedef int dev_status;
static const dev_status dev_ok = 0;
static dev_status dev_alloc(void **p, size_t bytes) {
  *p = calloc(bytes > 0 ? bytes : 1, 1);
  return *p ? 0 : 1;
}
static dev_status dev_to(void *dst, const void *src, size_t bytes) { return memcpy(dst, src, bytes), 0; }
static dev_status dev_from(void *dst, const void *src, size_t bytes) { return memcpy(dst, src, bytes), 0; }
static dev_status dev_zero(void *p, size_t bytes) { return memset(p, 0, bytes), 0; }
static dev_status dev_sync(void) { return 0; }
static void dev_free(void *p) { free(p); }
static const char *dev_message(dev_status) { return "host memory exhausted"; }
template <class F> static void each(int64_t n, F f) {
  for (int64_t i = 0; i < n; ++i) f(i);
}
static dev_status dev_launched(void) { return 0; }
#else
#include <cuda_runtime.h>
#define HD __host__ __device__
typedef cudaError_t dev_status;
static const dev_status dev_ok = cudaSuccess;
static dev_status dev_alloc(void **p, size_t bytes) { return cudaMalloc(p, bytes > 0 ? bytes : 1); }
static dev_status dev_to(void *dst, const void *src, size_t bytes) {
  return cudaMemcpy(dst, src, bytes, cudaMemcpyHostToDevice);
}
static dev_status dev_from(void *dst, const void *src, size_t bytes) {
  return cudaMemcpy(dst, src, bytes, cudaMemcpyDeviceToHost);
}
static dev_status dev_zero(void *p, size_t bytes) { return cudaMemset(p, 0, bytes); }
static dev_status dev_sync(void) { return cudaDeviceSynchronize(); }
static void dev_free(void *p) {
  if (p) cudaFree(p);
}
static const char *dev_message(dev_status s) { return cudaGetErrorString(s); }
/* threads per block of the per-node kernels */
#define BLOCK_THREADS 256
template <class F> __global__ void each_kernel(int64_t n, F f) {
  const int64_t i = (int64_t)blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) f(i);
}
template <class F> static void each(int64_t n, F f) {
  if (n > 0) each_kernel<<<(unsigned)((n + BLOCK_THREADS - 1) / BLOCK_THREADS), BLOCK_THREADS>>>(n, f);
}
static dev_status dev_launched(void) { return cudaGetLastError(); }
#endif

/* The per-step sums reduced on the device, one row of n each (REDUCED of them). */
enum { SUM_WORK, SUM_KINETIC, SUM_NONFINITE, SUM_INDENTER_X, SUM_INDENTER_Y, SUM_INDENTER_Z, REDUCED };
/* Nodes summed by one thread of a reduction level: the CPU's fixed blocks (PERI_SUM_BLOCK,
 * include/peri/decompose.h), so that the first level's sums are the CPU's block sums. */
#define SUM_GROUP 64
/* Per-material constants, a row of MATERIAL_ROWS doubles each. */
enum { MAT_DENSITY, MAT_C, MAT_N_THETA, MAT_K_THETA, MAT_ALPHA_M, MAT_PEER, MAT_S00, MAT_ALPHA_S, MATERIAL_ROWS };

/* What the kernels read: device pointers and constants, copied into each kernel by value. */
struct Dev {
  int64_t n, width;
  int model, influence, n_materials;
  bool breaking, lammps_s0, multi;
  double beta0, inv_dx, inv_delta2, dt, damping, damping_divisor;
  double indenter_radius, indenter_stiffness;
  const double *x0, *x1, *x2, *V, *inv_rho, *half_mass, *wvol;
  const double *p0, *p1, *p2; /* the positions as given (the indenter's) */
  double *u0, *u1, *u2, *v0, *v1, *v2, *f0, *f1, *f2, *b0, *b1, *b2, *e0, *e1, *e2, *l0, *l1, *l2;
  double *s0_node, *smin, *D, *B;
  const int32_t *count, *material;
  const int32_t *nbr;     /* [width * n] */
  uint8_t *brk;           /* [width * n] */
  const uint8_t *no_fail, *held_mask;
  const double *mat, *pair_s0;
  double *sums;           /* [REDUCED * n] */
};

struct peri_gpu {
  Dev d;
  int64_t n_bonds;
  int32_t held_count;
  int32_t *held_node;     /* [held_count] */
  double *held_old;       /* [held_count * 6] the state before the step (u then v) */
  double *held_new;       /* [held_count * 6] */
  int64_t *offset;        /* [n + 1] */
  uint8_t *broken_csr;    /* [n_bonds] */
  double *level[2];       /* the reductions' partial sums */
  bool break_after_force, indenter;
  double centre[3];
  double bytes, step_seconds;
  char err[512];
};

static double now_seconds(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int fail(peri_gpu *g, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(g->err, sizeof g->err, fmt, ap);
  va_end(ap);
  return -1;
}

#define CHECK(g, call, what)                                                               \
  do {                                                                                     \
    const dev_status status_ = (call);                                                     \
    if (status_ != dev_ok) return fail((g), "%s: %s", (what), dev_message(status_));       \
  } while (0)

/* ------------------------------------------------------------------------------------- */
/* Bonds: the family rules and the breaking test (src/model/bond_kernel.h, node_blocks.c). */

HD static inline double family_beta(const Dev &d, double r0) {
  const double beta = d.beta0 - r0 * d.inv_dx;
  return beta < 1.0 ? beta : 1.0;
}
HD static inline double family_omega(const Dev &d, double r0) {
  if (d.influence == 1) return 1.0 / r0;                    /* PERI_INFLUENCE_INVERSE */
  if (d.influence == 2) return exp(-(r0 * r0) * d.inv_delta2); /* PERI_INFLUENCE_GAUSSIAN */
  return 1.0;
}
/* The critical stretch of bond i-j (peri_bond_s0): INFINITY at a no-fail end. */
HD static inline double bond_s0(const Dev &d, int64_t i, int64_t j) {
  if (d.no_fail[i] | d.no_fail[j]) return INFINITY;
  if (d.lammps_s0) return fmin(d.s0_node[i], d.s0_node[j]);
  return d.pair_s0[d.material[i] * d.n_materials + d.material[j]];
}

/* One bond's geometry from node i's side: offsets, reference and deformed lengths, in
 * bond_stretch's operations (src/model/node_blocks.c): (r - r0)/r0 is its number. */
struct Bond {
  double y0, y1, y2, r0, r, stretch;
};
HD static inline Bond bond_of(const Dev &d, int64_t i, int64_t j) {
  Bond b;
  const double x0 = d.x0[j] - d.x0[i], x1 = d.x1[j] - d.x1[i], x2 = d.x2[j] - d.x2[i];
  b.r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2);
  b.y0 = x0 + (d.u0[j] - d.u0[i]), b.y1 = x1 + (d.u1[j] - d.u1[i]), b.y2 = x2 + (d.u2[j] - d.u2[i]);
  b.r = sqrt(b.y0 * b.y0 + b.y1 * b.y1 + b.y2 * b.y2);
  b.stretch = (b.r - b.r0) / b.r0;
  return b;
}

/* The breaking test of bond e = (a, i) at this displacement (node_blocks.c: the stretch of
 * bond_stretch against peri_bond_s0): true, and the bond marked broken, when it breaks now. */
HD static inline bool breaks_now(const Dev &d, int64_t e, int64_t i, int64_t j, const Bond &b) {
  if (!(b.stretch > bond_s0(d, i, j))) return false;
  d.brk[e] = 1;
  return true;
}

/* ------------------------------------------------------------------------------------- */
/* The models (src/model/pmb.c, lps.c; docs/model_reference.md 2-3). */

/* |a| by lps.c's peri_length3: the squares summed by fused operations. */
HD static inline double length3(double a0, double a1, double a2) { return sqrt(fma(a2, a2, fma(a1, a1, a0 * a0))); }

/* What a model's passes take from a bond's lengths besides the stretch of the breaking test:
 * PMB its stretch (r - r0) r / (r0 r) and 1/(r0 r) (pmb.c pmb_bond), LPS its extension and
 * |xi| from lengths by fused sums (lps.c lps_bond_sums); stretch() is the one the LAMMPS form
 * takes the smallest of. */
struct PmbBond {
  double stretch_, inv_r0_r;
  HD double stretch() const { return stretch_; }
};
HD static inline PmbBond pmb_measure(const Bond &b) {
  PmbBond m;
  m.inv_r0_r = 1.0 / (b.r0 * b.r);
  m.stretch_ = (b.r - b.r0) * b.r * m.inv_r0_r;
  return m;
}
struct LpsBond {
  double ext, r0;
  HD double stretch() const { return ext / r0; }
};
HD static inline LpsBond lps_measure(const Dev &d, int64_t i, int64_t j, const Bond &b) {
  LpsBond m;
  m.r0 = length3(d.x0[j] - d.x0[i], d.x1[j] - d.x1[i], d.x2[j] - d.x2[i]);
  m.ext = length3(b.y0, b.y1, b.y2) - m.r0;
  return m;
}

/* Visits node i's intact bonds in family order: measure(j, bond) (the model's view of it),
 * the breaking test (when `breaking`), then body(j, bond, measure) on the bonds that stay. The
 * LAMMPS form's smallest stretch is taken over the bonds intact before the test, as the CPU's
 * passes take it. */
template <class Measure, class Body>
HD static inline void visit_family(const Dev &d, int64_t i, bool breaking, Measure measure, Body body) {
  double smin = INFINITY;
  const int64_t cnt = d.count[i];
  for (int64_t a = 0; a < cnt; ++a) {
    const int64_t e = a * d.n + i;
    if (d.brk[e]) continue;
    const int64_t j = d.nbr[e];
    const Bond b = bond_of(d, i, j);
    const auto m = measure(j, b);
    if (d.lammps_s0 && m.stretch() < smin) smin = m.stretch();
    if (breaking && breaks_now(d, e, i, j, b)) continue;
    body(j, b, m);
  }
  if (d.lammps_s0) d.smin[i] = smin;
}

/* PMB, node i: breaks its bonds beyond their critical stretch (when `breaking`), then sums
 * f_i = sum c s omega beta V_j (y/|y|) over the intact ones in family order, in the
 * operations of pmb.c's scalar pmb_bond. */
HD static inline void pmb_node(const Dev &d, int64_t i, bool breaking) {
  const double ci = d.mat[MATERIAL_ROWS * d.material[i] + MAT_C];
  double f0 = 0.0, f1 = 0.0, f2 = 0.0;
  visit_family(
      d, i, breaking, [&](int64_t, const Bond &b) { return pmb_measure(b); },
      [&](int64_t j, const Bond &b, const PmbBond &m) {
        if (!(b.r > 0.0)) return;
        const double c = d.multi ? 0.5 * (ci + d.mat[MATERIAL_ROWS * d.material[j] + MAT_C]) : ci;
        const double g = c * m.stretch_ * family_omega(d, b.r0) * family_beta(d, b.r0) * d.V[j] * b.r0 * m.inv_r0_r;
        f0 = fma(g, b.y0, f0), f1 = fma(g, b.y1, f1), f2 = fma(g, b.y2, f2);
      });
  d.f0[i] = f0, d.f1[i] = f1, d.f2[i] = f2;
}

/* LPS pass 1, node i: the breaking test, then the dilatation's sums over the intact bonds and
 * the coefficients D_i and B_i of the force pass (lps.c lps_coefficients_of, no thermal
 * strain): theta = n_theta sum w e / m, P = sum w e - theta sum w |xi| / 3 (m for the peer
 * form), alpha = alpha_m / m, D = n_theta (K_theta theta - alpha P / 3) / m - alpha theta / 3. */
HD static inline void lps_dilatation_node(const Dev &d, int64_t i, bool breaking) {
  double we_x = 0.0, w_xx = 0.0;
  visit_family(
      d, i, breaking, [&](int64_t j, const Bond &b) { return lps_measure(d, i, j, b); },
      [&](int64_t j, const Bond &, const LpsBond &m) {
        /* omega |xi| = 1 for the inverse influence */
        const double omega_r0 = d.influence == 1 ? 1.0 : family_omega(d, m.r0) * m.r0;
        const double w = omega_r0 * family_beta(d, m.r0) * d.V[j];
        we_x = fma(w, m.ext, we_x);
        w_xx = fma(w, m.r0, w_xx);
      });
  const double *mat = d.mat + MATERIAL_ROWS * d.material[i];
  const double m = d.wvol[i], n_theta = mat[MAT_N_THETA];
  if (mat[MAT_PEER] != 0.0) w_xx = m;
  const double theta = n_theta * we_x / m;
  const double P = we_x - theta * w_xx / 3.0;
  const double alpha = mat[MAT_ALPHA_M] / m;
  d.D[i] = n_theta * (mat[MAT_K_THETA] * theta - alpha * P / 3.0) / m - alpha * (0.0 + theta / 3.0);
  d.B[i] = alpha;
}

/* LPS pass 2, node i: f_i = sum omega (|xi| (D_i + D_j) + e (B_i + B_j)) beta V_j y/|y|. */
HD static inline void lps_force_node(const Dev &d, int64_t i) {
  const double Di = d.D[i], Bi = d.B[i];
  double f0 = 0.0, f1 = 0.0, f2 = 0.0;
  const int64_t cnt = d.count[i];
  for (int64_t a = 0; a < cnt; ++a) {
    const int64_t e = a * d.n + i;
    if (d.brk[e]) continue;
    const int64_t j = d.nbr[e];
    /* (lps.c lps_bond_force) */
    const double x0 = d.x0[j] - d.x0[i], x1 = d.x1[j] - d.x1[i], x2 = d.x2[j] - d.x2[i];
    const double y0 = x0 + (d.u0[j] - d.u0[i]), y1 = x1 + (d.u1[j] - d.u1[i]), y2 = x2 + (d.u2[j] - d.u2[i]);
    const double r0 = length3(x0, x1, x2), r = length3(y0, y1, y2);
    if (!(r > 0.0)) continue;
    const double t = fma(r0, Di + d.D[j], (r - r0) * (Bi + d.B[j]));
    const double bv = family_beta(d, r0) * d.V[j];
    const double g = d.influence == 1 ? t * bv / (r0 * r) : family_omega(d, r0) * t * bv / r;
    f0 = fma(g, y0, f0), f1 = fma(g, y1, f1), f2 = fma(g, y2, f2);
  }
  d.f0[i] = f0, d.f1[i] = f1, d.f2[i] = f2;
}

/* The breaking test alone (the LAMMPS order's cut after the force, models.md 5.1). */
HD static inline void break_node(const Dev &d, int64_t i) {
  if (d.model == PERI_GPU_PMB)
    visit_family(d, i, true, [&](int64_t, const Bond &b) { return pmb_measure(b); },
                 [](int64_t, const Bond &, const PmbBond &) {});
  else
    visit_family(d, i, true, [&](int64_t j, const Bond &b) { return lps_measure(d, i, j, b); },
                 [](int64_t, const Bond &, const LpsBond &) {});
}

/* ------------------------------------------------------------------------------------- */
/* Passes */

/* The internal force with the solver's breaking order (peri_force_in_breaking_order): the
 * cut then the force, or the force then the cut; then the LAMMPS form's s0 of each node from
 * the smallest stretch at the test (lammps_s0.c). */
static void internal_force(peri_gpu *g) {
  const Dev d = g->d;
  const bool cut_first = d.breaking && !g->break_after_force;
  if (d.model == PERI_GPU_PMB) {
    each(d.n, [=] HD(int64_t i) { pmb_node(d, i, cut_first); });
  } else {
    each(d.n, [=] HD(int64_t i) { lps_dilatation_node(d, i, cut_first); });
    each(d.n, [=] HD(int64_t i) { lps_force_node(d, i); });
  }
  if (d.breaking && g->break_after_force) each(d.n, [=] HD(int64_t i) { break_node(d, i); });
  if (d.lammps_s0) /* (also without breaking, as the CPU keeps it) */
    each(d.n, [=] HD(int64_t i) {
      const double *mat = d.mat + MATERIAL_ROWS * d.material[i];
      if (isfinite(d.smin[i])) d.s0_node[i] = mat[MAT_S00] - mat[MAT_ALPHA_S] * d.smin[i];
    });
}

/* b = b_ext + the indenter's force density k (R - r)^2 outward for r < R (indenter.c), its
 * reaction per node into the sums. */
static void loads(peri_gpu *g) {
  const Dev d = g->d;
  const bool on = g->indenter;
  const double c0 = g->centre[0], c1 = g->centre[1], c2 = g->centre[2];
  each(d.n, [=] HD(int64_t i) {
    double b0 = d.e0[i], b1 = d.e1[i], b2 = d.e2[i];
    double r0 = 0.0, r1 = 0.0, r2 = 0.0;
    if (on) {
      const double y0 = d.p0[i] + d.u0[i] - c0, y1 = d.p1[i] + d.u1[i] - c1, y2 = d.p2[i] + d.u2[i] - c2;
      const double rr = y0 * y0 + y1 * y1 + y2 * y2, R = d.indenter_radius;
      if (rr < R * R) {
        const double r = sqrt(rr);
        if (r != 0.0) {
          const double mag = d.indenter_stiffness * (R - r) * (R - r) / r;
          b0 += mag * y0, b1 += mag * y1, b2 += mag * y2;
          r0 = -mag * y0 * d.V[i], r1 = -mag * y1 * d.V[i], r2 = -mag * y2 * d.V[i];
        }
      }
    }
    d.b0[i] = b0, d.b1[i] = b1, d.b2[i] = b2;
    d.sums[SUM_INDENTER_X * d.n + i] = r0, d.sums[SUM_INDENTER_Y * d.n + i] = r1, d.sums[SUM_INDENTER_Z * d.n + i] = r2;
  });
}

/* Component k of node i's u, v, f, b and step load. */
HD static inline double *comp(double *a0, double *a1, double *a2, int k) { return k == 0 ? a0 : k == 1 ? a1 : a2; }

/* The sums of each row of d.sums in fixed groups of SUM_GROUP, level by level, into out. */
static int reduce_rows(peri_gpu *g, double out[REDUCED]) {
  const Dev d = g->d;
  int64_t m = d.n;
  const double *src = d.sums;
  int64_t src_stride = d.n;
  int which = 0;
  do {
    const int64_t groups = (m + SUM_GROUP - 1) / SUM_GROUP;
    double *dst = g->level[which];
    const int64_t mm = m, ss = src_stride;
    each((int64_t)REDUCED * groups, [=] HD(int64_t t) {
      const int64_t row = t / groups, group = t % groups, first = group * SUM_GROUP;
      const int64_t last = first + SUM_GROUP < mm ? first + SUM_GROUP : mm;
      double s = 0.0;
      for (int64_t k = first; k < last; ++k) s += src[row * ss + k];
      dst[row * groups + group] = s;
    });
    src = dst, src_stride = groups, m = groups, which ^= 1;
  } while (m > 1);
  CHECK(g, dev_launched(), "a reduction kernel");
  /* (the last level has one group: the rows' sums lie side by side) */
  if (d.n == 0)
    for (int r = 0; r < REDUCED; ++r) out[r] = 0.0;
  else
    CHECK(g, dev_from(out, src, sizeof(double) * REDUCED), "the step's sums");
  return 0;
}

/* ------------------------------------------------------------------------------------- */
/* The interface */

extern "C" bool peri_gpu_probe(char *name, size_t size) {
#ifdef PERI_GPU_EMULATE
  snprintf(name, size, "the host (GPU emulation: every kernel a loop on the CPU)");
  return true;
#else
  int count = 0;
  const cudaError_t status = cudaGetDeviceCount(&count);
  if (status != cudaSuccess || count == 0) {
    snprintf(name, size, "%s", status != cudaSuccess ? cudaGetErrorString(status) : "no CUDA device");
    return false;
  }
  cudaDeviceProp prop;
  if (cudaGetDeviceProperties(&prop, 0) != cudaSuccess) {
    snprintf(name, size, "the CUDA device's properties could not be read");
    return false;
  }
  int runtime = 0;
  cudaRuntimeGetVersion(&runtime);
  snprintf(name, size, "%s (compute capability %d.%d, %.0f GiB, CUDA runtime %d.%d)", prop.name, prop.major,
           prop.minor, (double)prop.totalGlobalMem / 1073741824.0, runtime / 1000, (runtime % 1000) / 10);
  return true;
#endif
}

/* Allocates bytes on the device into *p, counted. */
static int alloc(peri_gpu *g, void *p, size_t bytes, const char *what) {
  const dev_status s = dev_alloc((void **)p, bytes);
  if (s != dev_ok)
    return fail(g, "cannot allocate %.3g GB on the device for %s (%.3g GB so far): %s", (double)bytes / 1e9, what,
                g->bytes / 1e9, dev_message(s));
  g->bytes += (double)bytes;
  return 0;
}

static int upload(peri_gpu *g, void *dst, const void *src, size_t bytes, const char *what) {
  CHECK(g, dev_to(dst, src, bytes), what);
  return 0;
}

/* A [3n] interleaved host array into three device arrays. */
static int upload3(peri_gpu *g, double *a0, double *a1, double *a2, const double *h, const char *what) {
  const int64_t n = g->d.n;
  double *tmp = (double *)malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  if (!tmp) return fail(g, "out of host memory");
  double *dst[3] = {a0, a1, a2};
  for (int k = 0; k < 3; ++k) {
    for (int64_t i = 0; i < n; ++i) tmp[i] = h ? h[3 * i + k] : 0.0;
    if (upload(g, dst[k], tmp, sizeof(double) * (size_t)n, what)) return free(tmp), -1;
  }
  free(tmp);
  return 0;
}

static int download3(peri_gpu *g, double *h, const double *a0, const double *a1, const double *a2, const char *what) {
  const int64_t n = g->d.n;
  double *tmp = (double *)malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  if (!tmp) return fail(g, "out of host memory");
  const double *src[3] = {a0, a1, a2};
  for (int k = 0; k < 3; ++k) {
    const dev_status s = dev_from(tmp, src[k], sizeof(double) * (size_t)n);
    if (s != dev_ok) return free(tmp), fail(g, "%s: %s", what, dev_message(s));
    for (int64_t i = 0; i < n; ++i) h[3 * i + k] = tmp[i];
  }
  free(tmp);
  return 0;
}

static int create(peri_gpu *g, const peri_gpu_problem *q) {
  Dev &d = g->d;
  const int64_t n = q->n, nb = q->n_bonds;
  const size_t N = (size_t)(n > 0 ? n : 1), dn = sizeof(double) * N;
  d.n = n, d.model = q->model, d.influence = q->influence, d.n_materials = q->n_materials;
  d.breaking = q->breaking, d.lammps_s0 = q->lammps_s0, d.multi = q->n_materials > 1;
  d.beta0 = q->beta0, d.inv_dx = q->inv_dx, d.inv_delta2 = q->inv_delta2;
  d.dt = q->dt, d.damping = q->damping, d.damping_divisor = 1.0 + 0.5 * q->dt * q->damping;
  d.indenter_radius = q->indenter_radius, d.indenter_stiffness = q->indenter_stiffness;
  g->n_bonds = nb, g->held_count = q->held_count;
  g->break_after_force = q->break_after_force, g->indenter = q->indenter;
  int64_t width = 0;
  for (int64_t i = 0; i < n; ++i) width = q->offset[i + 1] - q->offset[i] > width ? q->offset[i + 1] - q->offset[i] : width;
  d.width = width;
  /* per-node doubles */
  double **fields[] = {(double **)&d.x0, (double **)&d.x1, (double **)&d.x2, (double **)&d.p0, (double **)&d.p1,
                       (double **)&d.p2, (double **)&d.V, (double **)&d.inv_rho,
                       (double **)&d.half_mass, &d.u0, &d.u1, &d.u2, &d.v0, &d.v1, &d.v2, &d.f0, &d.f1, &d.f2,
                       &d.b0, &d.b1, &d.b2, &d.e0, &d.e1, &d.e2, &d.l0, &d.l1, &d.l2, &d.s0_node, &d.smin};
  for (size_t k = 0; k < sizeof fields / sizeof fields[0]; ++k)
    if (alloc(g, fields[k], dn, "the node fields")) return -1;
  if (q->model == PERI_GPU_LPS &&
      (alloc(g, &d.wvol, dn, "the weighted volumes") || alloc(g, &d.D, dn, "the LPS coefficients") ||
       alloc(g, &d.B, dn, "the LPS coefficients")))
    return -1;
  if (alloc(g, &d.sums, sizeof(double) * REDUCED * N, "the step's sums") ||
      alloc(g, &g->level[0], sizeof(double) * REDUCED * (N / SUM_GROUP + 1), "the step's sums") ||
      alloc(g, &g->level[1], sizeof(double) * REDUCED * (N / SUM_GROUP / SUM_GROUP + 1), "the step's sums") ||
      alloc(g, &d.count, sizeof(int32_t) * N, "the family sizes") ||
      alloc(g, &d.material, sizeof(int32_t) * N, "the materials") || alloc(g, &d.no_fail, N, "the no-fail flags") ||
      alloc(g, &d.held_mask, N, "the prescribed components") ||
      alloc(g, &d.nbr, sizeof(int32_t) * (size_t)(width * n > 0 ? width * n : 1), "the families") ||
      alloc(g, &d.brk, (size_t)(width * n > 0 ? width * n : 1), "the broken flags") ||
      alloc(g, &g->offset, sizeof(int64_t) * (N + 1), "the family offsets") ||
      alloc(g, &g->broken_csr, (size_t)(nb > 0 ? nb : 1), "the broken flags") ||
      alloc(g, &d.mat, sizeof(double) * MATERIAL_ROWS * PERI_GPU_MAX_MATERIALS, "the materials") ||
      alloc(g, &d.pair_s0, sizeof(double) * PERI_GPU_MAX_MATERIALS * PERI_GPU_MAX_MATERIALS, "the materials") ||
      alloc(g, &g->held_node, sizeof(int32_t) * (size_t)(q->held_count > 0 ? q->held_count : 1), "the held nodes") ||
      alloc(g, &g->held_old, sizeof(double) * 6 * (size_t)(q->held_count > 0 ? q->held_count : 1), "the held nodes") ||
      alloc(g, &g->held_new, sizeof(double) * 6 * (size_t)(q->held_count > 0 ? q->held_count : 1), "the held nodes"))
    return -1;
  /* host copies in the device's layouts */
  double *tmp = (double *)malloc(dn);
  int32_t *itmp = (int32_t *)malloc(sizeof(int32_t) * N);
  if (!tmp || !itmp) return free(tmp), free(itmp), fail(g, "out of host memory");
  int rc = 0;
  double *coords[6] = {(double *)d.x0, (double *)d.x1, (double *)d.x2, (double *)d.p0, (double *)d.p1, (double *)d.p2};
  for (int k = 0; k < 6 && !rc; ++k) {
    const double *x = k < 3 || !q->x_given ? q->x : q->x_given;
    for (int64_t i = 0; i < n; ++i) tmp[i] = x[3 * i + k % 3];
    rc = upload(g, coords[k], tmp, dn, "the positions");
  }
  if (!rc) rc = upload(g, (void *)d.V, q->volume, sizeof(double) * (size_t)n, "the volumes");
  for (int64_t i = 0; i < n; ++i) tmp[i] = 1.0 / q->density[q->material[i]];
  if (!rc) rc = upload(g, (void *)d.inv_rho, tmp, sizeof(double) * (size_t)n, "the densities");
  /* (explicit.c: half the node's mass, 0.5 V / (1/rho)) */
  for (int64_t i = 0; i < n; ++i) tmp[i] = 0.5 * q->volume[i] / (1.0 / q->density[q->material[i]]);
  if (!rc) rc = upload(g, (void *)d.half_mass, tmp, sizeof(double) * (size_t)n, "the masses");
  if (!rc && d.wvol) rc = upload(g, (void *)d.wvol, q->wvol, sizeof(double) * (size_t)n, "the weighted volumes");
  for (int64_t i = 0; i < n; ++i) itmp[i] = (int32_t)(q->offset[i + 1] - q->offset[i]);
  if (!rc) rc = upload(g, (void *)d.count, itmp, sizeof(int32_t) * (size_t)n, "the family sizes");
  if (!rc) rc = upload(g, (void *)d.material, q->material, sizeof(int32_t) * (size_t)n, "the materials");
  if (!rc) rc = upload(g, (void *)d.no_fail, q->no_fail, (size_t)n, "the no-fail flags");
  if (!rc) rc = upload(g, (void *)d.held_mask, q->held_mask, (size_t)n, "the prescribed components");
  if (!rc && q->held_count > 0)
    rc = upload(g, g->held_node, q->held_node, sizeof(int32_t) * (size_t)q->held_count, "the held nodes");
  if (!rc) rc = upload(g, g->offset, q->offset, sizeof(int64_t) * (size_t)(n + 1), "the family offsets");
  double mat[MATERIAL_ROWS * PERI_GPU_MAX_MATERIALS] = {0};
  for (int m = 0; m < q->n_materials; ++m) {
    double *row = mat + MATERIAL_ROWS * m;
    row[MAT_DENSITY] = q->density[m], row[MAT_C] = q->micromodulus[m], row[MAT_N_THETA] = q->n_theta[m];
    row[MAT_K_THETA] = q->K_theta[m], row[MAT_ALPHA_M] = q->alpha_m[m], row[MAT_PEER] = q->peer_force_state[m];
    row[MAT_S00] = q->s00[m], row[MAT_ALPHA_S] = q->alpha_s[m];
  }
  if (!rc) rc = upload(g, (void *)d.mat, mat, sizeof mat, "the materials");
  if (!rc) rc = upload(g, (void *)d.pair_s0, q->pair_s0, sizeof(double) * PERI_GPU_MAX_MATERIALS * PERI_GPU_MAX_MATERIALS, "the materials");
  free(tmp);
  free(itmp);
  if (rc) return rc;
  /* the families into ELL order on the device, through the CSR arrays (freed after) */
  int32_t *nbr_csr = NULL;
  if (alloc(g, &nbr_csr, sizeof(int32_t) * (size_t)(nb > 0 ? nb : 1), "the families (CSR, during the set-up)")) return -1;
  g->bytes -= sizeof(int32_t) * (double)(nb > 0 ? nb : 1);
  rc = upload(g, nbr_csr, q->neighbor, sizeof(int32_t) * (size_t)nb, "the families");
  if (!rc) rc = upload(g, g->broken_csr, q->broken, (size_t)nb, "the broken flags");
  /* (the temporary array is freed on every path: a failure below only sets rc) */
  dev_status st = dev_ok;
  if (!rc) st = dev_zero(d.brk, (size_t)(width * n > 0 ? width * n : 1));
  if (!rc && st == dev_ok) {
    const int64_t *offset = g->offset;
    const uint8_t *broken_csr = g->broken_csr;
    int32_t *nbr = (int32_t *)d.nbr;
    uint8_t *brk = d.brk;
    each(n, [=] HD(int64_t i) {
      for (int64_t k = offset[i]; k < offset[i + 1]; ++k) {
        const int64_t a = k - offset[i];
        nbr[a * n + i] = nbr_csr[k];
        brk[a * n + i] = broken_csr[k];
      }
    });
    st = dev_launched();
    if (st == dev_ok) st = dev_sync();
  }
  if (!rc && st != dev_ok) rc = fail(g, "the families' layout on the device: %s", dev_message(st));
  dev_free(nbr_csr);
  if (rc) return rc;
  CHECK(g, dev_zero(d.sums, sizeof(double) * REDUCED * N), "the step's sums");
  return 0;
}

extern "C" peri_gpu *peri_gpu_create(const peri_gpu_problem *problem, char *err, size_t size) {
  peri_gpu *g = (peri_gpu *)calloc(1, sizeof *g);
  if (!g) {
    snprintf(err, size, "out of host memory");
    return NULL;
  }
  if (problem->n_materials > PERI_GPU_MAX_MATERIALS) {
    snprintf(err, size, "%d materials: the GPU path takes at most %d", problem->n_materials, PERI_GPU_MAX_MATERIALS);
    free(g);
    return NULL;
  }
  if (create(g, problem) != 0) {
    snprintf(err, size, "%s", g->err);
    peri_gpu_free(g);
    return NULL;
  }
  return g;
}

extern "C" int peri_gpu_upload(peri_gpu *g, const double *u, const double *v, const double *f, const double *b_ext,
                               const double *s0_node, const double *step_load) {
  Dev &d = g->d;
  if (upload3(g, d.u0, d.u1, d.u2, u, "the displacements") || upload3(g, d.v0, d.v1, d.v2, v, "the velocities") ||
      upload3(g, d.f0, d.f1, d.f2, f, "the forces") || upload3(g, d.e0, d.e1, d.e2, b_ext, "the loads") ||
      upload3(g, d.l0, d.l1, d.l2, step_load, "the step load"))
    return -1;
  if (s0_node && upload(g, d.s0_node, s0_node, sizeof(double) * (size_t)d.n, "the critical stretches")) return -1;
  return 0;
}

extern "C" int peri_gpu_set_loads(peri_gpu *g, const double *b_ext) {
  return upload3(g, g->d.e0, g->d.e1, g->d.e2, b_ext, "the loads");
}

extern "C" int peri_gpu_start(peri_gpu *g, const double centre[3], bool force, bool step_load) {
  const Dev d = g->d;
  for (int k = 0; k < 3; ++k) g->centre[k] = centre ? centre[k] : 0.0;
  loads(g);
  if (force) internal_force(g);
  /* the step load of the present state (explicit.c external_load): b on free components, the
   * reaction -f on prescribed ones (rho (v - v) / dt - f) */
  if (step_load)
    each(d.n, [=] HD(int64_t i) {
      for (int k = 0; k < 3; ++k) {
        const double f = *(comp(d.f0, d.f1, d.f2, k) + i), b = *(comp(d.b0, d.b1, d.b2, k) + i);
        const double v = *(comp(d.v0, d.v1, d.v2, k) + i);
        const double rho = d.mat[MATERIAL_ROWS * d.material[i] + MAT_DENSITY];
        *(comp(d.l0, d.l1, d.l2, k) + i) = d.held_mask[i] & (1u << k) ? rho * (v - v) / d.dt - f : b;
      }
    });
  CHECK(g, dev_launched(), "the first force");
  CHECK(g, dev_sync(), "the first force");
  return 0;
}

extern "C" int peri_gpu_step(peri_gpu *g, const double *held, const double centre[3], peri_gpu_step_sums *sums) {
  const double t0 = now_seconds();
  const Dev d = g->d;
  const int64_t hc = g->held_count;
  const int32_t *held_node = g->held_node;
  double *held_old = g->held_old, *held_new = g->held_new;
  const double dt = d.dt;
  /* the first half: the held nodes' state kept, then the half kick and drift of the free
   * components (explicit.c kick_and_drift) */
  each(hc, [=] HD(int64_t h) {
    const int64_t i = held_node[h];
    for (int k = 0; k < 3; ++k) {
      held_old[6 * h + k] = *(comp(d.u0, d.u1, d.u2, k) + i);
      held_old[6 * h + 3 + k] = *(comp(d.v0, d.v1, d.v2, k) + i);
    }
  });
  each(d.n, [=] HD(int64_t i) {
    const uint8_t held_i = d.held_mask[i];
    for (int k = 0; k < 3; ++k) {
      if (held_i & (1u << k)) continue;
      double *v = comp(d.v0, d.v1, d.v2, k) + i, *u = comp(d.u0, d.u1, d.u2, k) + i;
      const double a = (*(comp(d.f0, d.f1, d.f2, k) + i) + *(comp(d.b0, d.b1, d.b2, k) + i)) * d.inv_rho[i] -
                       d.damping * *v;
      *v += 0.5 * dt * a;
      *u += dt * *v;
    }
  });
  /* the prescribed components' new values (evaluated by the host: peri_apply_prescribed_motion) */
  if (hc > 0) {
    CHECK(g, dev_to(held_new, held, sizeof(double) * 6 * (size_t)hc), "the prescribed motion");
    each(hc, [=] HD(int64_t h) {
      const int64_t i = held_node[h];
      for (int k = 0; k < 3; ++k)
        if (d.held_mask[i] & (1u << k)) {
          *(comp(d.u0, d.u1, d.u2, k) + i) = held_new[6 * h + k];
          *(comp(d.v0, d.v1, d.v2, k) + i) = held_new[6 * h + 3 + k];
        }
    });
  }
  for (int k = 0; k < 3; ++k) g->centre[k] = centre ? centre[k] : 0.0;
  loads(g);
  internal_force(g);
  /* the second half kick, the step's load and work by the trapezoid rule, the kinetic energy
   * of the half-step velocities and the finiteness check (explicit.c) */
  each(d.n, [=] HD(int64_t i) {
    const uint8_t held_i = d.held_mask[i];
    const double *old = NULL;
    if (held_i) { /* the slot of node i among the held nodes: they are in node order */
      int64_t lo = 0, hi = hc - 1;
      while (lo < hi) {
        const int64_t mid = (lo + hi) / 2;
        if (held_node[mid] < i) lo = mid + 1;
        else hi = mid;
      }
      old = held_old + 6 * lo;
    }
    double work = 0.0, v2 = 0.0, nonfinite = 0.0;
    for (int k = 0; k < 3; ++k) {
      double *v = comp(d.v0, d.v1, d.v2, k) + i, *u = comp(d.u0, d.u1, d.u2, k) + i,
             *l = comp(d.l0, d.l1, d.l2, k) + i;
      const double f = *(comp(d.f0, d.f1, d.f2, k) + i), b = *(comp(d.b0, d.b1, d.b2, k) + i);
      double load, du;
      if (!(held_i & (1u << k))) {
        const double v_half = *v, a = (f + b) * d.inv_rho[i];
        *v = d.damping_divisor == 1.0 ? v_half + 0.5 * dt * a : (v_half + 0.5 * dt * a) / d.damping_divisor;
        load = b;
        du = dt * v_half;
        v2 += v_half * v_half;
      } else {
        v2 += *v * *v;
        load = d.mat[MATERIAL_ROWS * d.material[i] + MAT_DENSITY] * (*v - old[3 + k]) / dt - f;
        du = *u - old[k];
      }
      work += 0.5 * (*l + load) * du * d.V[i];
      *l = load;
      if (!(fabs(*u) < 1e100 && fabs(*v) < 1e100)) nonfinite += 1.0;
    }
    d.sums[SUM_WORK * d.n + i] = work;
    d.sums[SUM_KINETIC * d.n + i] = d.half_mass[i] * v2;
    d.sums[SUM_NONFINITE * d.n + i] = nonfinite;
  });
  CHECK(g, dev_launched(), "a step's kernels");
  double out[REDUCED];
  if (reduce_rows(g, out) != 0) return -1;
  sums->work = out[SUM_WORK], sums->kinetic = out[SUM_KINETIC], sums->nonfinite = out[SUM_NONFINITE];
  for (int k = 0; k < 3; ++k) sums->indenter_force[k] = out[SUM_INDENTER_X + k];
  g->step_seconds += now_seconds() - t0;
  return 0;
}

extern "C" int peri_gpu_download(peri_gpu *g, double *u, double *v, double *f, double *b, uint8_t *broken,
                                 double *s0_node, double *step_load) {
  Dev &d = g->d;
  if ((u && download3(g, u, d.u0, d.u1, d.u2, "the displacements")) ||
      (v && download3(g, v, d.v0, d.v1, d.v2, "the velocities")) ||
      (f && download3(g, f, d.f0, d.f1, d.f2, "the forces")) || (b && download3(g, b, d.b0, d.b1, d.b2, "the loads")) ||
      (step_load && download3(g, step_load, d.l0, d.l1, d.l2, "the step load")))
    return -1;
  if (s0_node) CHECK(g, dev_from(s0_node, d.s0_node, sizeof(double) * (size_t)d.n), "the critical stretches");
  if (broken) {
    const int64_t n = d.n;
    const int64_t *offset = g->offset;
    uint8_t *csr = g->broken_csr;
    const uint8_t *brk = d.brk;
    each(n, [=] HD(int64_t i) {
      for (int64_t k = offset[i]; k < offset[i + 1]; ++k) csr[k] = brk[(k - offset[i]) * n + i];
    });
    CHECK(g, dev_launched(), "the broken flags");
    CHECK(g, dev_from(broken, csr, (size_t)g->n_bonds), "the broken flags");
  }
  return 0;
}

extern "C" const char *peri_gpu_error(const peri_gpu *g) { return g->err; }

extern "C" void peri_gpu_memory(const peri_gpu *g, double *bytes, double *per_bond) {
  *bytes = g->bytes;
  *per_bond = g->n_bonds > 0 ? g->bytes / (double)g->n_bonds : 0.0;
}

extern "C" double peri_gpu_step_seconds(peri_gpu *g) {
  dev_sync();
  return g->step_seconds;
}

extern "C" void peri_gpu_free(peri_gpu *g) {
  if (!g) return;
  Dev &d = g->d;
  void *all[] = {(void *)d.x0, (void *)d.x1, (void *)d.x2, (void *)d.p0, (void *)d.p1, (void *)d.p2, (void *)d.V, (void *)d.inv_rho, (void *)d.half_mass,
                 (void *)d.wvol, d.u0, d.u1, d.u2, d.v0, d.v1, d.v2, d.f0, d.f1, d.f2, d.b0, d.b1, d.b2, d.e0, d.e1,
                 d.e2, d.l0, d.l1, d.l2, d.s0_node, d.smin, d.D, d.B, (void *)d.count, (void *)d.material,
                 (void *)d.nbr, d.brk, (void *)d.no_fail, (void *)d.held_mask, (void *)d.mat, (void *)d.pair_s0,
                 d.sums, g->held_node, g->held_old, g->held_new, g->offset, g->broken_csr, g->level[0],
                 g->level[1]};
  for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k) dev_free(all[k]);
  free(g);
}
