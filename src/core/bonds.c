/* Bond families by a cell-list neighbour search, stored in compressed sparse rows. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/bonds.h"
#include "peri/error.h"

/* Relative tolerance so that lattice points exactly at the cutoff are neighbours. */
#define CUTOFF_RTOL 1e-12

double peri_partial_volume_factor(peri_partial_volume rule, double r, double delta, double dx) {
  double rmax = delta * (1 + CUTOFF_RTOL);
  if (rule == PERI_PV_NONE || !(dx > 0)) return r <= rmax ? 1.0 : 0.0;
  if (rule == PERI_PV_LAMMPS && r > rmax) return 0.0;
  if (r <= delta - 0.5 * dx) return 1.0;
  double beta = 0.5 + (delta - r) / dx;
  if (beta > 1) beta = 1;
  return beta > 0 ? beta : 0.0;
}

double peri_influence_value(peri_influence w, double r, double delta) {
  switch (w) {
  case PERI_INFLUENCE_CONSTANT: return 1.0;
  case PERI_INFLUENCE_INVERSE: return 1.0 / r;
  case PERI_INFLUENCE_GAUSSIAN: return exp(-(r * r) / (delta * delta));
  }
  return 1.0;
}

static double cutoff_of(const peri_family_params *fp) {
  if (fp->rule == PERI_PV_LINEAR && fp->spacing > 0) return fp->horizon + 0.5 * fp->spacing;
  return fp->horizon;
}

/* Bins of the cell list; items of a bin are in ascending node order (counting sort). */
typedef struct {
  int dim;
  double lo[3], h;
  int64_t nb[3];
  int64_t *start; /* [nbins+1] */
  int32_t *item;  /* [n] */
} cells;

static int64_t cell_coord(const cells *c, double x, int d) {
  int64_t k = (int64_t)floor((x - c->lo[d]) / c->h);
  if (k < 0) k = 0;
  if (k >= c->nb[d]) k = c->nb[d] - 1;
  return k;
}

static void cells_build(cells *c, const peri_particles *p, double cutoff) {
  int32_t n = p->n;
  int dim = p->dim;
  double hi[3] = {0, 0, 0};
  c->dim = dim;
  for (int d = 0; d < 3; d++) c->lo[d] = 0;
  for (int d = 0; d < dim && n > 0; d++) {
    c->lo[d] = hi[d] = p->x[d];
    for (int32_t i = 1; i < n; i++) {
      double v = p->x[3 * i + d];
      if (v < c->lo[d]) c->lo[d] = v;
      if (v > hi[d]) hi[d] = v;
    }
  }
  /* Bins of half the cutoff: a search visits 5^dim of them, skipping those whose box lies beyond
   * the cutoff (in 3D 84 of the 125 on average), and tests 39% of the candidates that bins of the
   * cutoff (3^dim of them) give.
   * Bins may be larger (still correct: scan reaches as many bins as the cutoff spans); keep
   * their number near n so that a sparse cloud with a tiny horizon cannot ask for an absurd
   * number of bins. */
  c->h = cutoff > 0 ? 0.5 * cutoff : 1.0;
  double limit = 2.0 * (double)n + 64;
  for (;;) {
    double total = 1;
    for (int d = 0; d < 3; d++) {
      c->nb[d] = 1;
      if (d < dim) {
        double m = floor((hi[d] - c->lo[d]) / c->h) + 1;
        c->nb[d] = m > 1e15 ? (int64_t)1e15 : (int64_t)m;
      }
      total *= (double)c->nb[d];
    }
    if (total <= limit) break;
    c->h *= 2;
  }
  int64_t nbins = c->nb[0] * c->nb[1] * c->nb[2];
  c->start = peri_calloc((size_t)nbins + 1, sizeof(int64_t));
  c->item = peri_malloc(sizeof(int32_t) * (size_t)(n > 0 ? n : 1));
  int64_t *bin = peri_malloc(sizeof(int64_t) * (size_t)(n > 0 ? n : 1));
  for (int32_t i = 0; i < n; i++) {
    int64_t b = 0;
    for (int d = dim - 1; d >= 0; d--) b = b * c->nb[d] + cell_coord(c, p->x[3 * i + d], d);
    bin[i] = b;
    c->start[b + 1]++;
  }
  for (int64_t b = 0; b < nbins; b++) c->start[b + 1] += c->start[b];
  int64_t *fill = peri_malloc(sizeof(int64_t) * (size_t)(nbins + 1));
  memcpy(fill, c->start, sizeof(int64_t) * (size_t)(nbins + 1));
  for (int32_t i = 0; i < n; i++) c->item[fill[bin[i]]++] = i;
  free(fill);
  free(bin);
}

static void cells_free(cells *c) {
  free(c->start);
  free(c->item);
}

/* The squared distance from x to the slab of bin k along dimension d (0 inside), the slab
 * widened by a hair so that rounding in cell_coord cannot put a node outside its bin's slab. */
static double slab_gap2(const cells *c, int d, int64_t k, double x) {
  if (d >= c->dim) return 0.0;
  const double hair = 1e-9 * c->h, lo = c->lo[d] + (double)k * c->h - hair, hi = lo + c->h + 2.0 * hair;
  const double gap = x < lo ? lo - x : x > hi ? x - hi : 0.0;
  return gap * gap;
}

/* Visits the candidate neighbours of node i (the nodes of the bins within the cutoff's reach
 * whose box is within the cutoff), keeping those within the cutoff with beta > 0. With
 * out == NULL only counts. */
static int64_t scan(const cells *c, const peri_particles *p, const peri_family_params *fp,
                    double rcut, int32_t i, int32_t *out, int64_t *n_coincident) {
  const double *xi = p->x + 3 * (size_t)i;
  int64_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  const int64_t reach = (int64_t)ceil(rcut / c->h); /* bins the cutoff spans */
  for (int d = 0; d < c->dim; d++) {
    int64_t k = cell_coord(c, xi[d], d);
    lo[d] = k > reach ? k - reach : 0;
    hi[d] = k + reach < c->nb[d] ? k + reach : c->nb[d] - 1;
  }
  int64_t count = 0;
  double r2max = rcut * rcut, r2sure = fp->horizon * fp->horizon;
  for (int64_t k2 = lo[2]; k2 <= hi[2]; k2++) {
    const double gap2 = slab_gap2(c, 2, k2, xi[2]);
    if (gap2 > r2max) continue;
    for (int64_t k1 = lo[1]; k1 <= hi[1]; k1++) {
      const double gap1 = gap2 + slab_gap2(c, 1, k1, xi[1]);
      if (gap1 > r2max) continue;
      for (int64_t k0 = lo[0]; k0 <= hi[0]; k0++) {
        if (gap1 + slab_gap2(c, 0, k0, xi[0]) > r2max) continue; /* the bin's box is beyond the cutoff */
        int64_t b = (k2 * c->nb[1] + k1) * c->nb[0] + k0;
        for (int64_t t = c->start[b]; t < c->start[b + 1]; t++) {
          int32_t j = c->item[t];
          if (j == i) continue;
          const double *xj = p->x + 3 * (size_t)j;
          double r2 = 0;
          for (int d = 0; d < 3; d++) r2 += (xj[d] - xi[d]) * (xj[d] - xi[d]);
          if (r2 > r2max) continue;
          /* Coincident nodes would give a zero-length bond (infinite stretch). */
          if (r2 == 0) {
            if (n_coincident) (*n_coincident)++;
            continue;
          }
          if (fp->node_horizon) { /* a horizon per node: bonded within the larger of the two */
            const double d = fmax(fp->node_horizon[i], fp->node_horizon[j]);
            if (peri_partial_volume_factor(fp->rule, sqrt(r2), d, fp->spacing) <= 0) continue;
          }
          /* Within delta every rule gives beta >= 1/2; only the LINEAR tail can reach 0. */
          else if (r2 > r2sure &&
              peri_partial_volume_factor(fp->rule, sqrt(r2), fp->horizon, fp->spacing) <= 0)
            continue;
          if (out) out[count] = j;
          count++;
        }
      }
    }
  }
  return count;
}

/* Sorts a family in place: quicksort (median of three) down to short runs, then insertion
 * sort. Inline comparisons: the library qsort's callback dominated the family search. */
static void sort_family(int32_t *a, int64_t n) {
  while (n > 24) {
    const int32_t x = a[0], y = a[n / 2], z = a[n - 1];
    const int32_t pivot = x < y ? (y < z ? y : (x < z ? z : x)) : (x < z ? x : (y < z ? z : y));
    int64_t i = 0, j = n - 1;
    for (;;) {
      while (a[i] < pivot) ++i;
      while (a[j] > pivot) --j;
      if (i >= j) break;
      const int32_t tmp = a[i];
      a[i++] = a[j];
      a[j--] = tmp;
    }
    /* recurse into the smaller part, loop on the larger: O(log n) depth */
    if (j + 1 < n - j - 1) {
      sort_family(a, j + 1);
      a += j + 1;
      n -= j + 1;
    } else {
      sort_family(a + j + 1, n - j - 1);
      n = j + 1;
    }
  }
  for (int64_t i = 1; i < n; ++i) {
    const int32_t v = a[i];
    int64_t k = i;
    for (; k > 0 && a[k - 1] > v; --k) a[k] = a[k - 1];
    a[k] = v;
  }
}

/* Sorts a family of distinct indices: through a bitmap of their range when it is short (a
 * node's neighbours in the nodes' order span a few hundred words: set a bit per index, read the
 * set bits in order), else sort_family. `bits` is the caller's zeroed scratch of `words`
 * words, left zeroed. */
static void sort_distinct(int32_t *a, int64_t n, uint64_t *bits, int64_t words) {
  if (n < 2) return;
  int32_t lo = a[0], hi = a[0];
  for (int64_t k = 1; k < n; ++k) {
    lo = a[k] < lo ? a[k] : lo;
    hi = a[k] > hi ? a[k] : hi;
  }
  const int64_t span = ((int64_t)hi - lo) / 64 + 1;
  if (span > words || span > 8 * n) {
    sort_family(a, n);
    return;
  }
  for (int64_t k = 0; k < n; ++k) bits[(a[k] - lo) >> 6] |= 1ull << ((a[k] - lo) & 63);
  int64_t out = 0;
  for (int64_t w = 0; w < span; ++w)
    for (uint64_t word = bits[w]; word; word &= word - 1) a[out++] = lo + (int32_t)(64 * w + __builtin_ctzll(word));
  memset(bits, 0, sizeof(uint64_t) * (size_t)span);
}

void peri_bonds_build(peri_bonds *b, const peri_particles *p, const peri_family_params *fp) {
  memset(b, 0, sizeof *b);
  int32_t n_own = p->n_owned;
  b->n_nodes = n_own;
  b->family = *fp;
  b->offset = peri_calloc((size_t)n_own + 1, sizeof(int64_t));
  double rcut = cutoff_of(fp) * (1 + CUTOFF_RTOL);
  cells c;
  cells_build(&c, p, rcut);

  /* Pass 1: family sizes. Each node writes only its own slot, so the result does not
   * depend on the number of threads. */
  int64_t n_coincident = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : n_coincident)
  for (int32_t i = 0; i < n_own; i++) {
    int64_t nc = 0;
    b->offset[i + 1] = scan(&c, p, fp, rcut, i, NULL, &nc);
    n_coincident += nc;
  }
  if (n_coincident > 0)
    peri_warning("%lld pairs of nodes coincide; they are not bonded", (long long)n_coincident / 2);
  for (int32_t i = 0; i < n_own; i++) b->offset[i + 1] += b->offset[i];
  int64_t nb = b->offset[n_own];
  b->n_bonds = nb;
  size_t m = (size_t)(nb > 0 ? nb : 1);
  b->neighbor = peri_malloc(sizeof(int32_t) * m);
  b->broken = peri_calloc(m, 1);

  /* Pass 2: fill each family and sort it by index. Reference length, partial volume and
   * influence are not stored: kernels evaluate them from the reference positions
   * (peri_bond_xi, peri_bonds_beta, peri_bonds_omega), which costs less than reading them. */
#pragma omp parallel
  {
    enum { SORT_WORDS = 4096 }; /* a range of 262,144 indices */
    uint64_t *bits = peri_calloc(SORT_WORDS, sizeof(uint64_t));
#pragma omp for schedule(dynamic, 256)
    for (int32_t i = 0; i < n_own; i++) {
      int64_t o = b->offset[i], cnt = b->offset[i + 1] - o;
      scan(&c, p, fp, rcut, i, b->neighbor + o, NULL);
      sort_distinct(b->neighbor + o, cnt, bits, SORT_WORDS);
    }
    free(bits);
  }
  cells_free(&c);
}

int64_t peri_bonds_find(const peri_bonds *b, int32_t i, int32_t j) {
  if (i < 0 || i >= b->n_nodes) return -1;
  int64_t lo = b->offset[i], hi = b->offset[i + 1] - 1;
  while (lo <= hi) {
    int64_t mid = lo + (hi - lo) / 2;
    int32_t v = b->neighbor[mid];
    if (v == j) return mid;
    if (v < j)
      lo = mid + 1;
    else
      hi = mid - 1;
  }
  return -1;
}

int64_t peri_bonds_keep_within(peri_bonds *b, const int32_t *label) {
  int64_t kept = 0;
  for (int32_t i = 0; i < b->n_nodes; i++) { /* in place: kept never passes the read position */
    const int64_t from = b->offset[i], to = b->offset[i + 1];
    b->offset[i] = kept;
    for (int64_t k = from; k < to; k++)
      if (label[b->neighbor[k]] == label[i]) {
        b->neighbor[kept] = b->neighbor[k];
        b->broken[kept] = b->broken[k];
        kept++;
      }
  }
  const int64_t removed = b->n_bonds - kept;
  b->offset[b->n_nodes] = kept;
  b->n_bonds = kept;
  return removed;
}

double peri_bonds_bytes_per_bond(const peri_bonds *b) {
  if (b->n_bonds <= 0) return 0.0;
  return (double)(sizeof *b->neighbor + sizeof *b->broken);
}

void peri_bonds_free(peri_bonds *b) {
  free(b->offset);
  free(b->neighbor);
  free(b->broken);
  free(b->surface_G);
  free(b->surface_D);
  free(b->surface_G_rev);
  free(b->surface_D_rev);
  memset(b, 0, sizeof *b);
}

long peri_broken_count(const peri_bonds *b) {
  long count = 0;
#pragma omp parallel for reduction(+ : count) schedule(static)
  for (int64_t k = 0; k < b->n_bonds; ++k) count += b->broken[k];
  return count;
}

/* FNV-1a over the CSR arrays, value by value least significant byte first. */
uint64_t peri_bonds_hash(const peri_bonds *b, int32_t n) {
  uint64_t h = 1469598103934665603ULL; /* FNV-1a 64-bit offset basis and prime (Fowler, Noll, Vo) */
  const uint64_t prime = 1099511628211ULL;
  for (int32_t i = 0; i <= n; ++i) {
    uint64_t v = (uint64_t)b->offset[i];
    for (int k = 0; k < 8; ++k) h = (h ^ ((v >> (8 * k)) & 0xff)) * prime;
  }
  for (int64_t k = 0; k < b->offset[n]; ++k) {
    uint32_t v = (uint32_t)b->neighbor[k];
    for (int c = 0; c < 4; ++c) h = (h ^ ((v >> (8 * c)) & 0xff)) * prime;
  }
  return h;
}

int64_t peri_bonds_longest_family(const peri_bonds *b, int32_t n) {
  int64_t longest = 0;
  for (int32_t i = 0; i < n; ++i)
    if (b->offset[i + 1] - b->offset[i] > longest) longest = b->offset[i + 1] - b->offset[i];
  return longest;
}
