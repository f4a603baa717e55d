/* Work items of the bond loops (see node_blocks.h). */
#include <stdlib.h>
#include "peri/discretize.h"
#include "peri/error.h"
#include "peri/model.h"
#include "bond_kernel.h"
#include "node_blocks.h"

#define LANES_1(m) {(m) & 1, (m) >> 1 & 1, (m) >> 2 & 1, (m) >> 3 & 1, (m) >> 4 & 1, (m) >> 5 & 1, (m) >> 6 & 1, (m) >> 7 & 1}
#define LANES_4(m) LANES_1(m), LANES_1((m) + 1), LANES_1((m) + 2), LANES_1((m) + 3)
#define LANES_16(m) LANES_4(m), LANES_4((m) + 4), LANES_4((m) + 8), LANES_4((m) + 12)
#define LANES_64(m) LANES_16(m), LANES_16((m) + 16), LANES_16((m) + 32), LANES_16((m) + 48)
const double peri_lane_on[256][PERI_BLOCK] = {LANES_64(0), LANES_64(64), LANES_64(128), LANES_64(192)};

/* A template may have at most this many entries per bond of the largest family in it: the
 * lanes without the entry idle, and beyond this the block costs more than its nodes alone. */
#define PERI_TEMPLATE_SLACK 1.5

/* Builds in tj/lanes (capacity cap) the template of nodes i0 .. i0+7: the sorted union of
 * their families shifted by the lane. Returns its length, or -1 when the nodes do not form
 * a block: a family is not increasing (MPI ghosts numbered after the owned nodes), a lane's
 * shifted neighbour leaves 0 .. n-8, or the union is too long. */
static int64_t build_template(const peri_bonds *b, int32_t n, int32_t i0, int32_t *tj, uint8_t *lanes,
                              int32_t *merged_j, uint8_t *merged_lanes, int64_t cap) {
  int64_t len = 0, largest = 0;
  for (int l = 0; l < PERI_BLOCK; ++l) {
    const int64_t k0 = b->offset[i0 + l], count = b->offset[i0 + l + 1] - k0;
    if (count > largest) largest = count;
    /* merge the shifted family into the template */
    int64_t a = 0, c = 0, m = 0;
    while (a < len || c < count) {
      const int64_t shifted = c < count ? (int64_t)b->neighbor[k0 + c] - l : INT64_MAX;
      if (c < count) {
        if (shifted < 0 || shifted + PERI_BLOCK > n) return -1;
        if (c > 0 && b->neighbor[k0 + c] <= b->neighbor[k0 + c - 1]) return -1;
      }
      if (m >= cap) return -1;
      if (a < len && tj[a] < shifted) {
        merged_j[m] = tj[a], merged_lanes[m++] = lanes[a++];
      } else if (a < len && tj[a] == shifted) {
        merged_j[m] = tj[a], merged_lanes[m++] = (uint8_t)(lanes[a++] | 1u << l), ++c;
      } else {
        merged_j[m] = (int32_t)shifted, merged_lanes[m++] = (uint8_t)(1u << l), ++c;
      }
    }
    memcpy(tj, merged_j, sizeof(int32_t) * (size_t)m);
    memcpy(lanes, merged_lanes, (size_t)m);
    len = m;
  }
  if (largest == 0 || (double)len > PERI_TEMPLATE_SLACK * (double)largest) return -1;
  return len;
}

/* Clears from the lane masks the broken bonds of node i (in item `item`). */
static void clear_broken_lanes(peri_node_blocks *nb, const peri_bonds *b, int32_t item, int32_t i) {
  if (!peri_item_is_block(nb, item)) return;
  /* (an intact family, every one at the start of a run: nothing to clear, no merge) */
  if (!memchr(b->broken + b->offset[i], 1, (size_t)(b->offset[i + 1] - b->offset[i]))) return;
  const int32_t lane = i - nb->first[item];
  const uint8_t clear = (uint8_t) ~(1u << lane);
  /* the template and the shifted family are both increasing: one merge (a dropped entry's
   * bonds are all broken: nothing to clear) */
  int64_t a = nb->tpl[item];
  const int64_t end = nb->tpl_end[item];
  for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
    const int32_t shifted = b->neighbor[k] - lane;
    while (a < end && nb->tpl_node[a] < shifted) ++a;
    if (a == end) break;
    if (b->broken[k] && nb->tpl_node[a] == shifted) {
      nb->tpl_lanes[a] &= clear;
      if (!nb->tpl_lanes[a]) nb->emptied[item] = 1;
    }
  }
}

/* Clears from block item `item`'s lane masks the bond of node i to neighbour j, just broken:
 * its template entry by bisection (the entries are increasing). */
static void clear_broken_lane(peri_node_blocks *nb, int32_t item, int32_t i, int32_t j) {
  const int32_t lane = i - nb->first[item], shifted = j - lane;
  int64_t lo = nb->tpl[item], hi = nb->tpl_end[item];
  while (lo < hi) {
    const int64_t mid = lo + (hi - lo) / 2;
    if (nb->tpl_node[mid] < shifted) lo = mid + 1;
    else hi = mid;
  }
  if (lo < nb->tpl_end[item] && nb->tpl_node[lo] == shifted) {
    nb->tpl_lanes[lo] &= (uint8_t) ~(1u << lane);
    if (!nb->tpl_lanes[lo]) nb->emptied[item] = 1;
  }
}

/* Drops the entries of block `item` whose lanes have all lost their bond; the loops' sums do
 * not change (such an entry adds nothing to any lane). Every such entry, however few (a
 * fragmenting cylinder kept 6% of its entries empty under a threshold of an eighth of the
 * block, each as costly as a full one), unless `whole_share`: then only when they are an
 * eighth of the block's entries or more, for the deviatoric yield rule's block loops, which
 * count each lane's bonds along the whole template and leave a compacted block to the
 * one-node loops. */
static void compact_template(peri_node_blocks *nb, int32_t item, bool whole_share) {
  const int64_t a0 = nb->tpl[item], end = nb->tpl_end[item];
  int64_t empty = 0;
  for (int64_t a = a0; a < end; ++a) empty += nb->tpl_lanes[a] == 0;
  nb->emptied[item] = 0;
  if (empty == 0 || (whole_share && 8 * empty < end - a0)) return;
  int64_t kept = a0;
  for (int64_t a = a0; a < end; ++a)
    if (nb->tpl_lanes[a]) {
      nb->tpl_node[kept] = nb->tpl_node[a];
      nb->tpl_lanes[kept] = nb->tpl_lanes[a];
      nb->tpl_geom[kept] = nb->tpl_geom[a];
      nb->tpl_bonds[kept++] = nb->tpl_bonds[a];
    }
  nb->tpl_end[item] = kept;
}

/* The mechanical stretch of bond i-j on the structure-of-arrays copies, the same operations
 * from either end (x_j - x_i is exactly -(x_i - x_j)): both directions break together. */
static inline double bond_stretch(const double *restrict X0, const double *restrict X1, const double *restrict X2,
                                  const double *restrict U0, const double *restrict U1, const double *restrict U2,
                                  const double *restrict eth, int32_t i, int32_t j) {
  const double x0 = X0[j] - X0[i], x1 = X1[j] - X1[i], x2 = X2[j] - X2[i];
  const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2);
  const double d0 = x0 + (U0[j] - U0[i]), d1 = x1 + (U1[j] - U1[i]), d2 = x2 + (U2[j] - U2[i]);
  const double r = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
  return (r - r0) / r0 - (eth ? 0.5 * (eth[i] + eth[j]) : 0.0);
}

/* The exact breaking test of node i's family, on the structure-of-arrays copies: the
 * stretches of a chunk of the family by a vector loop (the same operations from either end of
 * a bond, so both directions break together), then the exact critical stretch for the bonds
 * beyond the lower bound of theirs. */
static long break_family_vector(peri_sim *s, peri_node_blocks *nb, int32_t item, int32_t i) {
  peri_bonds *b = &s->disc.bonds;
  const size_t n_nodes = (size_t)nb->n;
  const double *restrict X0 = nb->soa, *restrict X1 = X0 + n_nodes, *restrict X2 = X1 + n_nodes,
                         *restrict U0 = X2 + n_nodes, *restrict U1 = U0 + n_nodes, *restrict U2 = U1 + n_nodes;
  const double *restrict eth = s->state.thermal_strain, *restrict bound = s->disc.p.s0_bound;
  const int32_t *restrict neighbor = b->neighbor;
  const double xi0 = X0[i], xi1 = X1[i], xi2 = X2[i], ui0 = U0[i], ui1 = U1[i], ui2 = U2[i];
  const double bound_i = bound[i];
  const bool block = peri_item_is_block(nb, item);
  bool beyond[PERI_INTACT_CHUNK];
  long broken = 0;
  for (int64_t k0 = b->offset[i]; k0 < b->offset[i + 1]; k0 += PERI_INTACT_CHUNK) {
    const int count = (int)(b->offset[i + 1] - k0 < PERI_INTACT_CHUNK ? b->offset[i + 1] - k0 : PERI_INTACT_CHUNK);
    if (eth) {
#pragma omp simd
      for (int a = 0; a < count; ++a) {
        const int32_t j = neighbor[k0 + a];
        beyond[a] = bond_stretch(X0, X1, X2, U0, U1, U2, eth, i, j) > peri_min(bound_i, bound[j]);
      }
    } else {
      /* without square roots: s > b is r > r0 (1 + b), taken with a margin of 1e-12 so that
       * the screen keeps every bond the exact stretch below may find beyond b */
#pragma omp simd
      for (int a = 0; a < count; ++a) {
        const int32_t j = neighbor[k0 + a];
        const double x0 = X0[j] - xi0, x1 = X1[j] - xi1, x2 = X2[j] - xi2;
        const double d0 = x0 + (U0[j] - ui0), d1 = x1 + (U1[j] - ui1), d2 = x2 + (U2[j] - ui2);
        const double grow = 1.0 + peri_min(bound_i, bound[j]);
        const double r0_sq = x0 * x0 + x1 * x1 + x2 * x2, r_sq = d0 * d0 + d1 * d1 + d2 * d2;
        beyond[a] = !(grow > 0.0) || r_sq > r0_sq * grow * grow * (1.0 - 1e-12);
      }
    }
    for (int a = 0; a < count; ++a) {
      const int64_t k = k0 + a;
      if (beyond[a] && !b->broken[k] &&
          bond_stretch(X0, X1, X2, U0, U1, U2, eth, i, neighbor[k]) > peri_bond_s0(s, i, neighbor[k])) {
        b->broken[k] = 1;
        ++broken;
        if (block) clear_broken_lane(nb, item, i, neighbor[k]);
      }
    }
  }
  return broken;
}

long peri_node_blocks_break_marked(peri_sim *s, peri_node_blocks *nb, int32_t item, const peri_break_marks *marks,
                                   unsigned *lost_lanes) {
  peri_bonds *b = &s->disc.bonds;
  const size_t n_nodes = (size_t)nb->n;
  const double *restrict X0 = nb->soa, *restrict X1 = X0 + n_nodes, *restrict X2 = X1 + n_nodes,
                         *restrict U0 = X2 + n_nodes, *restrict U1 = U0 + n_nodes, *restrict U2 = U1 + n_nodes;
  const double *restrict eth = s->state.thermal_strain;
  const int32_t i0 = nb->first[item];
  const int64_t t0 = nb->tpl[item];
  long broken = 0;
  for (int m = 0; m < marks->n; ++m) {
    const int64_t a = t0 + marks->entry[m];
    for (unsigned over = marks->lanes[m]; over; over &= over - 1) {
      const int lane = __builtin_ctz(over);
      const int32_t i = i0 + lane, j = nb->tpl_node[a] + lane;
      if (bond_stretch(X0, X1, X2, U0, U1, U2, eth, i, j) <= peri_bond_s0(s, i, j)) continue;
      const int64_t k = peri_bonds_find(b, i, j); /* (a block's families are increasing) */
      if (k < 0 || b->broken[k]) continue;
      b->broken[k] = 1;
      ++broken;
      *lost_lanes |= 1u << lane;
      nb->tpl_lanes[a] &= (uint8_t) ~(1u << lane);
      if (!nb->tpl_lanes[a]) nb->emptied[item] = 1;
    }
  }
  return broken;
}

long peri_node_blocks_break_family(peri_sim *s, peri_node_blocks *nb, int32_t item, int32_t i) {
  return break_family_vector(s, nb, item, i);
}

void peri_node_blocks_clear_broken(peri_node_blocks *nb, const peri_bonds *b, int32_t item, int32_t i) {
  clear_broken_lanes(nb, b, item, i);
}

double peri_bond_coordinate(const peri_geometry *g, int axis, double x) {
  return g->lattice ? peri_exact_coordinate(&g->lattice_axis[axis], x) : x;
}

/* Lane masks from the structure and the broken flags. */
static void sync_broken(peri_node_blocks *nb, const peri_bonds *b) {
  memcpy(nb->tpl_lanes, nb->tpl_bonds, (size_t)nb->tpl_entries);
#pragma omp parallel for schedule(dynamic, 64)
  for (int32_t item = 0; item < nb->n_items; ++item)
    for (int32_t i = nb->first[item]; i < nb->first[item + 1]; ++i) clear_broken_lanes(nb, b, item, i);
  nb->broken_edits = b->broken_edits;
}

/* The distinct offsets, by their bits: an open-addressing table of indices into geom. */
typedef struct geom_map {
  int32_t *slot; /* -1: empty */
  uint32_t mask;
} geom_map;

static uint32_t geom_hash(const double xi[3]) {
  uint64_t h = 0x9e3779b97f4a7c15u, bits;
  for (int c = 0; c < 3; ++c) {
    memcpy(&bits, &xi[c], sizeof bits);
    h = (h ^ bits) * 0xff51afd7ed558ccdu;
    h ^= h >> 33;
  }
  return (uint32_t)h;
}

/* The index of offset xi in nb->geom, added with its lengths if new; PERI_GEOM_NONE when the
 * table is full. */
static uint16_t geom_index(peri_node_blocks *nb, geom_map *map, const double xi[3]) {
  for (uint32_t h = geom_hash(xi) & map->mask;; h = (h + 1) & map->mask) {
    const int32_t k = map->slot[h];
    if (k < 0) break;
    const double *g = nb->geom + (size_t)k * PERI_GEOM_STRIDE;
    if (memcmp(g, xi, 3 * sizeof(double)) == 0) return (uint16_t)k;
  }
  if (nb->n_geom >= PERI_GEOM_NONE) return PERI_GEOM_NONE;
  const int32_t k = nb->n_geom++;
  nb->geom = peri_realloc(nb->geom, sizeof(double) * PERI_GEOM_STRIDE * (size_t)nb->n_geom);
  double *g = nb->geom + (size_t)k * PERI_GEOM_STRIDE;
  memset(g, 0, sizeof(double) * PERI_GEOM_STRIDE);
  memcpy(g, xi, 3 * sizeof(double));
#ifdef PERI_BOND_V8
  /* the lengths by the kernels' own function, so that they are each lane's to the bit */
  const peri_v8d zero = v8_setzero_pd(), c[3] = {zero, zero, zero},
                 xj[3] = {v8_set1_pd(xi[0]), v8_set1_pd(xi[1]), v8_set1_pd(xi[2])};
  const peri_offset_v8 by_norm2 = peri_offset_of_positions_v8(xj, c, false), by_fma = peri_offset_of_positions_v8(xj, c, true);
  double lanes[PERI_BLOCK];
  v8_storeu_pd(lanes, by_norm2.r0), g[PERI_GEOM_R0_NORM2] = lanes[0];
  v8_storeu_pd(lanes, by_norm2.inv_r0), g[PERI_GEOM_INV_R0_NORM2] = lanes[0];
  v8_storeu_pd(lanes, by_fma.r0), g[PERI_GEOM_R0_FMA] = lanes[0];
  v8_storeu_pd(lanes, by_fma.inv_r0), g[PERI_GEOM_INV_R0_FMA] = lanes[0];
#endif
  uint32_t h = geom_hash(xi) & map->mask;
  while (map->slot[h] >= 0) h = (h + 1) & map->mask;
  map->slot[h] = k;
  return (uint16_t)k;
}

/* The offsets of every block's entries (tpl_geom), on the positions' copies: a block keeps
 * them when each entry's offset is one number for all lanes with the bond, else it is marked
 * PERI_GEOM_NONE and its loops compute the offsets lane by lane. */
static void build_geometry(peri_node_blocks *nb) {
  free(nb->geom);
  nb->geom = NULL;
  nb->n_geom = 0;
  nb->lattice_bonds = 0;
  const size_t n = (size_t)nb->n;
  const double *X[3] = {nb->soa, nb->soa + n, nb->soa + 2 * n};
  geom_map map = {NULL, 2u * PERI_GEOM_NONE + 1}; /* 2^17 slots: at most half full */
  map.slot = peri_malloc(sizeof(int32_t) * ((size_t)map.mask + 1));
  for (uint32_t h = 0; h <= map.mask; ++h) map.slot[h] = -1;
  for (int32_t item = 0; item < nb->n_items; ++item) {
    const int64_t a0 = nb->tpl[item], a1 = nb->tpl_end[item];
    const int32_t i0 = nb->first[item];
    bool lattice = a1 > a0;
#ifndef PERI_BOND_V8
    lattice = false;
#endif
    for (int64_t a = a0; a < a1 && lattice; ++a) {
      const unsigned lanes = nb->tpl_bonds[a];
      const int first = lanes ? __builtin_ctz(lanes) : 0;
      const int32_t j = nb->tpl_node[a];
      double xi[3];
      for (int c = 0; c < 3; ++c) xi[c] = X[c][j + first] - X[c][i0 + first];
      for (int l = first + 1; l < PERI_BLOCK && lattice; ++l)
        if (lanes >> l & 1u)
          for (int c = 0; c < 3; ++c) lattice = lattice && X[c][j + l] - X[c][i0 + l] == xi[c];
      if (lattice) nb->tpl_geom[a] = geom_index(nb, &map, xi);
      lattice = lattice && nb->tpl_geom[a] != PERI_GEOM_NONE;
    }
    if (!lattice)
      for (int64_t a = a0; a < nb->tpl[item + 1]; ++a) nb->tpl_geom[a] = PERI_GEOM_NONE;
    else
      nb->lattice_bonds += nb->offset[nb->first[item + 1]] - nb->offset[i0];
  }
  free(map.slot);
}

/* Every build's generation (node_blocks.h), distinct over all the item sets of a process. */
static uint64_t builds_so_far;

static void build(peri_node_blocks *nb, const peri_sim *s) {
  nb->generation = __atomic_add_fetch(&builds_so_far, 1, __ATOMIC_RELAXED); /* (sims may build in threads of their own) */
  const peri_bonds *b = &s->disc.bonds;
  const int32_t n_owned = s->disc.p.n_owned, n = s->disc.p.n;
  free(nb->first);
  free(nb->tpl);
  free(nb->tpl_node);
  free(nb->tpl_geom);
  free(nb->tpl_lanes);
  free(nb->tpl_bonds);
  free(nb->tpl_end);
  free(nb->emptied);
  int64_t largest = 0;
  for (int32_t i = 0; i < n_owned; ++i)
    if (b->offset[i + 1] - b->offset[i] > largest) largest = b->offset[i + 1] - b->offset[i];
  const int64_t cap = (int64_t)(PERI_TEMPLATE_SLACK * (double)largest) + 1;
  int32_t *tj = peri_malloc(sizeof(int32_t) * (size_t)cap * 2);
  uint8_t *lanes = peri_malloc((size_t)cap * 2);
  nb->first = peri_malloc(sizeof(int32_t) * ((size_t)n_owned + 1));
  nb->tpl = peri_malloc(sizeof(int64_t) * ((size_t)n_owned + 1));
  /* templates take at most the slack times the block's bonds */
  const int64_t tpl_cap = (int64_t)(PERI_TEMPLATE_SLACK * (double)b->offset[n_owned]) / PERI_BLOCK + cap + 1;
  nb->tpl_node = peri_malloc(sizeof(int32_t) * (size_t)tpl_cap);
  nb->tpl_lanes = peri_malloc((size_t)tpl_cap);
  int32_t items = 0;
  int64_t used = 0;
  nb->block_bonds = 0;
  for (int32_t i = 0; i < n_owned;) {
    int64_t len = -1;
    if (!s->disc.generic_bond_loops && i + PERI_BLOCK <= n_owned && used + cap <= tpl_cap)
      len = build_template(b, n, i, tj, lanes, tj + cap, lanes + cap, cap);
    nb->first[items] = i;
    nb->tpl[items++] = used;
    if (len > 0) {
      memcpy(nb->tpl_node + used, tj, sizeof(int32_t) * (size_t)len);
      memcpy(nb->tpl_lanes + used, lanes, (size_t)len);
      used += len;
      nb->block_bonds += b->offset[i + PERI_BLOCK] - b->offset[i];
      i += PERI_BLOCK;
    } else {
      i += 1;
    }
  }
  nb->first[items] = n_owned;
  nb->tpl[items] = used;
  nb->n_items = items;
  nb->tpl_entries = used;
  /* the items' cost for sharing them among threads: their bonds */
  free(nb->cost);
  nb->cost = peri_malloc(sizeof(int64_t) * ((size_t)items + 1));
  for (int32_t k = 0; k <= items; ++k) nb->cost[k] = b->offset[nb->first[k]] - b->offset[0];
  if (!nb->share) nb->share = peri_work_share_new();
  nb->tpl_bonds = peri_malloc((size_t)(used > 0 ? used : 1));
  memcpy(nb->tpl_bonds, nb->tpl_lanes, (size_t)used);
  nb->tpl_geom = peri_malloc(sizeof(uint16_t) * (size_t)(used > 0 ? used : 1));
  nb->tpl_end = peri_malloc(sizeof(int64_t) * ((size_t)items + 1));
  for (int32_t k = 0; k < items; ++k) nb->tpl_end[k] = nb->tpl[k + 1];
  nb->emptied = peri_calloc((size_t)items + 1, 1);
  nb->compacted = false;
  free(tj);
  free(lanes);
  nb->offset = b->offset;
  nb->neighbor = b->neighbor;
  nb->n_owned = n_owned;
  nb->generic = s->disc.generic_bond_loops;
}

/* a template entry: the neighbour (int32), two lane masks and the offset's index */
#define TEMPLATE_ENTRY_BYTES (sizeof(int32_t) + 2 + sizeof(uint16_t))

double peri_node_blocks_share(const peri_sim *s, double *template_bytes_per_bond, double *lattice_share) {
  const peri_node_blocks *nb = s->disc.node_blocks;
  if (!nb || !nb->offset) return -1.0;
  const double bonds = (double)(nb->offset[nb->n_owned] > 0 ? nb->offset[nb->n_owned] : 1);
  if (template_bytes_per_bond) *template_bytes_per_bond = (double)nb->tpl_entries * TEMPLATE_ENTRY_BYTES / bonds;
  if (lattice_share) *lattice_share = nb->block_bonds > 0 ? (double)nb->lattice_bonds / (double)nb->block_bonds : 0.0;
  return (double)nb->block_bonds / bonds;
}

double peri_node_blocks_bytes_bound(void) { return PERI_TEMPLATE_SLACK * TEMPLATE_ENTRY_BYTES / PERI_BLOCK; }

peri_node_blocks *peri_node_blocks_refresh(peri_sim *s) {
  const peri_particles *p = &s->disc.p;
  if (!s->disc.node_blocks) s->disc.node_blocks = peri_calloc(1, sizeof(peri_node_blocks));
  peri_node_blocks *nb = s->disc.node_blocks;
  const size_t n = (size_t)p->n;
  if (nb->offset != s->disc.bonds.offset || nb->neighbor != s->disc.bonds.neighbor || nb->n_owned != p->n_owned ||
      nb->n != p->n || nb->x != p->x || nb->volume != p->volume || nb->generic != s->disc.generic_bond_loops) {
    build(nb, s);
    free(nb->soa);
    nb->soa = peri_malloc(sizeof(double) * 6 * (n > 0 ? n : 1));
    nb->n = p->n;
    nb->x = p->x;
    nb->volume = p->volume;
    nb->uniform_volume = peri_uniform_volume(p);
    /* a uniform grid's nodes at exact lattice coordinates (peri_exact_coordinate: within
     * 1e-13 of dx for grids of up to about a thousand cells from the origin), so that on the
     * lattice a block's neighbour offset is one number for its eight lanes (build_geometry) */
    const peri_geometry *geom = &s->disc.geom;
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c)
        nb->soa[c * n + i] = peri_bond_coordinate(geom, c, p->x[3 * i + (size_t)c]);
    build_geometry(nb);
    sync_broken(nb, &s->disc.bonds);
  }
  if (nb->broken_edits != s->disc.bonds.broken_edits) {
    if (nb->compacted) build(nb, s), build_geometry(nb); /* bonds may have come back: every entry again */
    sync_broken(nb, &s->disc.bonds);
  }
  bool dropped = false;
  const bool whole_templates = s->state.plastic_reverse != NULL; /* (the deviatoric rule) */
#pragma omp parallel for schedule(dynamic, 256) reduction(|| : dropped)
  for (int32_t item = 0; item < nb->n_items; ++item)
    if (nb->emptied[item]) {
      const int64_t end = nb->tpl_end[item];
      compact_template(nb, item, whole_templates);
      dropped = dropped || nb->tpl_end[item] < end;
    }
  if (dropped) nb->compacted = true;
  double *restrict u_soa = nb->soa + 3 * n;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n; ++i)
    for (int c = 0; c < 3; ++c) u_soa[c * n + (size_t)i] = p->u[3 * i + c];
  return nb;
}

void peri_node_blocks_free(struct peri_node_blocks *nb) {
  if (!nb) return;
  free(nb->first);
  free(nb->tpl);
  free(nb->tpl_node);
  free(nb->tpl_lanes);
  free(nb->tpl_bonds);
  free(nb->tpl_geom);
  free(nb->geom);
  free(nb->tpl_end);
  free(nb->emptied);
  free(nb->soa);
  free(nb->cost);
  peri_work_share_free(nb->share);
  free(nb);
}
