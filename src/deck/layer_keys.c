/* discretization.fictitious_layers (docs/deck.md section 3, docs/models.md section 6): layers
 * of width delta added outside the faces of the body's bounding box, `auto` those faces that
 * hold nodes of a displacement or velocity condition (not only at the face's edges), or the
 * faces named. Every node of the
 * outermost row of such a face that a displacement or velocity condition holds is continued
 * outward by ceil(delta/dx) nodes on the grid (its volume and material), and each new node
 * joins every region of the node it continues: the neighbouring condition prescribes it, at
 * its own position. The new nodes are flagged as fictitious-layer nodes (never damaged, out
 * of output), as those of a `fictitious_layer` region. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "setup_parts.h"

static const char *const face_names[] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max", NULL};

/* held[r]: region r carries a displacement or velocity condition (read from the deck's list;
 * the conditions themselves are parsed later). */
static void prescribed_regions(const peri_sim *s, const peri_node *root, bool *held) {
  const peri_node *bcs = peri_deck_get(root, "boundary_conditions");
  for (int k = 0; bcs && bcs->kind == PERI_NODE_SEQUENCE && k < bcs->count; ++k) {
    const peri_node *type = peri_deck_get(bcs->items[k], "type"), *region = peri_deck_get(bcs->items[k], "region");
    if (!type || !region || type->kind != PERI_NODE_SCALAR || region->kind != PERI_NODE_SCALAR) continue;
    if (strcmp(type->scalar, "displacement") != 0 && strcmp(type->scalar, "velocity") != 0) continue;
    for (int r = 0; r < s->cond.n_regions; ++r)
      if (strcmp(s->cond.regions[r].name, region->scalar) == 0) held[r] = true;
  }
}

int peri_setup_fictitious_layers(peri_sim *s, const peri_node *root) {
  const peri_node *d = peri_deck_get(root, "discretization");
  const peri_node *v = d ? peri_deck_get(d, "fictitious_layers") : NULL;
  if (!v) return PERI_OK;
  const peri_node *key = peri_deck_key_node(d, "fictitious_layers");
  const int dim = s->disc.geom.dim;
  bool wanted[6] = {false}, automatic = false;
  if (v->kind == PERI_NODE_SCALAR && strcmp(v->scalar, "auto") == 0) {
    automatic = true;
  } else if (v->kind == PERI_NODE_SEQUENCE && v->count > 0) {
    for (int k = 0; k < v->count; ++k) {
      int face = -1;
      for (int f = 0; f < 2 * dim; ++f)
        if (v->items[k]->kind == PERI_NODE_SCALAR && strcmp(v->items[k]->scalar, face_names[f]) == 0) face = f;
      if (face < 0)
        return peri_deck_error(v->items[k], "key 'fictitious_layers': expected a face of the body's bounding box "
                                            "(x_min, x_max%s%s) or the list's single alternative `auto`",
                               dim > 1 ? ", y_min, y_max" : "", dim > 2 ? ", z_min, z_max" : "");
      wanted[face] = true;
    }
  } else {
    return peri_deck_error(key, "key 'fictitious_layers': expected `auto` or a list of faces (x_min, x_max, ...)");
  }
  if (s->disc.horizon_field || s->disc.p.n_owned != s->disc.p.n)
    return peri_deck_error(key, "key 'fictitious_layers': not with a horizon that varies");
  peri_particles *p = &s->disc.p;
  const int32_t n0 = p->n;
  const double dx = s->disc.geom.spacing, delta = s->disc.geom.horizon;
  const int rows = (int)ceil(delta / dx - 1e-9);
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int32_t i = 0; i < n0; ++i)
    for (int c = 0; c < dim; ++c) lo[c] = fmin(lo[c], p->x[3 * i + c]), hi[c] = fmax(hi[c], p->x[3 * i + c]);
  /* in_held[i]: node i is in a region with a displacement or velocity condition */
  const int nr = s->cond.n_regions;
  bool *held = peri_calloc((size_t)nr, sizeof(bool));
  prescribed_regions(s, root, held);
  uint8_t *in_held = peri_calloc((size_t)(n0 > 0 ? n0 : 1), 1);
  uint8_t *member = peri_calloc((size_t)nr * (size_t)(n0 > 0 ? n0 : 1), 1); /* [r * n0 + i] */
  for (int r = 0; r < nr; ++r)
    for (int32_t a = 0; a < s->cond.regions[r].count; ++a) {
      const int32_t i = s->cond.regions[r].nodes[a];
      member[(size_t)r * n0 + i] = 1;
      if (held[r]) in_held[i] = 1;
    }
  int rc = PERI_OK;
  for (int f = 0; f < 2 * dim && rc == PERI_OK; ++f) {
    const int axis = f / 2;
    const double face = f % 2 ? hi[axis] : lo[axis], outward = f % 2 ? 1.0 : -1.0;
    long sources = 0, inner = 0; /* inner: not also on another face (a corner alone does not count) */
    for (int32_t i = 0; i < n0; ++i) {
      if (!(fabs(p->x[3 * i + axis] - face) < 0.25 * dx && in_held[i])) continue;
      sources++;
      bool edge = false;
      for (int c = 0; c < dim; ++c)
        if (c != axis) edge = edge || fabs(p->x[3 * i + c] - lo[c]) < 0.25 * dx || fabs(p->x[3 * i + c] - hi[c]) < 0.25 * dx;
      inner += !edge;
    }
    if (!wanted[f] && !(automatic && inner > 0)) continue;
    if (sources == 0) {
      rc = peri_deck_error(key, "key 'fictitious_layers': face %s holds no node of a displacement or velocity "
                                "condition, which would prescribe its layer", face_names[f]);
      break;
    }
    for (int32_t i = 0; i < n0; ++i) {
      if (!(fabs(p->x[3 * i + axis] - face) < 0.25 * dx && in_held[i])) continue;
      for (int k = 1; k <= rows; ++k) {
        double x[3] = {p->x[3 * i], p->x[3 * i + 1], p->x[3 * i + 2]};
        x[axis] += outward * k * dx;
        const int32_t added = peri_particles_add(p, x, p->volume[i], p->material[i], p->block[i]);
        p->flags[added] |= PERI_NODE_NO_FAIL | PERI_NODE_FICTITIOUS;
        for (int r = 0; r < nr; ++r) { /* the regions of the node it continues (ascending lists) */
          peri_region *reg = &s->cond.regions[r];
          if (!member[(size_t)r * n0 + i]) continue;
          reg->nodes = peri_realloc(reg->nodes, sizeof(int32_t) * ((size_t)reg->count + 1));
          reg->nodes[reg->count++] = added;
        }
      }
    }
  }
  free(held);
  free(in_held);
  free(member);
  return rc;
}

/* Every node of the automatic layers is prescribed on every component (the conditions are
 * parsed by now). */
int peri_setup_check_fictitious_layers(const peri_sim *s, const peri_node *root) {
  const peri_node *d = peri_deck_get(root, "discretization");
  if (!d || !peri_deck_get(d, "fictitious_layers")) return PERI_OK;
  const peri_particles *p = &s->disc.p;
  const int dim = s->disc.geom.dim;
  uint8_t *mask = peri_calloc((size_t)(p->n_owned > 0 ? p->n_owned : 1), 1);
  for (int b = 0; b < s->cond.n_bcs; ++b) {
    const peri_bc *bc = &s->cond.bcs[b];
    if (bc->kind != PERI_BC_DISPLACEMENT && bc->kind != PERI_BC_VELOCITY) continue;
    const peri_region *r = &s->cond.regions[bc->region];
    for (int32_t a = 0; a < r->count; ++a)
      for (int c = 0; c < dim; ++c)
        if (bc->value[c]) mask[r->nodes[a]] |= (uint8_t)(1u << c);
  }
  long loose = 0;
  for (int32_t i = 0; i < p->n_owned; ++i)
    loose += (p->flags[i] & PERI_NODE_FICTITIOUS) && mask[i] != (uint8_t)((1u << dim) - 1);
  free(mask);
  if (loose > 0)
    return peri_deck_error(peri_deck_key_node(d, "fictitious_layers"),
                           "key 'fictitious_layers': %ld layer node(s) continue a node whose conditions do not "
                           "prescribe every component (a layer needs a displacement or velocity on each)", loose);
  return PERI_OK;
}
