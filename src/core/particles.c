/* Particle storage: structure of arrays with stride-3 vectors. */
#include <string.h>
#include <stdlib.h>
#include "peri/particles.h"
#include "peri/error.h"

void peri_particles_init(peri_particles *p, int dim) {
  memset(p, 0, sizeof *p);
  p->dim = dim;
}

/* Grows an array of `size`-byte elements from old_cap to new_cap, zeroing the new part;
 * arrays that were never allocated stay NULL. */
static void *grow(void *a, size_t size, int32_t old_cap, int32_t new_cap) {
  if (!a) return NULL;
  char *r = peri_realloc(a, size * (size_t)new_cap);
  memset(r + size * (size_t)old_cap, 0, size * (size_t)(new_cap - old_cap));
  return r;
}

static void reserve(peri_particles *p, int32_t need) {
  if (need <= p->capacity) return;
  int64_t cap = p->capacity ? p->capacity : 1024;
  while (cap < need) cap *= 2;
  if (cap > INT32_MAX) cap = INT32_MAX;
  int32_t old = p->capacity, nc = (int32_t)cap;
  /* The core arrays always exist once a node is added. */
  if (!p->x) {
    p->x = peri_calloc(1, 1);
    p->volume = peri_calloc(1, 1);
    p->material = peri_calloc(1, 1);
    p->block = peri_calloc(1, 1);
    p->flags = peri_calloc(1, 1);
    old = 0;
  }
  p->x = grow(p->x, 3 * sizeof(double), old, nc);
  p->volume = grow(p->volume, sizeof(double), old, nc);
  p->material = grow(p->material, sizeof(int32_t), old, nc);
  p->block = grow(p->block, sizeof(int32_t), old, nc);
  p->flags = grow(p->flags, sizeof(uint8_t), old, nc);
  /* State arrays, if already allocated, follow so that indices stay valid. */
  p->u = grow(p->u, 3 * sizeof(double), old, nc);
  p->v = grow(p->v, 3 * sizeof(double), old, nc);
  p->f = grow(p->f, 3 * sizeof(double), old, nc);
  p->b = grow(p->b, 3 * sizeof(double), old, nc);
  p->damage = grow(p->damage, sizeof(double), old, nc);
  p->capacity = nc;
}

int32_t peri_particles_add(peri_particles *p, const double x[3], double volume, int32_t material,
                           int32_t block) {
  if (p->n == INT32_MAX) {
    peri_error("too many particles (limit %d)", (int)INT32_MAX);
    exit(PERI_ERR_RUN);
  }
  reserve(p, p->n + 1);
  int32_t i = p->n;
  for (int d = 0; d < 3; d++) p->x[3 * i + d] = d < p->dim ? x[d] : 0.0;
  p->volume[i] = volume;
  p->material[i] = material;
  p->block[i] = block;
  p->flags[i] = 0;
  /* A node appended before any ghost exists is owned; after ghosts, it is a ghost. */
  if (p->n_owned == p->n) p->n_owned++;
  p->n++;
  return i;
}

void peri_particles_alloc_state(peri_particles *p) {
  /* Sized to the capacity so later appends (ghosts) need no special case. */
  size_t cap = (size_t)(p->capacity > p->n ? p->capacity : p->n);
  free(p->u);
  free(p->v);
  free(p->f);
  free(p->b);
  free(p->damage);
  p->u = peri_calloc(3 * cap, sizeof(double));
  p->v = peri_calloc(3 * cap, sizeof(double));
  p->f = peri_calloc(3 * cap, sizeof(double));
  p->b = peri_calloc(3 * cap, sizeof(double));
  p->damage = peri_calloc(cap, sizeof(double));
}

/* new[k] = old[perm[k]] for an array of n elements of `size` bytes. */
static void permute_array(void *a, size_t size, int32_t n, const int32_t *perm, void *tmp) {
  if (!a) return;
  char *src = a, *dst = tmp;
  for (int32_t k = 0; k < n; k++)
    memcpy(dst + size * (size_t)k, src + size * (size_t)perm[k], size);
  memcpy(src, dst, size * (size_t)n);
}

void peri_particles_permute(peri_particles *p, const int32_t *perm) {
  if (p->n <= 0) return;
  void *tmp = peri_malloc(3 * sizeof(double) * (size_t)p->n);
  permute_array(p->x, 3 * sizeof(double), p->n, perm, tmp);
  permute_array(p->u, 3 * sizeof(double), p->n, perm, tmp);
  permute_array(p->v, 3 * sizeof(double), p->n, perm, tmp);
  permute_array(p->f, 3 * sizeof(double), p->n, perm, tmp);
  permute_array(p->b, 3 * sizeof(double), p->n, perm, tmp);
  permute_array(p->volume, sizeof(double), p->n, perm, tmp);
  permute_array(p->material, sizeof(int32_t), p->n, perm, tmp);
  permute_array(p->block, sizeof(int32_t), p->n, perm, tmp);
  permute_array(p->flags, sizeof(uint8_t), p->n, perm, tmp);
  permute_array(p->damage, sizeof(double), p->n, perm, tmp);
  permute_array(p->theta, sizeof(double), p->n, perm, tmp);
  permute_array(p->wvol, sizeof(double), p->n, perm, tmp);
  permute_array(p->pstate, sizeof(double), p->n, perm, tmp);
  permute_array(p->energy, sizeof(double), p->n, perm, tmp);
  permute_array(p->smin, sizeof(double), p->n, perm, tmp);
  free(tmp);
}

void peri_particles_free(peri_particles *p) {
  free(p->x);
  free(p->u);
  free(p->v);
  free(p->f);
  free(p->b);
  free(p->volume);
  free(p->material);
  free(p->block);
  free(p->flags);
  free(p->damage);
  free(p->theta);
  free(p->wvol);
  free(p->pstate);
  free(p->energy);
  free(p->smin);
  free(p->coef);
  free(p->s0_bound);
  int dim = p->dim;
  peri_particles_init(p, dim);
}
