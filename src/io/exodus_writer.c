/* Exodus II results file through the Exodus C API (include/peri/exodus_writer.h). The layout
 * follows Peridigm's sphere-element meshes: one SPHERE element of one node per node, the node
 * volume as the element attribute `volume`, so that the file is also a valid mesh for a
 * reader of that convention. Built only when the library is found (PERI_HAVE_EXODUS). */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/exodus_writer.h"

#ifdef PERI_HAVE_EXODUS
#include <exodusII.h>

/* Longest variable and block name the file holds (Exodus' default is 32, too short for
 * history columns such as reaction_REGION_x; ParaView reads longer names). */
enum { EXODUS_NAME_LENGTH = 80 };

struct peri_exodus {
  int id;
  char *path;
  int64_t n;
  int n_node_vars, n_global_vars, steps;
  double *zeros; /* global values when the caller has none */
};

bool peri_exodus_available(void) { return true; }

/* The library's last message after a failed call. */
static int fail(const char *path, const char *what) {
  const char *msg = NULL, *func = NULL;
  int code = 0;
  ex_get_err(&msg, &func, &code);
  peri_error("cannot write '%s': %s failed%s%s", path, what, msg && *msg ? ": " : "", msg && *msg ? msg : "");
  return PERI_ERR_RUN;
}

static int put_mesh(peri_exodus *e, const peri_exodus_mesh *m) {
  const int id = e->id;
  const size_t n = (size_t)m->n;
  if (ex_put_init(id, m->title, m->dim, m->n, m->n, m->n_blocks, 0, 0) < 0) return fail(e->path, "ex_put_init");
  double *c = peri_malloc(sizeof(double) * 3 * (n > 0 ? n : 1));
  for (size_t k = 0; k < n; ++k)
    for (int d = 0; d < 3; ++d) c[d * n + k] = m->reference[3 * k + d];
  int rc = ex_put_coord(id, c, m->dim > 1 ? c + n : NULL, m->dim > 2 ? c + 2 * n : NULL);
  free(c);
  if (rc < 0) return fail(e->path, "ex_put_coord");
  char *axes[3] = {"x", "y", "z"};
  if (ex_put_coord_names(id, axes) < 0) return fail(e->path, "ex_put_coord_names");
  /* elements block by block, each block's nodes ascending; element ids are the node ids */
  int64_t *elem_ids = peri_malloc(sizeof(int64_t) * (n > 0 ? n : 1));
  int64_t *conn = peri_malloc(sizeof(int64_t) * (n > 0 ? n : 1));
  double *attr = peri_malloc(sizeof(double) * (n > 0 ? n : 1));
  size_t placed = 0;
  for (int b = 0; b < m->n_blocks && rc >= 0; ++b) {
    size_t count = 0;
    for (size_t k = 0; k < n; ++k)
      if (m->group[k] == b) conn[count] = (int64_t)k + 1, attr[count++] = m->volume[k];
    for (size_t j = 0; j < count; ++j) elem_ids[placed + j] = conn[j];
    placed += count;
    char *attr_name[1] = {"volume"};
    if ((rc = ex_put_block(id, EX_ELEM_BLOCK, m->block_ids[b], "SPHERE", (int64_t)count, 1, 0, 0, 1)) < 0)
      fail(e->path, "ex_put_block");
    else if (count > 0 && (rc = ex_put_conn(id, EX_ELEM_BLOCK, m->block_ids[b], conn, NULL, NULL)) < 0)
      fail(e->path, "ex_put_conn");
    else if (count > 0 && (rc = ex_put_attr(id, EX_ELEM_BLOCK, m->block_ids[b], attr)) < 0)
      fail(e->path, "ex_put_attr");
    else if ((rc = ex_put_attr_names(id, EX_ELEM_BLOCK, m->block_ids[b], attr_name)) < 0)
      fail(e->path, "ex_put_attr_names");
    else if ((rc = ex_put_name(id, EX_ELEM_BLOCK, m->block_ids[b], m->block_names[b])) < 0)
      fail(e->path, "ex_put_name");
  }
  if (rc >= 0 && placed != n) {
    peri_error("cannot write '%s': %zu of %zu nodes are in no element block", e->path, n - placed, n);
    rc = -1;
  }
  if (rc >= 0 && (rc = ex_put_id_map(id, EX_ELEM_MAP, elem_ids)) < 0) fail(e->path, "ex_put_id_map (elements)");
  for (size_t k = 0; rc >= 0 && k < n; ++k) conn[k] = (int64_t)k + 1;
  if (rc >= 0 && (rc = ex_put_id_map(id, EX_NODE_MAP, conn)) < 0) fail(e->path, "ex_put_id_map (nodes)");
  free(attr);
  free(conn);
  free(elem_ids);
  return rc < 0 ? PERI_ERR_RUN : PERI_OK;
}

static int put_names(peri_exodus *e, ex_entity_type type, int count, const char *const *names) {
  if (count == 0) return PERI_OK;
  if (ex_put_variable_param(e->id, type, count) < 0) return fail(e->path, "ex_put_variable_param");
  if (ex_put_variable_names(e->id, type, count, (char **)names) < 0) return fail(e->path, "ex_put_variable_names");
  return PERI_OK;
}

peri_exodus *peri_exodus_create(const char *path, const peri_exodus_mesh *mesh, int n_node_vars,
                                const char *const *node_var_names, int n_global_vars,
                                const char *const *global_var_names) {
  ex_opts(0); /* errors come back as return values, reported here; the library neither prints nor aborts */
  int cpu_word = 8, io_word = 8; /* doubles in memory and in the file */
  int id = ex_create(path, EX_CLOBBER | EX_LARGE_MODEL, &cpu_word, &io_word);
  if (id < 0) {
    fail(path, "ex_create");
    return NULL;
  }
  ex_set_int64_status(id, EX_ALL_INT64_API); /* ids, counts and maps are passed as int64_t */
  ex_set_max_name_length(id, EXODUS_NAME_LENGTH);
  peri_exodus *e = peri_calloc(1, sizeof *e);
  *e = (peri_exodus){.id = id, .path = peri_strdup(path), .n = mesh->n, .n_node_vars = n_node_vars,
                     .n_global_vars = n_global_vars};
  e->zeros = peri_calloc((size_t)(n_global_vars > 0 ? n_global_vars : 1), sizeof(double));
  if (put_mesh(e, mesh) != PERI_OK || put_names(e, EX_NODAL, n_node_vars, node_var_names) != PERI_OK ||
      put_names(e, EX_GLOBAL, n_global_vars, global_var_names) != PERI_OK) {
    peri_exodus_close(e);
    return NULL;
  }
  if (ex_update(id) < 0) {
    fail(path, "ex_update");
    peri_exodus_close(e);
    return NULL;
  }
  return e;
}

int peri_exodus_write_step(peri_exodus *e, double time, const double *const *node_vars, const double *globals) {
  const int step = e->steps + 1; /* Exodus counts steps from 1 */
  if (ex_put_time(e->id, step, &time) < 0) return fail(e->path, "ex_put_time");
  for (int v = 0; v < e->n_node_vars; ++v)
    if (ex_put_var(e->id, step, EX_NODAL, v + 1, 1, e->n, node_vars[v]) < 0) return fail(e->path, "ex_put_var (nodal)");
  if (e->n_global_vars > 0 &&
      ex_put_var(e->id, step, EX_GLOBAL, 1, 0, e->n_global_vars, globals ? globals : e->zeros) < 0)
    return fail(e->path, "ex_put_var (global)");
  if (ex_update(e->id) < 0) return fail(e->path, "ex_update");
  e->steps = step;
  return PERI_OK;
}

int peri_exodus_globals(peri_exodus *e, int step, const double *globals) {
  if (e->n_global_vars == 0) return PERI_OK;
  if (ex_put_var(e->id, step, EX_GLOBAL, 1, 0, e->n_global_vars, globals) < 0) return fail(e->path, "ex_put_var (global)");
  if (ex_update(e->id) < 0) return fail(e->path, "ex_update");
  return PERI_OK;
}

int peri_exodus_copy_steps(peri_exodus *e, const char *old_path, int n_steps) {
  if (n_steps <= 0) return PERI_OK;
  int cpu_word = 8, io_word = 0;
  float version = 0.0f;
  int old = ex_open(old_path, EX_READ, &cpu_word, &io_word, &version);
  if (old < 0) {
    peri_error("restart: cannot open '%s', the Exodus file of the run to continue", old_path);
    return PERI_ERR_RUN;
  }
  ex_set_int64_status(old, EX_ALL_INT64_API);
  int node_vars = 0, global_vars = 0;
  ex_get_variable_param(old, EX_NODAL, &node_vars);
  ex_get_variable_param(old, EX_GLOBAL, &global_vars);
  const int64_t steps = ex_inquire_int(old, EX_INQ_TIME), nodes = ex_inquire_int(old, EX_INQ_NODES);
  int rc = PERI_OK;
  if (nodes != e->n || node_vars != e->n_node_vars || global_vars != e->n_global_vars || steps < n_steps) {
    peri_error("restart: '%s' has %lld nodes, %d node and %d global variables and %lld time steps; the run "
               "continued from the checkpoint needs %lld nodes, %d and %d variables and %d steps",
               old_path, (long long)nodes, node_vars, global_vars, (long long)steps, (long long)e->n,
               e->n_node_vars, e->n_global_vars, n_steps);
    rc = PERI_ERR_RUN;
  }
  const size_t n = (size_t)e->n;
  double **values = peri_calloc((size_t)(node_vars > 0 ? node_vars : 1), sizeof(double *));
  double *globals = peri_calloc((size_t)(global_vars > 0 ? global_vars : 1), sizeof(double));
  for (int v = 0; v < node_vars; ++v) values[v] = peri_malloc(sizeof(double) * (n > 0 ? n : 1));
  for (int step = 1; rc == PERI_OK && step <= n_steps; ++step) {
    double time = 0.0;
    bool ok = ex_get_time(old, step, &time) >= 0;
    for (int v = 0; ok && v < node_vars; ++v) ok = ex_get_var(old, step, EX_NODAL, v + 1, 1, e->n, values[v]) >= 0;
    if (ok && global_vars > 0) ok = ex_get_var(old, step, EX_GLOBAL, 1, 0, global_vars, globals) >= 0;
    if (!ok) {
      peri_error("restart: cannot read time step %d of '%s'", step, old_path);
      rc = PERI_ERR_RUN;
    } else {
      rc = peri_exodus_write_step(e, time, (const double *const *)values, globals);
    }
  }
  for (int v = 0; v < node_vars; ++v) free(values[v]);
  free(values);
  free(globals);
  ex_close(old);
  return rc;
}

int peri_exodus_steps(const peri_exodus *e) { return e ? e->steps : 0; }

int peri_exodus_close(peri_exodus *e) {
  if (!e) return PERI_OK;
  int rc = ex_close(e->id) < 0 ? fail(e->path, "ex_close") : PERI_OK;
  free(e->zeros);
  free(e->path);
  free(e);
  return rc;
}

#else /* built without the Exodus II library: the deck refuses output.format exodus */

struct peri_exodus {
  int unused;
};

bool peri_exodus_available(void) { return false; }

peri_exodus *peri_exodus_create(const char *path, const peri_exodus_mesh *mesh, int n_node_vars,
                                const char *const *node_var_names, int n_global_vars,
                                const char *const *global_var_names) {
  (void)mesh, (void)n_node_vars, (void)node_var_names, (void)n_global_vars, (void)global_var_names;
  peri_error("cannot write '%s': this peri was built without the Exodus II library (libexodusii-dev)", path);
  return NULL;
}

int peri_exodus_write_step(peri_exodus *e, double time, const double *const *node_vars, const double *globals) {
  (void)e, (void)time, (void)node_vars, (void)globals;
  return PERI_ERR_RUN;
}

int peri_exodus_globals(peri_exodus *e, int step, const double *globals) {
  (void)e, (void)step, (void)globals;
  return PERI_ERR_RUN;
}

int peri_exodus_copy_steps(peri_exodus *e, const char *old_path, int n_steps) {
  (void)e, (void)old_path, (void)n_steps;
  return PERI_ERR_RUN;
}

int peri_exodus_steps(const peri_exodus *e) {
  (void)e;
  return 0;
}

int peri_exodus_close(peri_exodus *e) {
  (void)e;
  return PERI_OK;
}
#endif
