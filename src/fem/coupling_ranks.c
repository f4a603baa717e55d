/* The PD-FEM coupling on MPI ranks (docs/coupling.md, "On MPI ranks"). The coupling is built on
 * the whole body before the split (every rank builds it alike), in the built (global)
 * numbering. A rank assembles the rows of its owned nodes: the bonds of its PD nodes and the
 * elements that contain its FEM nodes. Those rows read nodes beyond the bonds: the corners of
 * the elements, the lattice nodes of the exact partial volumes, the columns of the kept
 * state-based rows. peri_coupling_set_reach lists them so that peri_decompose makes them
 * ghosts, and peri_coupling_localize renumbers the coupling to the rank's local nodes
 * afterwards. Each row is then the same sum, in the same order, as in one process. */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include "peri/coupling.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/sim.h"
#include "lattice_mesh.h"

/* The nodes that row g reads beyond its bonds; appends to list (or only counts, list NULL). */
static int64_t row_reach(const peri_sim *s, int32_t g, int32_t *list) {
  const peri_coupling *c = s->coupling;
  int64_t count = 0;
  for (int64_t q = c->node_offset[g]; q < c->node_offset[g + 1]; ++q) { /* the corners of its elements */
    const int32_t e = c->node_element[q];
    for (int64_t a = c->element_offset[e]; a < c->element_offset[e + 1]; ++a) {
      if (list) list[count] = c->element_nodes[a];
      ++count;
    }
  }
  if (!c->node_type[g]) return count;
  if (c->exact_volumes) /* the lattice nodes whose cells meet the horizon (coupling.c, pd_row) */
    for (int32_t q = 0; q < c->n_offsets; ++q) {
      int64_t k[3];
      for (int d = 0; d < 3; ++d) k[d] = c->lattice->cell[3 * (size_t)g + d] + c->offset[3 * (size_t)q + d];
      const int32_t j = peri_lattice_node(c->lattice, k);
      if (j < 0) continue;
      if (list) list[count] = j;
      ++count;
    }
  if (c->tangent_count) { /* state-based: the neighbours of the neighbours */
    if (list) memcpy(&list[count], c->tangent_cols[g], sizeof(int32_t) * (size_t)c->tangent_count[g]);
    count += c->tangent_count[g];
  }
  return count;
}

void peri_coupling_set_reach(peri_sim *s) {
  const int32_t n = s->disc.p.n;
  free(s->par.reach_offset), free(s->par.reach_node);
  int64_t *offset = peri_malloc(sizeof(int64_t) * ((size_t)n + 1));
  offset[0] = 0;
  for (int32_t g = 0; g < n; ++g) offset[g + 1] = offset[g] + row_reach(s, g, NULL);
  int32_t *node = peri_malloc(sizeof(int32_t) * (size_t)(offset[n] > 0 ? offset[n] : 1));
  for (int32_t g = 0; g < n; ++g) row_reach(s, g, &node[offset[g]]);
  s->par.reach_offset = offset;
  s->par.reach_node = node;
}

/* out[l] = in[ids[l]] for elements of `size` bytes; the input is freed. */
static void *take(void *in, size_t size, const int32_t *ids, int32_t n) {
  if (!in) return NULL;
  char *out = peri_malloc(size * (size_t)(n > 0 ? n : 1));
  for (int32_t l = 0; l < n; ++l) memcpy(out + size * (size_t)l, (const char *)in + size * (size_t)ids[l], size);
  free(in);
  return out;
}

/* Keeps the elements with an owned corner (those enter this rank's FEM rows), their corners
 * renamed to local nodes, and the elements of each owned node. */
static int localize_elements(peri_coupling *c, const int32_t *local_of, int32_t n_owned) {
  int32_t kept = 0;
  int64_t corners = 0;
  for (int32_t e = 0; e < c->n_elements; ++e) {
    bool owned = false, local = true;
    for (int64_t a = c->element_offset[e]; a < c->element_offset[e + 1]; ++a) {
      const int32_t l = local_of[c->element_nodes[a]];
      owned |= l >= 0 && l < n_owned;
      local &= l >= 0;
    }
    if (!owned) continue;
    if (!local) return PERI_ERR_RUN; /* a corner not brought as a ghost: peri_coupling_set_reach */
    const int64_t from = c->element_offset[e], to = c->element_offset[e + 1];
    c->element_offset[kept] = corners;
    for (int64_t a = from; a < to; ++a) c->element_nodes[corners++] = local_of[c->element_nodes[a]];
    c->element_material[kept] = c->element_material[e];
    c->element_K_offset[kept] = c->element_K_offset[e];
    ++kept;
  }
  c->element_offset[kept] = corners; /* the arrays shrink in place: kept <= e, corners <= from */
  c->n_elements = kept;
  free(c->node_offset), free(c->node_element);
  c->node_offset = peri_calloc((size_t)n_owned + 1, sizeof(int64_t));
  for (int32_t e = 0; e < kept; ++e)
    for (int64_t a = c->element_offset[e]; a < c->element_offset[e + 1]; ++a)
      if (c->element_nodes[a] < n_owned) c->node_offset[c->element_nodes[a] + 1]++;
  for (int32_t i = 0; i < n_owned; ++i) c->node_offset[i + 1] += c->node_offset[i];
  c->node_element = peri_malloc(sizeof(int32_t) * (size_t)(c->node_offset[n_owned] + 1));
  int64_t *fill = peri_malloc(sizeof(int64_t) * ((size_t)n_owned + 1));
  memcpy(fill, c->node_offset, sizeof(int64_t) * ((size_t)n_owned + 1));
  for (int32_t e = 0; e < kept; ++e) /* in element order, as in one process */
    for (int64_t a = c->element_offset[e]; a < c->element_offset[e + 1]; ++a)
      if (c->element_nodes[a] < n_owned) c->node_element[fill[c->element_nodes[a]]++] = e;
  free(fill);
  return PERI_OK;
}

/* The kept state-based rows of the owned PD nodes, their columns renamed to local nodes. */
static int localize_tangent_rows(peri_coupling *c, const int32_t *global_id, const int32_t *local_of, int32_t n_local,
                                 int32_t n_owned, int64_t n_global) {
  int32_t *count = peri_calloc((size_t)(n_local > 0 ? n_local : 1), sizeof(int32_t));
  int32_t **cols = peri_calloc((size_t)(n_local > 0 ? n_local : 1), sizeof(int32_t *));
  double **blocks = peri_calloc((size_t)(n_local > 0 ? n_local : 1), sizeof(double *));
  int rc = PERI_OK;
  for (int32_t i = 0; i < n_owned; ++i) {
    const int32_t g = global_id[i];
    count[i] = c->tangent_count[g], cols[i] = c->tangent_cols[g], blocks[i] = c->tangent_blocks[g];
    c->tangent_cols[g] = NULL, c->tangent_blocks[g] = NULL;
    for (int32_t k = 0; k < count[i]; ++k)
      if ((cols[i][k] = local_of[cols[i][k]]) < 0) rc = PERI_ERR_RUN;
  }
  for (int64_t g = 0; g < n_global; ++g) free(c->tangent_cols[g]), free(c->tangent_blocks[g]);
  free(c->tangent_count), free(c->tangent_cols), free(c->tangent_blocks);
  c->tangent_count = count, c->tangent_cols = cols, c->tangent_blocks = blocks;
  return rc;
}

int peri_coupling_localize(peri_sim *s) {
  peri_coupling *c = s->coupling;
  const peri_decomposition *d = s->par.dd;
  if (!c || !d) return PERI_OK;
  const int32_t n_local = s->disc.p.n, n_owned = s->disc.p.n_owned;
  const int32_t *ids = d->global_id;
  int32_t *local_of = peri_malloc(sizeof(int32_t) * (size_t)(d->n_global > 0 ? d->n_global : 1));
  for (int64_t g = 0; g < d->n_global; ++g) local_of[g] = -1;
  for (int32_t l = 0; l < n_local; ++l) local_of[ids[l]] = l;
  c->node_type = take(c->node_type, sizeof(int32_t), ids, n_local); /* ghosts too: a bond's far end */
  c->fem_only = take(c->fem_only, 1, ids, n_local);
  int rc = localize_elements(c, local_of, n_owned);
  if (c->lattice) { /* lattice points name local nodes, -1 where a node is not on this rank */
    c->lattice->cell = take(c->lattice->cell, 3 * sizeof(int64_t), ids, n_local);
    const int64_t points = c->lattice->extent[0] * c->lattice->extent[1] * c->lattice->extent[2];
    for (int64_t k = 0; k < points; ++k)
      if (c->lattice->at[k] >= 0) c->lattice->at[k] = local_of[c->lattice->at[k]];
  }
  if (rc == PERI_OK && c->tangent_count) rc = localize_tangent_rows(c, ids, local_of, n_local, n_owned, d->n_global);
  c->n_nodes = n_owned;
  free(local_of);
  if (rc != PERI_OK) peri_error("coupling: a row reads a node that is not on this rank (rank %d)", d->rank);
  return rc;
}
