/* The frames as one Exodus II file (output.format exodus, docs/output.md): rank 0 gathers
 * every rank's owned nodes in the global node order and writes one file, so that the file,
 * like the picture, does not depend on the number of ranks. Node k of the file is the node
 * with node_id k + 1 in the VTU frames. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/exodus_writer.h"
#include "peri/frames.h"
#include "peri/history.h"
#include "frames_parts.h"

struct peri_frames_exodus {
  peri_exodus *file; /* rank 0 */
  char *path, *create_path;
  int64_t n;          /* global nodes */
  int n_vars;         /* node variables (field components) */
  int n_history;
  double *history;    /* the latest history row */
  bool history_seen;
  int pending_step;   /* the last step written whose globals await a row of its time (0: none) */
  double pending_time;
  int steps;
};

static bool is_vector(const char *name) {
  return !strcmp(name, "displacement") || !strcmp(name, "velocity") || !strcmp(name, "force") ||
         !strcmp(name, "heat_flux");
}

/* The node variables of one field: vectors by axis (the problem's dimensions; ParaView joins
 * name_x, name_y, name_z into a vector), tensors by row and column, principal values by rank. */
static int component_names(const char *name, int ncomp, int dim, char names[9][96]) {
  static const char *const tensor[9] = {"xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"};
  if (ncomp == 1) {
    snprintf(names[0], 96, "%s", name);
    return 1;
  }
  if (ncomp == 3 && is_vector(name)) {
    for (int d = 0; d < dim; ++d) snprintf(names[d], 96, "%s_%c", name, "xyz"[d]);
    return dim;
  }
  for (int c = 0; c < ncomp; ++c) {
    if (ncomp == 9) snprintf(names[c], 96, "%s_%s", name, tensor[c]);
    else snprintf(names[c], 96, "%s_%d", name, c + 1);
  }
  return ncomp;
}

/* Element blocks: one per distinct (block, material) pair of the nodes, in ascending order.
 * Ids are the deck's block numbers when those are positive and each has one material
 * (Peridigm's meshes, fill shapes), else 1, 2, ... */
static int make_blocks(int64_t n, const double *block, const double *material, const peri_sim *s, int32_t *group,
                       int32_t **ids, char ***names) {
  int count = 0, cap = 8;
  long(*pairs)[2] = peri_malloc(sizeof *pairs * (size_t)cap);
  for (int64_t k = 0; k < n; ++k) {
    long b = lround(block[k]), m = lround(material[k]);
    int at = 0;
    while (at < count && (pairs[at][0] < b || (pairs[at][0] == b && pairs[at][1] < m))) ++at;
    if (at == count || pairs[at][0] != b || pairs[at][1] != m) {
      if (count == cap) pairs = peri_realloc(pairs, sizeof *pairs * (size_t)(cap *= 2));
      memmove(pairs + at + 1, pairs + at, sizeof *pairs * (size_t)(count - at));
      pairs[at][0] = b, pairs[at][1] = m;
      ++count;
    }
  }
  bool own_ids = true;
  for (int j = 0; j < count; ++j) own_ids = own_ids && pairs[j][0] > 0 && (j == 0 || pairs[j][0] != pairs[j - 1][0]);
  *ids = peri_malloc(sizeof(int32_t) * (size_t)(count > 0 ? count : 1));
  *names = peri_calloc((size_t)(count > 0 ? count : 1), sizeof(char *));
  for (int j = 0; j < count; ++j) {
    (*ids)[j] = own_ids ? (int32_t)pairs[j][0] : j + 1;
    char name[256];
    const long m = pairs[j][1];
    const char *material_name = m >= 0 && m < s->mat.n_materials ? s->mat.materials[m].name : "?";
    snprintf(name, sizeof name, "block_%ld_%s", pairs[j][0], material_name ? material_name : "?");
    (*names)[j] = peri_strdup(name);
  }
  for (int64_t k = 0; k < n; ++k) { /* binary search of the node's pair */
    long b = lround(block[k]), m = lround(material[k]);
    int lo = 0, hi = count - 1;
    while (lo < hi) {
      int mid = (lo + hi) / 2;
      if (pairs[mid][0] < b || (pairs[mid][0] == b && pairs[mid][1] < m)) lo = mid + 1;
      else hi = mid;
    }
    group[k] = lo;
  }
  free(pairs);
  return count;
}

/* Rank 0: the mesh of the gathered reference configuration and the variable names. */
static peri_exodus *create_file(peri_frames_exodus *x, const peri_sim *s, const double *ref, const double *volume,
                                const double *block, const double *material) {
  int32_t *group = peri_malloc(sizeof(int32_t) * (size_t)(x->n > 0 ? x->n : 1));
  int32_t *ids = NULL;
  char **block_names = NULL;
  const int n_blocks = make_blocks(x->n, block, material, s, group, &ids, &block_names);
  char title[256];
  snprintf(title, sizeof title, "peri %s: %s", PERI_VERSION, s->out.basename);
  const peri_exodus_mesh mesh = {.title = title, .dim = s->disc.geom.dim, .n = x->n, .reference = ref,
                                 .volume = volume, .group = group, .n_blocks = n_blocks, .block_ids = ids,
                                 .block_names = (const char *const *)block_names};
  /* node variables: the components of the frame fields */
  char **vars = NULL;
  int n_vars = 0;
  for (int k = 0; k < s->out.n_fields; ++k) {
    const int ncomp = peri_frame_field_components(s, s->out.fields[k]);
    if (ncomp == 0) continue;
    char names[9][96];
    const int m = component_names(s->out.fields[k], ncomp, s->disc.geom.dim, names);
    vars = peri_realloc(vars, sizeof(char *) * (size_t)(n_vars + m));
    for (int c = 0; c < m; ++c) vars[n_vars++] = peri_strdup(names[c]);
  }
  x->n_vars = n_vars;
  char **columns = peri_history_columns(s, &x->n_history);
  peri_exodus *file = peri_exodus_create(x->create_path, &mesh, n_vars, (const char *const *)vars, x->n_history,
                                         (const char *const *)columns);
  peri_history_columns_free(columns, x->n_history);
  for (int v = 0; v < n_vars; ++v) free(vars[v]);
  free(vars);
  for (int b = 0; b < n_blocks; ++b) free(block_names[b]);
  free(block_names);
  free(ids);
  free(group);
  return file;
}

peri_frames_exodus *peri_frames_exodus_open(const peri_sim *s, const char *path, const char *create_path) {
  peri_frames_exodus *x = peri_calloc(1, sizeof *x);
  x->path = peri_strdup(path);
  x->create_path = peri_strdup(create_path);
  x->n = peri_global_nodes(s);
  const peri_particles *p = &s->disc.p;
  const size_t n_owned = (size_t)p->n_owned, all = (size_t)(x->n > 0 ? x->n : 1);
  const bool root = peri_comm_rank() == 0;
  double *local = peri_malloc(sizeof(double) * 2 * (n_owned > 0 ? n_owned : 1));
  for (size_t i = 0; i < n_owned; ++i) local[2 * i] = p->block[i], local[2 * i + 1] = p->material[i];
  double *ref = root ? peri_malloc(sizeof(double) * 3 * all) : NULL;
  double *volume = root ? peri_malloc(sizeof(double) * all) : NULL;
  double *labels = root ? peri_malloc(sizeof(double) * 2 * all) : NULL;
  peri_gather_owned(s, p->x, 3, ref);
  peri_gather_owned(s, p->volume, 1, volume);
  peri_gather_owned(s, local, 2, labels);
  free(local);
  int failed = 0;
  if (root) {
    double *block = peri_malloc(sizeof(double) * all), *material = peri_malloc(sizeof(double) * all);
    for (size_t k = 0; k < (size_t)x->n; ++k) block[k] = labels[2 * k], material[k] = labels[2 * k + 1];
    x->file = create_file(x, s, ref, volume, block, material);
    failed = !x->file;
    x->history = peri_calloc((size_t)(x->n_history > 0 ? x->n_history : 1), sizeof(double));
    free(block);
    free(material);
  }
  free(ref);
  free(volume);
  free(labels);
  if (peri_comm_max_int(failed)) {
    peri_frames_exodus_close(x);
    return NULL;
  }
  return x;
}

/* The globals of the step just written: the latest history row if it is of this time, else
 * NaN until a row of this time arrives (peri_frames_exodus_history). */
int peri_frames_exodus_write(peri_frames_exodus *x, const peri_sim *s, const peri_field *fields, int n_fields) {
  const bool root = peri_comm_rank() == 0;
  const size_t all = (size_t)(x->n > 0 ? x->n : 1), n_owned = (size_t)s->disc.p.n_owned;
  double **vars = root ? peri_calloc((size_t)(x->n_vars > 0 ? x->n_vars : 1), sizeof(double *)) : NULL;
  double *gathered = root ? peri_malloc(sizeof(double) * 9 * all) : NULL;
  double *as_double = NULL;
  int v = 0;
  for (int k = 0; k < n_fields; ++k) {
    const peri_field *fl = &fields[k];
    const double *data = fl->data;
    if (fl->idata) { /* material, block: written as doubles, as Exodus holds node variables */
      as_double = peri_realloc(as_double, sizeof(double) * (n_owned > 0 ? n_owned : 1));
      for (size_t i = 0; i < n_owned; ++i) as_double[i] = fl->idata[i];
      data = as_double;
    }
    peri_gather_owned(s, data, fl->ncomp, gathered);
    if (!root) continue;
    char names[9][96];
    const int m = component_names(fl->name, fl->ncomp, s->disc.geom.dim, names);
    for (int c = 0; c < m && v < x->n_vars; ++c, ++v) {
      vars[v] = peri_malloc(sizeof(double) * all);
      for (size_t i = 0; i < (size_t)x->n; ++i) vars[v][i] = gathered[(size_t)fl->ncomp * i + (size_t)c];
    }
  }
  free(as_double);
  int rc = PERI_OK;
  if (root) {
    if (v != x->n_vars) {
      peri_error("cannot write '%s': the frame has %d field components, the file %d", x->path, v, x->n_vars);
      rc = PERI_ERR_RUN;
    }
    const double time = s->state.time;
    const bool matching = x->history_seen && x->n_history > 0 && x->history[0] == time;
    double *globals = peri_malloc(sizeof(double) * (size_t)(x->n_history > 0 ? x->n_history : 1));
    for (int j = 0; j < x->n_history; ++j) globals[j] = matching ? x->history[j] : NAN;
    if (rc == PERI_OK) rc = peri_exodus_write_step(x->file, time, (const double *const *)vars, globals);
    free(globals);
    if (rc == PERI_OK) {
      x->steps = peri_exodus_steps(x->file);
      x->pending_step = matching ? 0 : x->steps;
      x->pending_time = time;
    }
    for (int j = 0; j < x->n_vars; ++j) free(vars[j]);
    free(vars);
    free(gathered);
  }
  return peri_comm_max_int(rc);
}

void peri_frames_exodus_history(peri_frames_exodus *x, const double *row) {
  if (!x->file) return; /* rank 0 writes */
  memcpy(x->history, row, sizeof(double) * (size_t)x->n_history);
  x->history_seen = true;
  if (x->pending_step > 0 && x->n_history > 0 && row[0] == x->pending_time) {
    /* the frame came first (the one at t = 0): its globals now */
    peri_exodus_globals(x->file, x->pending_step, row);
    x->pending_step = 0;
  }
}

int peri_frames_exodus_resume(peri_frames_exodus *x, long next) {
  int rc = PERI_OK;
  if (x->file) {
    FILE *old = fopen(x->path, "rb");
    if (old) fclose(old);
    if (!old) /* a restart into another directory: nothing to keep, as for the .pvd */
      peri_warning("restart: no '%s' to continue: the new Exodus file holds the frames after the checkpoint only",
                   x->path);
    else
      rc = peri_exodus_copy_steps(x->file, x->path, (int)next);
    if (rc == PERI_OK && strcmp(x->path, x->create_path) && rename(x->create_path, x->path) != 0) {
      peri_error("restart: cannot replace '%s' by '%s'", x->path, x->create_path);
      rc = PERI_ERR_RUN;
    }
    if (rc == PERI_OK) {
      free(x->create_path);
      x->create_path = peri_strdup(x->path);
    }
  }
  return peri_comm_max_int(rc);
}

void peri_frames_exodus_close(peri_frames_exodus *x) {
  if (!x) return;
  peri_exodus_close(x->file);
  if (x->file && strcmp(x->path, x->create_path)) remove(x->create_path); /* a restart that never resumed */
  free(x->history);
  free(x->path);
  free(x->create_path);
  free(x);
}
