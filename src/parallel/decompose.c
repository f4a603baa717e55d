/* Domain decomposition (include/peri/decompose.h, docs/parallel.md; Ebrahimi 2020 ch. 7):
 * every rank holds the whole built simulation, chooses its contiguous range of the Morton
 * order with equal bond counts per rank, and keeps its owned nodes, then its ghosts (the
 * nodes its families reference) in global order. Families keep their global order, so every
 * sum over a family runs in the same order as in a single process and the results agree
 * bit for bit. */
#include <stdlib.h>
#include <string.h>
#include "peri/bond_halo.h"
#include "peri/comm.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/horizon_field.h"
#include "peri/thermal.h"

/* out[k] = src[ids[k]] for elements of `size` bytes; NULL stays NULL. */
static void *take(const void *src, size_t size, const int32_t *ids, int32_t n) {
  if (!src) return NULL;
  char *out = peri_malloc(size * (size_t)(n > 0 ? n : 1));
  for (int32_t k = 0; k < n; ++k) memcpy(out + size * (size_t)k, (const char *)src + size * (size_t)ids[k], size);
  return out;
}

/* Replaces *array (a per-node array of `size`-byte elements) by its local subset. */
#define LOCALIZE(array, size, ids, n)            \
  do {                                           \
    void *subset_ = take((array), (size), ids, n); \
    free(array);                                 \
    (array) = subset_;                           \
  } while (0)

/* A contiguous slice of a per-bond array, at a cache-line boundary (error.h); NULL stays NULL. */
static void *slice(const void *src, size_t size, int64_t from, int64_t count) {
  if (!src) return NULL;
  void *out = peri_malloc_aligned(size * (size_t)(count > 0 ? count : 1));
  if (count > 0) memcpy(out, (const char *)src + size * (size_t)from, size * (size_t)count);
  return out;
}

#define SLICE(array, size, from, count)            \
  do {                                             \
    void *slice_ = slice((array), (size), from, count); \
    free(array);                                   \
    (array) = slice_;                              \
  } while (0)

/* Rank boundaries on sum-block boundaries, with equal bond counts (the work of a step is
 * proportional to the bonds). */
static void split(const peri_bonds *b, int64_t n, int size, int64_t *first) {
  const int64_t n_blocks = (n + PERI_SUM_BLOCK - 1) / PERI_SUM_BLOCK;
  const double total = (double)b->offset[n];
  first[0] = 0;
  int64_t block = 0;
  for (int r = 1; r < size; ++r) {
    const double target = total * r / size;
    /* the block boundary whose cumulative bond count is nearest the target */
    while (block < n_blocks) {
      const int64_t end = (block + 1) * PERI_SUM_BLOCK < n ? (block + 1) * PERI_SUM_BLOCK : n;
      const double here = (double)b->offset[block * PERI_SUM_BLOCK], next = (double)b->offset[end];
      if (next > target) {
        if (target - here > next - target) ++block;
        break;
      }
      ++block;
    }
    int64_t at = block * PERI_SUM_BLOCK < n ? block * PERI_SUM_BLOCK : n;
    first[r] = at > first[r - 1] ? at : first[r - 1];
  }
  first[size] = n;
}

static int owner_of(const int64_t *first, int size, int64_t g) {
  int lo = 0, hi = size - 1;
  while (lo < hi) { /* last rank r with first[r] <= g (empty ranks share a boundary) */
    int mid = (lo + hi + 1) / 2;
    if (first[mid] <= g) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

/* The messages of the halo: ghosts received from each owner, and the owned nodes that each
 * other rank references (found by scanning that rank's families in the global bonds, and the
 * nodes its equations reach beyond them, reach_offset/reach_node, NULL when none). */
static void build_halo(peri_decomposition *d, const peri_bonds *global, const int64_t *reach_offset,
                       const int32_t *reach_node, int32_t n_owned, int32_t n_local) {
  peri_halo *h = &d->halo;
  const int64_t g0 = d->first[d->rank], g1 = d->first[d->rank + 1];
  int32_t *recv_count = peri_calloc((size_t)d->size, sizeof(int32_t));
  int32_t *recv_start = peri_calloc((size_t)d->size, sizeof(int32_t));
  for (int32_t l = n_local - 1; l >= n_owned; --l) {
    int q = owner_of(d->first, d->size, d->global_id[l]);
    recv_count[q]++;
    recv_start[q] = l;
  }
  uint8_t *mark = peri_calloc((size_t)(n_owned > 0 ? n_owned : 1), 1);
  int64_t *send_count = peri_calloc((size_t)d->size, sizeof(int64_t));
  int32_t *send_node = NULL;
  int64_t n_send = 0, cap = 0;
  int *neighbor = peri_malloc(sizeof(int) * (size_t)d->size);
  int n_neighbors = 0;
  for (int q = 0; q < d->size; ++q) {
    if (q == d->rank) continue;
    memset(mark, 0, (size_t)(n_owned > 0 ? n_owned : 1));
    for (int64_t k = global->offset[d->first[q]]; k < global->offset[d->first[q + 1]]; ++k) {
      const int64_t j = global->neighbor[k];
      if (j >= g0 && j < g1) mark[j - g0] = 1;
    }
    for (int64_t k = reach_offset ? reach_offset[d->first[q]] : 0; reach_offset && k < reach_offset[d->first[q + 1]]; ++k) {
      const int64_t j = reach_node[k];
      if (j >= g0 && j < g1) mark[j - g0] = 1;
    }
    int64_t before = n_send;
    for (int32_t i = 0; i < n_owned; ++i) {
      if (!mark[i]) continue;
      if (n_send == cap) {
        cap = cap ? 2 * cap : 1024;
        send_node = peri_realloc(send_node, sizeof(int32_t) * (size_t)cap);
      }
      send_node[n_send++] = i;
    }
    send_count[q] = n_send - before;
    if (send_count[q] > 0 || recv_count[q] > 0) neighbor[n_neighbors++] = q;
  }
  h->n_neighbors = n_neighbors;
  h->rank = peri_malloc(sizeof(int) * (size_t)(n_neighbors + 1));
  h->recv_start = peri_malloc(sizeof(int32_t) * (size_t)(n_neighbors + 1));
  h->recv_count = peri_malloc(sizeof(int32_t) * (size_t)(n_neighbors + 1));
  h->send_start = peri_calloc((size_t)n_neighbors + 1, sizeof(int64_t));
  for (int m = 0; m < n_neighbors; ++m) {
    const int q = neighbor[m];
    h->rank[m] = q;
    h->recv_start[m] = recv_start[q];
    h->recv_count[m] = recv_count[q];
    h->send_start[m + 1] = h->send_start[m] + send_count[q];
  }
  h->send_node = send_node ? send_node : peri_malloc(sizeof(int32_t));
  h->send_buffer = peri_malloc(sizeof(double) * PERI_HALO_MAX_COMPONENTS * (size_t)(n_send > 0 ? n_send : 1));
  h->requests = peri_comm_requests(2 * n_neighbors);
  free(mark);
  free(send_count);
  free(recv_count);
  free(recv_start);
  free(neighbor);
}

static void exchange(peri_sim *s, double *field, int ncomp) { peri_halo_exchange(&s->par.dd->halo, field, ncomp); }

static void localize_particles(peri_particles *p, const int32_t *ids, int32_t n_local, int32_t n_owned) {
  LOCALIZE(p->x, 3 * sizeof(double), ids, n_local);
  LOCALIZE(p->u, 3 * sizeof(double), ids, n_local);
  LOCALIZE(p->v, 3 * sizeof(double), ids, n_local);
  LOCALIZE(p->f, 3 * sizeof(double), ids, n_local);
  LOCALIZE(p->b, 3 * sizeof(double), ids, n_local);
  LOCALIZE(p->volume, sizeof(double), ids, n_local);
  LOCALIZE(p->material, sizeof(int32_t), ids, n_local);
  LOCALIZE(p->block, sizeof(int32_t), ids, n_local);
  LOCALIZE(p->flags, sizeof(uint8_t), ids, n_local);
  LOCALIZE(p->damage, sizeof(double), ids, n_local);
  LOCALIZE(p->theta, sizeof(double), ids, n_local);
  LOCALIZE(p->wvol, sizeof(double), ids, n_local);
  LOCALIZE(p->pstate, sizeof(double), ids, n_local);
  LOCALIZE(p->energy, sizeof(double), ids, n_local);
  LOCALIZE(p->smin, sizeof(double), ids, n_local);
  LOCALIZE(p->s0_bound, sizeof(double), ids, n_local);
  /* p->coef (the models' per-node coefficients, 1 or 2 per node) keeps its global size: the
   * models rewrite it at every force evaluation and the halo brings the ghosts' values */
  p->n = n_local;
  p->n_owned = n_owned;
  p->capacity = n_local;
}

/* Families of the owned nodes: a contiguous run of the global bonds, neighbours renamed to
 * local indices, in the global order. */
static void localize_bonds(peri_bonds *b, int64_t g0, int64_t g1, const int32_t *local_of) {
  const int32_t n_owned = (int32_t)(g1 - g0);
  const int64_t from = b->offset[g0], count = b->offset[g1] - from;
  int64_t *offset = peri_malloc(sizeof(int64_t) * ((size_t)n_owned + 1));
  for (int32_t i = 0; i <= n_owned; ++i) offset[i] = b->offset[g0 + i] - from;
  int32_t *neighbor = peri_malloc(sizeof(int32_t) * (size_t)(count > 0 ? count : 1));
  for (int64_t k = 0; k < count; ++k) neighbor[k] = local_of[b->neighbor[from + k]];
  free(b->offset);
  free(b->neighbor);
  b->offset = offset;
  b->neighbor = neighbor;
  SLICE(b->broken, sizeof(uint8_t), from, count);
  /* the surface-correction factors, computed on the whole body before the split */
  SLICE(b->surface_G, sizeof(double), from, count);
  SLICE(b->surface_D, sizeof(double), from, count);
  SLICE(b->surface_G_rev, sizeof(double), from, count);
  SLICE(b->surface_D_rev, sizeof(double), from, count);
  b->n_nodes = n_owned;
  b->n_bonds = count;
}

/* A horizon per node (docs/variable_horizon.md): on ranks only full peridynamics runs (deck
 * check), whose force reads each bond's constants or state and each node's and ghost's horizon,
 * constant and critical-stretch factor; the reverse bonds are dropped (a node computes the other
 * end's state of its bonds itself, src/model/variable_horizon.c). */
static void localize_horizon(peri_horizon_field *h, const int32_t *ids, int32_t n_local, int64_t from, int64_t count) {
  if (!h) return;
  LOCALIZE(h->delta, sizeof(double), ids, n_local);
  LOCALIZE(h->s0_scale, sizeof(double), ids, n_local);
  LOCALIZE(h->coupled, sizeof(uint8_t), ids, n_local);
  LOCALIZE(h->node_constant, sizeof(double), ids, n_local);
  SLICE(h->bond_length, sizeof(double), from, count);
  SLICE(h->bond_pair_state, sizeof(double), from, count);
  SLICE(h->bond_pair, sizeof(double), from, count);
  SLICE(h->bond_critical, sizeof(double), from, count);
  SLICE(h->state, sizeof(double), from, count);
  free(h->reverse), h->reverse = NULL;
  h->n = n_local;
}

static void localize_regions(peri_sim *s, int64_t g0, int64_t g1) {
  for (int r = 0; r < s->cond.n_regions; ++r) {
    peri_region *reg = &s->cond.regions[r];
    int32_t kept = 0;
    for (int32_t a = 0; a < reg->count; ++a)
      if (reg->nodes[a] >= g0 && reg->nodes[a] < g1) reg->nodes[kept++] = (int32_t)(reg->nodes[a] - g0);
    reg->count = kept;
  }
}

/* The heat operator: per-node arrays to local nodes, per-bond arrays to the owned families,
 * the growing-crack bond list to local bond indices (in the same cut order). */
static void localize_thermal(peri_sim *s, const int32_t *ids, int32_t n_local, int32_t n_owned, int64_t from,
                             int64_t count) {
  peri_thermal *th = s->thermal;
  th->n = n_owned;
  LOCALIZE(th->T, sizeof(double), ids, n_local);
  LOCALIZE(th->T_ref, sizeof(double), ids, n_local);
  LOCALIZE(th->rhoc, sizeof(double), ids, n_local);
  LOCALIZE(th->area, sizeof(double), ids, n_local);
  LOCALIZE(th->source, sizeof(double), ids, n_local);
  LOCALIZE(th->sink, sizeof(double), ids, n_local);
  LOCALIZE(th->fixed, sizeof(uint8_t), ids, n_local);
  LOCALIZE(th->alg_axis, sizeof(int8_t), ids, n_local);
  LOCALIZE(th->alg_bc, sizeof(int32_t), ids, n_local);
  LOCALIZE(th->flux, 3 * sizeof(double), ids, n_local);
  for (int k = 0; k < 6; ++k) LOCALIZE(th->work[k], sizeof(double), ids, n_local);
  SLICE(th->H, sizeof(double), from, count);
  SLICE(th->Hs, sizeof(double), from, count);
  if (th->own_cut) SLICE(th->cut, sizeof(uint8_t), from, count);
  else th->cut = s->disc.bonds.broken;
  int64_t kept = 0, next = 0;
  for (int64_t a = 0; a < th->n_growing_bonds; ++a) {
    const int64_t k = th->growing_bond[a];
    if (k < from || k >= from + count) continue;
    if (a < th->growing_next) next = kept + 1;
    th->growing_bond[kept] = k - from;
    th->growing_time[kept++] = th->growing_time[a];
  }
  th->n_growing_bonds = kept;
  th->growing_next = next;
}

/* The deviatoric yield rule (docs/plasticity.md section 8): the reverse bond of each owned
 * bond as a local index; where the other end is a ghost, the bond's own index past the owned
 * bonds, the entry of the plastic terms into which the ghost's owner sends its term through
 * the bond halo. Needs the global families. */
static void localize_reverse(peri_sim *s, peri_decomposition *d) {
  const int64_t b0 = d->bond_first[d->rank], b1 = d->bond_first[d->rank + 1];
  d->bond_halo = peri_bond_halo_build(&s->disc.bonds, s->state.plastic_reverse, d->first, d->bond_first, d->rank, d->size);
  int64_t *reverse = peri_malloc(sizeof(int64_t) * (size_t)(b1 > b0 ? b1 - b0 : 1));
  for (int64_t k = b0; k < b1; ++k) {
    const int64_t r = s->state.plastic_reverse[k];
    reverse[k - b0] = r >= b0 && r < b1 ? r - b0 : (b1 - b0) + (k - b0);
  }
  free(s->state.plastic_reverse);
  s->state.plastic_reverse = reverse;
  SLICE(s->state.plastic_bond_weight, sizeof(double), b0, b1 - b0);
}

int peri_decompose(peri_sim *s) {
  const int size = peri_comm_size(), rank = peri_comm_rank();
  if (size == 1) return PERI_OK;
  if (s->state.plastic_slots.generation) { /* (the slices below are cut in bond order) */
    peri_error("internal: the bonds are divided among ranks after a force evaluation of the deviatoric yield rule");
    return PERI_ERR_RUN;
  }
  peri_particles *p = &s->disc.p;
  peri_bonds *b = &s->disc.bonds;
  peri_decomposition *d = peri_calloc(1, sizeof *d);
  d->rank = rank;
  d->size = size;
  d->n_global = p->n;
  d->n_bonds_global = b->n_bonds;
  d->first = peri_malloc(sizeof(int64_t) * ((size_t)size + 1));
  d->owned = peri_malloc(sizeof(int64_t) * (size_t)size);
  d->blocks = peri_malloc(sizeof(int64_t) * (size_t)size);
  split(b, p->n, size, d->first);
  for (int r = 0; r < size; ++r) {
    d->owned[r] = d->first[r + 1] - d->first[r];
    d->blocks[r] = (d->owned[r] + PERI_SUM_BLOCK - 1) / PERI_SUM_BLOCK;
  }
  /* checkpoints (docs/restart.md) hold the global bond order: each rank's families are one
   * run of it, and the file's bond hash is that of the global families */
  d->bond_first = peri_malloc(sizeof(int64_t) * ((size_t)size + 1));
  for (int r = 0; r <= size; ++r) d->bond_first[r] = b->offset[d->first[r]];
  if (s->out.checkpoint_every > 0) d->bond_hash = peri_bonds_hash(b, p->n);
  const int64_t g0 = d->first[rank], g1 = d->first[rank + 1];
  const int32_t n_owned = (int32_t)(g1 - g0);

  /* local nodes: owned, then ghosts in global order */
  int32_t *local_of = peri_malloc(sizeof(int32_t) * (size_t)(p->n > 0 ? p->n : 1));
  for (int32_t g = 0; g < p->n; ++g) local_of[g] = -1;
  for (int64_t g = g0; g < g1; ++g) local_of[g] = (int32_t)(g - g0);
  for (int64_t k = b->offset[g0]; k < b->offset[g1]; ++k) {
    const int32_t j = b->neighbor[k];
    if (local_of[j] < 0) local_of[j] = -2; /* a ghost, numbered below */
  }
  const int64_t *reach_offset = s->par.reach_offset; /* beyond the bonds: the elements of a coupling */
  for (int64_t k = reach_offset ? reach_offset[g0] : 0; reach_offset && k < reach_offset[g1]; ++k) {
    const int32_t j = s->par.reach_node[k];
    if (local_of[j] < 0) local_of[j] = -2;
  }
  int32_t n_local = n_owned;
  for (int32_t g = 0; g < p->n; ++g)
    if (local_of[g] == -2) local_of[g] = n_local++;
  d->global_id = peri_malloc(sizeof(int32_t) * (size_t)(n_local > 0 ? n_local : 1));
  for (int32_t g = 0; g < p->n; ++g)
    if (local_of[g] >= 0) d->global_id[local_of[g]] = g;

  s->par.dd = d;
  build_halo(d, b, reach_offset, s->par.reach_node, n_owned, n_local); /* needs the global families */
  if (s->state.plastic_reverse) localize_reverse(s, d); /* so does this */
  free(s->par.reach_offset), s->par.reach_offset = NULL;
  free(s->par.reach_node), s->par.reach_node = NULL;

  const int32_t *ids = d->global_id;
  const int64_t bond_from = b->offset[g0], bond_count = b->offset[g1] - bond_from;
  localize_particles(p, ids, n_local, n_owned);
  LOCALIZE(s->mat.s0_node, sizeof(double), ids, n_local);
  LOCALIZE(s->state.thermal_strain, sizeof(double), ids, n_local);
  free(s->cond.prescribed);
  s->cond.prescribed = peri_calloc(3 * (size_t)(n_local > 0 ? n_local : 1), 1);
  localize_regions(s, g0, g1);
  localize_horizon(s->disc.horizon_field, ids, n_local, bond_from, bond_count);
  /* the plastic state of the owned families (docs/plasticity.md), in bond rows: the split comes
   * before the first force evaluation, so the deviatoric rule has not taken it into its slots */
  SLICE(s->state.plastic_stretch, sizeof(double) * (size_t)s->state.plastic_layers, bond_from, bond_count);
  SLICE(s->state.plastic_committed, sizeof(double) * (size_t)s->state.plastic_layers, bond_from, bond_count);
  free(s->state.plastic_nodes), s->state.plastic_nodes = NULL; /* (rebuilt from the state) */
  if (s->thermal) {
    const bool shared_cut = !s->thermal->own_cut;
    localize_bonds(b, g0, g1, local_of);
    if (shared_cut) s->thermal->cut = b->broken;
    localize_thermal(s, ids, n_local, n_owned, bond_from, bond_count);
  } else {
    localize_bonds(b, g0, g1, local_of);
  }
  free(local_of);
  s->par.exchange = exchange;
  return PERI_OK;
}

void peri_print_decomposition(const peri_sim *s, FILE *out) {
  const peri_decomposition *d = s->par.dd;
  if (!d) return;
  enum { STATS = 4 };
  const double mine[STATS] = {(double)s->disc.p.n_owned, (double)(s->disc.p.n - s->disc.p.n_owned), (double)d->halo.n_neighbors,
                              (double)peri_halo_send_volume(&d->halo)};
  int64_t *counts = peri_malloc(sizeof(int64_t) * (size_t)d->size);
  for (int r = 0; r < d->size; ++r) counts[r] = STATS;
  double *all = d->rank == 0 ? peri_malloc(sizeof(double) * STATS * (size_t)d->size) : NULL;
  peri_comm_gather_doubles(mine, STATS, counts, all);
  if (d->rank == 0) {
    double lo[STATS], hi[STATS], sum[STATS] = {0};
    for (int k = 0; k < STATS; ++k) lo[k] = hi[k] = all[k];
    for (int r = 0; r < d->size; ++r)
      for (int k = 0; k < STATS; ++k) {
        const double v = all[STATS * r + k];
        lo[k] = v < lo[k] ? v : lo[k];
        hi[k] = v > hi[k] ? v : hi[k];
        sum[k] += v;
      }
    fprintf(out, "  MPI ranks    %d: %.0f to %.0f nodes and %.0f to %.0f ghosts per rank, %.0f to %.0f "
            "neighbour ranks; one exchange sends %.0f to %.0f values per rank (%.0f in all, per component)\n",
            d->size, lo[0], hi[0], lo[1], hi[1], lo[2], hi[2], lo[3], hi[3], sum[3]);
  }
  free(all);
  free(counts);
}

void peri_exchange_state(peri_sim *s) {
  peri_sim_exchange(s, s->disc.p.u, 3);
  if (s->mat.s0_node) peri_sim_exchange(s, s->mat.s0_node, 1);
}

void peri_decomposition_free(peri_decomposition *d) {
  if (!d) return;
  peri_halo_free(&d->halo);
  peri_bond_halo_free(d->bond_halo);
  free(d->first);
  free(d->owned);
  free(d->blocks);
  free(d->global_id);
  free(d->bond_first);
  free(d);
}
