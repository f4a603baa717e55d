/* Checkpoint files (docs/restart.md): the state of a run in HDF5, written through a
 * temporary file and a rename, and read back and checked against the deck for a restart.
 *
 * Layout (format version 1):
 *   /                 attributes format = "peri checkpoint", format_version, peri_version,
 *                     deck_path, model, solver, solver_name, dimension
 *   /deck_text        the deck file as it was when the checkpoint was written
 *   /state            attributes time, step, steps, dt, external_work, frames, history_rows
 *   /discretization   attributes n_nodes, n_bonds, bond_hash; dataset x [n][3]
 *   /nodes            u, v, f [n][3], damage [n]; theta, wvol, pstate, smin, s0,
 *                     thermal_strain [n] and step_load [n][3] when the run has them
 *   /bonds/broken     [n_bonds] uint8, 0 intact / 1 broken, in bond (CSR) order
 *   /bonds/plastic_stretch [n_bonds][layers] doubles, the sublayers' plastic stretches
 *                     (docs/plasticity.md), when a material is plastic
 *   /nodes/plastic_tensor [n][6 layers] doubles, the tensor yield rule's plastic tensors
 *                     (sublayer by sublayer, xx yy zz xy xz yz; docs/plasticity.md section 10)
 *   /indenter/force   [3]
 *   /tools/K          (a deck with tools: one group per tool, K = 0, 1, ... in the deck's order)
 *                     attribute name; state [TOOL_STATE] doubles (tool_state_pack)
 *   /quasi_static     attributes reference, last_reference, residual, iterations, solves,
 *                     force_evaluations, cutbacks, dynamic_time, dynamic_phases, dynamic_steps
 *   /thermal          attributes time, growing_next, every, substeps; T [n]; cut [n_bonds]
 *                     (only when conduction keeps its own cut flags)
 * Node arrays hold every node in the node order of the discretization, bond arrays every
 * directed bond in CSR order: both are deterministic functions of the deck. On MPI ranks
 * rank 0 gathers them in that order and writes the same file; a restart reads it on every
 * rank before the decomposition and takes each rank's part after it. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <fcntl.h>
#include <string.h>
#include "peri/checkpoint.h"
#include "peri/comm.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/plasticity.h"
#include "peri/tensor_plasticity.h"
#include "peri/thermal.h"
#include "peri/tools.h"

/* What a restart carries from the checkpoint to the run (filled by peri_restart_load). */
struct peri_restart {
  char *path;
  double time, external_work;
  long step;
  peri_checkpoint_progress done;
  int32_t n;
  int64_t n_bonds;
  double *u, *v, *f, *damage, *theta, *wvol, *pstate, *smin, *s0, *thermal_strain, *step_load;
  uint8_t *broken;
  double *plastic; /* [n_bonds * plastic_layers] */
  double *plastic_tensor; /* [n * 6 * layers] of the tensor rule */
  double indenter_force[3];
  double *tools; /* [count * TOOL_STATE]: each tool's state (tool_state_pack) */
  peri_quasi_static qs;
  bool thermal;
  double thermal_time;
  long growing_next, every, substeps;
  double *T;
  uint8_t *cut;
  int64_t *growing_cut; /* global bonds of the first growing_next growing-crack cuts */
  /* output kept from before the checkpoint */
  double *history;
  long history_rows;
  int history_columns;
  char **history_names;
  long frames_listed;
  double *frame_times;
  char **frame_files;
};

/* A tool's state between evaluations, as doubles in a fixed order: its load-controlled offset
 * and rate, the load search's compliance, the contact force of the last evaluation (which
 * an explicit step's load control reads), the sliding distance and where it counts from,
 * the first contact, and the flags. What a tool evaluates afresh (block sums) is left out. */
enum { TOOL_STATE = 29 };

#ifdef PERI_HAVE_HDF5 /* (written only with HDF5) */
static void tool_state_pack(const peri_tool *tl, double out[TOOL_STATE]) {
  double *o = out;
  *o++ = tl->q, *o++ = tl->q_rate, *o++ = tl->load_compliance;
  *o++ = tl->normal_force, *o++ = tl->tangential_force, *o++ = tl->contact_area;
  *o++ = tl->sliding, *o++ = tl->last_t;
  *o++ = tl->touched ? 1.0 : 0.0, *o++ = tl->started ? 1.0 : 0.0;
  const double *vectors[] = {tl->at, tl->velocity, tl->force, tl->last_at, tl->start, tl->contact_at};
  for (int k = 0; k < 6; ++k)
    for (int d = 0; d < 3; ++d) *o++ = vectors[k][d];
  *o++ = 0.0; /* reserved */
}
#endif

static void tool_state_unpack(peri_tool *tl, const double in[TOOL_STATE]) {
  const double *i = in;
  tl->q = *i++, tl->q_rate = *i++, tl->load_compliance = *i++;
  tl->normal_force = *i++, tl->tangential_force = *i++, tl->contact_area = *i++;
  tl->sliding = *i++, tl->last_t = *i++;
  tl->touched = *i++ != 0.0, tl->started = *i++ != 0.0;
  double *vectors[] = {tl->at, tl->velocity, tl->force, tl->last_at, tl->start, tl->contact_at};
  for (int k = 0; k < 6; ++k)
    for (int d = 0; d < 3; ++d) vectors[k][d] = *i++;
}

void peri_restart_free(struct peri_restart *r) {
  if (!r) return;
  double *arrays[] = {r->u, r->v, r->f, r->damage, r->theta, r->wvol, r->pstate, r->smin, r->s0,
                      r->thermal_strain, r->step_load, r->T, r->history, r->frame_times};
  for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; ++k) free(arrays[k]);
  free(r->broken);
  free(r->plastic);
  free(r->plastic_tensor);
  free(r->tools);
  free(r->cut);
  free(r->growing_cut);
  for (long k = 0; k < r->frames_listed; ++k) free(r->frame_files[k]);
  free(r->frame_files);
  for (int k = 0; r->history_names && k < r->history_columns; ++k) free(r->history_names[k]);
  free(r->history_names);
  free(r->path);
  free(r);
}

const double *peri_restart_history(const peri_sim *s, long *rows, int *n_columns) {
  const struct peri_restart *r = s->state.restart;
  *rows = r ? r->history_rows : 0;
  *n_columns = r ? r->history_columns : 0;
  return r && r->history_rows > 0 ? r->history : NULL;
}

char *const *peri_restart_history_names(const peri_sim *s, int *n_columns) {
  const struct peri_restart *r = s->state.restart;
  *n_columns = r && r->history_names ? r->history_columns : 0;
  return r ? r->history_names : NULL;
}

long peri_restart_frames(const peri_sim *s, long *n_listed, const double **times, char *const **files) {
  const struct peri_restart *r = s->state.restart;
  *n_listed = r ? r->frames_listed : 0;
  *times = r ? r->frame_times : NULL;
  *files = r ? r->frame_files : NULL;
  return r ? r->done.frames : 0;
}

void peri_restart_print(const peri_sim *s, FILE *out) {
  const struct peri_restart *r = s->state.restart;
  if (!r) return;
  fprintf(out, "  restart      from %s at step %ld (t = %g s), %ld frames and %ld history rows kept\n", r->path,
          r->step, r->time, r->frames_listed, r->history_rows);
}

/* A node array of the checkpoint (every node, global order) into the local nodes of s:
 * the same order in one process; on MPI ranks the owned nodes and ghosts by global index. */
static void copy_nodes(const peri_sim *s, double *to, const double *from, int ncomp) {
  if (!to || !from) return;
  const peri_decomposition *d = s->par.dd;
  if (!d) {
    memcpy(to, from, sizeof(double) * (size_t)ncomp * (size_t)s->state.restart->n);
    return;
  }
  for (int32_t l = 0; l < s->disc.p.n; ++l)
    memcpy(to + (size_t)ncomp * l, from + (size_t)ncomp * d->global_id[l], sizeof(double) * (size_t)ncomp);
}

/* A bond array of the checkpoint (global CSR order) into the families of s: on MPI ranks
 * the run of the global order that this rank's owned nodes hold. */
static void copy_bonds(const peri_sim *s, uint8_t *to, const uint8_t *from) {
  const int64_t first = s->par.dd ? s->par.dd->bond_first[s->par.dd->rank] : 0;
  if (to && from && s->disc.bonds.n_bonds > 0) memcpy(to, from + first, (size_t)s->disc.bonds.n_bonds);
}

/* The growing-crack cuts already made among this rank's bonds: decomposition keeps the
 * growing bonds of the rank's families in the global cut order, so they are those of the
 * checkpoint's first growing_next cuts that fall in the rank's run of bonds. */
static int64_t growing_next_local(const peri_sim *s, const struct peri_restart *r) {
  if (!s->par.dd) return r->growing_next;
  const int64_t first = s->par.dd->bond_first[s->par.dd->rank], end = first + s->disc.bonds.n_bonds;
  int64_t next = 0;
  for (long a = 0; a < r->growing_next; ++a)
    if (r->growing_cut[a] >= first && r->growing_cut[a] < end) ++next;
  return next;
}

/* The checkpoint's arrays, once their values are in the simulation: on MPI ranks each
 * holds the whole problem, which a rank should not keep for the rest of the run. */
static void release_arrays(struct peri_restart *r) {
  double **arrays[] = {&r->u, &r->v, &r->f, &r->damage, &r->theta, &r->wvol, &r->pstate, &r->smin, &r->s0,
                       &r->thermal_strain, &r->step_load, &r->T};
  for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; ++k) {
    free(*arrays[k]);
    *arrays[k] = NULL;
  }
  free(r->broken);
  free(r->plastic);
  r->plastic = NULL;
  free(r->plastic_tensor);
  r->plastic_tensor = NULL;
  free(r->tools);
  r->tools = NULL;
  free(r->cut);
  free(r->growing_cut);
  r->broken = r->cut = NULL;
  r->growing_cut = NULL;
}

void peri_restart_apply(peri_sim *s) {
  struct peri_restart *r = s->state.restart;
  if (!r) return;
  peri_particles *p = &s->disc.p;
  const size_t n3 = 3 * (size_t)p->n; /* local nodes: owned and ghosts */
  s->state.time = r->time;
  s->state.step = r->step;
  s->state.external_work = r->external_work;
  copy_nodes(s, p->u, r->u, 3);
  copy_nodes(s, p->v, r->v, 3);
  copy_nodes(s, p->f, r->f, 3);
  copy_nodes(s, p->damage, r->damage, 1);
  copy_nodes(s, p->theta, r->theta, 1);
  copy_nodes(s, p->wvol, r->wvol, 1);
  copy_nodes(s, p->pstate, r->pstate, 1);
  copy_nodes(s, p->smin, r->smin, 1);
  copy_nodes(s, s->mat.s0_node, r->s0, 1);
  copy_nodes(s, s->state.thermal_strain, r->thermal_strain, 1);
  if (r->step_load) {
    if (!s->state.step_load) s->state.step_load = peri_calloc(n3 ? n3 : 1, sizeof(double));
    copy_nodes(s, s->state.step_load, r->step_load, 3);
  }
  copy_bonds(s, s->disc.bonds.broken, r->broken);
  ++s->disc.bonds.broken_edits;
  if (r->plastic && s->state.plastic_stretch && s->disc.bonds.n_bonds > 0) {
    peri_plastic_state_in_bond_order(s); /* (the deviatoric rule takes it into its slots again) */
    const size_t layers = (size_t)s->state.plastic_layers;
    const int64_t first = s->par.dd ? s->par.dd->bond_first[s->par.dd->rank] : 0;
    memcpy(s->state.plastic_stretch, r->plastic + (size_t)first * layers,
           sizeof(double) * layers * (size_t)s->disc.bonds.n_bonds);
    if (s->state.plastic_committed) /* a checkpoint is written at an accepted load step */
      memcpy(s->state.plastic_committed, s->state.plastic_stretch,
             sizeof(double) * layers * (size_t)s->disc.bonds.n_bonds);
    free(s->state.plastic_nodes), s->state.plastic_nodes = NULL; /* (rebuilt from the state) */
  }
  if (r->plastic_tensor) peri_tensor_set_state_rows(s, r->plastic_tensor, s->par.dd ? s->par.dd->global_id : NULL);
  memcpy(s->cond.indenter.force, r->indenter_force, sizeof r->indenter_force);
  if (r->tools)
    for (int k = 0; k < s->tools->count; ++k) tool_state_unpack(&s->tools->tool[k], r->tools + (size_t)k * TOOL_STATE);
  peri_quasi_static *q = &s->solver.qs;
  q->reference = r->qs.reference;
  q->last_reference = r->qs.last_reference;
  q->residual = r->qs.residual;
  q->iterations = r->qs.iterations;
  q->solves = r->qs.solves;
  q->force_evaluations = r->qs.force_evaluations;
  q->cutbacks = r->qs.cutbacks;
  q->dynamic_time = r->qs.dynamic_time;
  q->dynamic_phases = r->qs.dynamic_phases;
  q->dynamic_steps = r->qs.dynamic_steps;
  peri_thermal *th = s->thermal;
  if (th && r->thermal) {
    th->time = r->thermal_time;
    th->growing_next = growing_next_local(s, r);
    th->every = r->every;
    th->substeps = r->substeps;
    copy_nodes(s, th->T, r->T, 1);
    /* a private copy of the cut flags (one-way coupling); otherwise they are the broken flags */
    if (th->own_cut) copy_bonds(s, th->cut, r->cut);
  }
  release_arrays(r);
}

static const char *solver_kind_name(peri_solver_kind k) {
  switch (k) {
  case PERI_SOLVER_EXPLICIT: return "explicit";
  case PERI_SOLVER_ADR: return "adr";
  case PERI_SOLVER_DYNAMIC_RELAXATION: return "dynamic_relaxation";
  case PERI_SOLVER_NLCG: return "nlcg";
  case PERI_SOLVER_HEAT: return "heat";
  case PERI_SOLVER_IMPLICIT: return "implicit";
  }
  return "unknown";
}

/* The whole file, or NULL (with errno) if it cannot be read. */
static char *read_text(const char *path) {
  FILE *in = fopen(path, "rb");
  if (!in) return NULL;
  size_t size = 0, cap = 4096;
  char *text = peri_malloc(cap);
  size_t got;
  while ((got = fread(text + size, 1, cap - size - 1, in)) > 0) {
    size += got;
    if (cap - size - 1 == 0) text = peri_realloc(text, cap *= 2);
  }
  const bool failed = ferror(in) != 0;
  fclose(in);
  if (failed) {
    free(text);
    return NULL;
  }
  text[size] = '\0';
  return text;
}

#ifdef PERI_HAVE_HDF5
#include <hdf5.h>

bool peri_checkpoint_supported(void) { return true; }

/* ---------------------------------------------------------------- writing */

typedef struct writer {
  hid_t file, dcpl, gcpl;
  bool failed;
} writer;

static hid_t group_create(writer *w, hid_t loc, const char *name) {
  hid_t g = H5Gcreate2(loc, name, H5P_DEFAULT, w->gcpl, H5P_DEFAULT);
  if (g < 0) w->failed = true;
  return g;
}

static void group_close(hid_t g) {
  if (g >= 0) H5Gclose(g);
}

static void attr_put(writer *w, hid_t loc, const char *name, hid_t file_type, hid_t mem_type, const void *value) {
  if (w->failed || loc < 0) return;
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(loc, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT);
  if (a < 0 || H5Awrite(a, mem_type, value) < 0) w->failed = true;
  if (a >= 0) H5Aclose(a);
  H5Sclose(space);
}

static void attr_double(writer *w, hid_t loc, const char *name, double v) {
  attr_put(w, loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &v);
}

static void attr_long(writer *w, hid_t loc, const char *name, long v) {
  long long value = v;
  attr_put(w, loc, name, H5T_STD_I64LE, H5T_NATIVE_LLONG, &value);
}

static void attr_u64(writer *w, hid_t loc, const char *name, uint64_t v) {
  unsigned long long value = v;
  attr_put(w, loc, name, H5T_STD_U64LE, H5T_NATIVE_ULLONG, &value);
}

static hid_t string_type(size_t length) {
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, length > 0 ? length : 1);
  H5Tset_strpad(t, H5T_STR_NULLPAD);
  return t;
}

static void attr_string(writer *w, hid_t loc, const char *name, const char *value) {
  const size_t len = strlen(value);
  hid_t t = string_type(len);
  attr_put(w, loc, name, t, t, len > 0 ? value : "");
  H5Tclose(t);
}

/* A dataset of `rows` x `cols` values (cols 0: one dimension). NULL data: nothing. */
static void dataset_put(writer *w, hid_t loc, const char *name, hid_t file_type, hid_t mem_type, hsize_t rows,
                        hsize_t cols, const void *data) {
  if (w->failed || loc < 0 || !data) return;
  hsize_t dims[2] = {rows, cols};
  hid_t space = H5Screate_simple(cols ? 2 : 1, dims, NULL);
  /* chunks with a Fletcher-32 checksum: a damaged array fails to read instead of restarting
   * from garbage (chunks of at most 2^20 rows stay under HDF5's 4 GB chunk limit) */
  hid_t dcpl = H5Pcopy(w->dcpl);
  if (rows > 0) {
    hsize_t chunk[2] = {rows < ((hsize_t)1 << 20) ? rows : ((hsize_t)1 << 20), cols};
    if (H5Pset_chunk(dcpl, cols ? 2 : 1, chunk) < 0 || H5Pset_fletcher32(dcpl) < 0) w->failed = true;
  }
  hid_t d = H5Dcreate2(loc, name, file_type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  if (d < 0 || (rows > 0 && H5Dwrite(d, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)) w->failed = true;
  if (d >= 0) H5Dclose(d);
  H5Pclose(dcpl);
  H5Sclose(space);
}

static void doubles_put(writer *w, hid_t loc, const char *name, size_t n, int ncomp, const double *data) {
  dataset_put(w, loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, n, ncomp > 1 ? (hsize_t)ncomp : 0, data);
}

static void text_put(writer *w, hid_t loc, const char *name, const char *text) {
  if (w->failed) return;
  const size_t len = strlen(text);
  hid_t t = string_type(len);
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t d = H5Dcreate2(loc, name, t, space, H5P_DEFAULT, w->dcpl, H5P_DEFAULT);
  if (d < 0 || H5Dwrite(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, len > 0 ? text : "") < 0) w->failed = true;
  if (d >= 0) H5Dclose(d);
  H5Sclose(space);
  H5Tclose(t);
}

/* The arrays a checkpoint holds, whole and in the global order: the simulation's own arrays
 * in one process; on MPI ranks rank 0's copies gathered from every rank's owned nodes and
 * families (NULL on the other ranks, which write nothing). A NULL array is one the run does
 * not have; whether it has one is the same on every rank. */
typedef struct state_view {
  int64_t n, n_bonds;
  uint64_t bond_hash;
  const double *x, *u, *v, *f, *damage, *theta, *wvol, *pstate, *smin, *s0, *thermal_strain, *step_load, *T;
  const uint8_t *broken, *cut;
  const double *plastic; /* plastic_layers per bond, NULL without plasticity */
  const double *plastic_tensor; /* the tensor rule's 6 layers per node, NULL without it */
  long growing_next; /* growing-crack bonds cut, over all ranks */
  void *gathered[16]; /* rank 0's gathered arrays, freed by view_free */
  int n_gathered;
} state_view;

/* A per-node array of every rank's owned nodes on rank 0 (collective). */
static const double *gather_nodes(const peri_sim *s, state_view *v, const double *local, int ncomp) {
  if (!local) return NULL;
  double *all = NULL;
  if (s->par.dd->rank == 0) all = peri_malloc(sizeof(double) * (size_t)ncomp * (size_t)(v->n > 0 ? v->n : 1));
  peri_gather_owned(s, local, ncomp, all);
  if (all) v->gathered[v->n_gathered++] = all;
  return all;
}

/* A per-bond byte array of every rank's families on rank 0 (collective). */
static const uint8_t *gather_bonds(const peri_sim *s, state_view *v, const uint8_t *local) {
  if (!local) return NULL;
  uint8_t *all = NULL;
  if (s->par.dd->rank == 0) all = peri_malloc((size_t)(v->n_bonds > 0 ? v->n_bonds : 1));
  peri_gather_owned_bonds(s, local, all);
  if (all) v->gathered[v->n_gathered++] = all;
  return all;
}

/* The rank's plastic stretches in bond rows: the state itself, or where the deviatoric rule
 * keeps it in slots (peri_plastic_row) a copy, returned in *copy as well for the caller to free. */
static const double *plastic_rows(const peri_sim *s, double **copy) {
  *copy = NULL;
  if (!s->state.plastic_stretch || !s->state.plastic_slots.state_in_slots) return s->state.plastic_stretch;
  const int64_t n = s->disc.bonds.n_bonds;
  const int L = s->state.plastic_layers;
  double *rows = peri_malloc(sizeof(double) * (size_t)(n * L > 0 ? n * L : 1));
  for (int64_t k = 0; k < n; ++k) {
    double row[PERI_MAX_SUBLAYERS];
    memcpy(rows + k * L, peri_plastic_row(s, s->state.plastic_stretch, k, row), sizeof(double) * (size_t)L);
  }
  *copy = rows;
  return rows;
}

/* The plastic stretches of every rank's families on rank 0 (collective). */
static const double *gather_plastic(const peri_sim *s, state_view *v) {
  double *copy;
  const double *local = plastic_rows(s, &copy);
  if (!local) return NULL;
  const peri_decomposition *d = s->par.dd;
  const int64_t layers = s->state.plastic_layers;
  double *all = NULL;
  if (d->rank == 0) all = peri_malloc(sizeof(double) * (size_t)(v->n_bonds > 0 ? v->n_bonds * layers : 1));
  int64_t *counts = peri_malloc(sizeof(int64_t) * (size_t)d->size);
  for (int r = 0; r < d->size; ++r) counts[r] = (d->bond_first[r + 1] - d->bond_first[r]) * layers;
  peri_comm_gather_doubles(local, s->disc.bonds.n_bonds * layers, counts, all);
  free(counts);
  free(copy);
  if (all) v->gathered[v->n_gathered++] = all;
  return all;
}

/* The view of the state of s; on MPI ranks every rank must call it (it gathers). */
static void view_of(const peri_sim *s, state_view *v) {
  const peri_particles *p = &s->disc.p;
  const peri_thermal *th = s->thermal;
  const uint8_t *cut = th && th->own_cut ? th->cut : NULL;
  memset(v, 0, sizeof *v);
  if (!s->par.dd) {
    v->n = p->n_owned;
    v->n_bonds = s->disc.bonds.n_bonds;
    v->bond_hash = peri_bonds_hash(&s->disc.bonds, p->n_owned);
    v->x = p->x, v->u = p->u, v->v = p->v, v->f = p->f, v->damage = p->damage;
    v->theta = p->theta, v->wvol = p->wvol, v->pstate = p->pstate, v->smin = p->smin;
    v->s0 = s->mat.s0_node, v->thermal_strain = s->state.thermal_strain, v->step_load = s->state.step_load;
    v->T = th ? th->T : NULL;
    v->broken = s->disc.bonds.broken, v->cut = cut;
    double *copy;
    v->plastic = plastic_rows(s, &copy);
    if (copy) v->gathered[v->n_gathered++] = copy;
    if (s->state.plastic_tensor) v->plastic_tensor = v->gathered[v->n_gathered++] = peri_tensor_state_rows(s);
    v->growing_next = th ? (long)th->growing_next : 0;
    return;
  }
  v->n = s->par.dd->n_global;
  v->n_bonds = s->par.dd->n_bonds_global;
  v->bond_hash = s->par.dd->bond_hash; /* of the global families, computed before they were split */
  v->x = gather_nodes(s, v, p->x, 3);
  v->u = gather_nodes(s, v, p->u, 3);
  v->v = gather_nodes(s, v, p->v, 3);
  v->f = gather_nodes(s, v, p->f, 3);
  v->damage = gather_nodes(s, v, p->damage, 1);
  v->theta = gather_nodes(s, v, p->theta, 1);
  v->wvol = gather_nodes(s, v, p->wvol, 1);
  v->pstate = gather_nodes(s, v, p->pstate, 1);
  v->smin = gather_nodes(s, v, p->smin, 1);
  v->s0 = gather_nodes(s, v, s->mat.s0_node, 1);
  v->thermal_strain = gather_nodes(s, v, s->state.thermal_strain, 1);
  v->step_load = gather_nodes(s, v, s->state.step_load, 3);
  v->T = th ? gather_nodes(s, v, th->T, 1) : NULL;
  v->broken = gather_bonds(s, v, s->disc.bonds.broken);
  v->plastic = gather_plastic(s, v);
  if (s->state.plastic_tensor) {
    double *rows = peri_tensor_state_rows(s);
    v->plastic_tensor = gather_nodes(s, v, rows, PERI_TENSOR_COMPONENTS * s->state.plastic_tensor->layers);
    free(rows);
  }
  v->cut = gather_bonds(s, v, cut);
  /* each rank cuts the growing bonds of its families in the global (time) order, so the
   * global position is the sum of the ranks' positions */
  v->growing_next = th ? peri_comm_sum_long((long)th->growing_next) : 0;
}

static void view_free(state_view *v) {
  for (int k = 0; k < v->n_gathered; ++k) free(v->gathered[k]);
  v->n_gathered = 0;
}

static void write_contents(writer *w, const peri_sim *s, const state_view *v, const peri_checkpoint_progress *done) {
  const size_t n = (size_t)v->n;
  const hid_t root = w->file;
  attr_string(w, root, "format", "peri checkpoint");
  attr_long(w, root, "format_version", PERI_CHECKPOINT_FORMAT_VERSION);
  attr_string(w, root, "peri_version", PERI_VERSION);
  attr_string(w, root, "deck_path", s->deck_path);
  attr_string(w, root, "model", s->mat.model ? s->mat.model->name : "");
  attr_long(w, root, "solver", (long)s->solver.kind);
  attr_string(w, root, "solver_name", solver_kind_name(s->solver.kind));
  attr_long(w, root, "dimension", s->disc.geom.dim);
  char *deck = read_text(s->deck_path); /* the deck as it is now: a record of the run */
  text_put(w, root, "deck_text", deck ? deck : "");
  free(deck);

  hid_t g = group_create(w, root, "state");
  attr_double(w, g, "time", s->state.time);
  attr_long(w, g, "step", s->state.step);
  attr_long(w, g, "steps", s->solver.steps);
  attr_double(w, g, "dt", s->solver.dt);
  attr_double(w, g, "external_work", s->state.external_work);
  attr_long(w, g, "frames", done ? done->frames : 0);
  attr_long(w, g, "history_rows", done ? done->history_rows : 0);
  group_close(g);

  g = group_create(w, root, "discretization");
  attr_long(w, g, "n_nodes", (long)n);
  attr_long(w, g, "n_bonds", (long)v->n_bonds);
  attr_u64(w, g, "bond_hash", v->bond_hash);
  doubles_put(w, g, "x", n, 3, v->x);
  group_close(g);

  g = group_create(w, root, "nodes");
  doubles_put(w, g, "u", n, 3, v->u);
  doubles_put(w, g, "v", n, 3, v->v);
  doubles_put(w, g, "f", n, 3, v->f);
  doubles_put(w, g, "damage", n, 1, v->damage);
  doubles_put(w, g, "theta", n, 1, v->theta);
  doubles_put(w, g, "wvol", n, 1, v->wvol);
  doubles_put(w, g, "pstate", n, 1, v->pstate);
  doubles_put(w, g, "smin", n, 1, v->smin);
  doubles_put(w, g, "s0", n, 1, v->s0);
  doubles_put(w, g, "thermal_strain", n, 1, v->thermal_strain);
  doubles_put(w, g, "step_load", n, 3, v->step_load);
  if (v->plastic_tensor)
    doubles_put(w, g, "plastic_tensor", n, PERI_TENSOR_COMPONENTS * s->state.plastic_tensor->layers, v->plastic_tensor);
  group_close(g);

  g = group_create(w, root, "bonds");
  dataset_put(w, g, "broken", H5T_STD_U8LE, H5T_NATIVE_UINT8, (hsize_t)v->n_bonds, 0, v->broken);
  if (v->plastic) doubles_put(w, g, "plastic_stretch", (size_t)v->n_bonds, s->state.plastic_layers, v->plastic);
  group_close(g);

  g = group_create(w, root, "indenter");
  doubles_put(w, g, "force", 3, 1, s->cond.indenter.force);
  group_close(g);

  if (s->tools) { /* the same on every rank: the tools' forces are summed over all of them */
    g = group_create(w, root, "tools");
    for (int k = 0; k < s->tools->count; ++k) {
      char name[32];
      snprintf(name, sizeof name, "%d", k);
      hid_t t = group_create(w, g, name);
      attr_string(w, t, "name", s->tools->tool[k].name);
      double state[TOOL_STATE];
      tool_state_pack(&s->tools->tool[k], state);
      doubles_put(w, t, "state", TOOL_STATE, 1, state);
      group_close(t);
    }
    group_close(g);
  }

  g = group_create(w, root, "quasi_static");
  const peri_quasi_static *q = &s->solver.qs;
  attr_double(w, g, "reference", q->reference);
  attr_double(w, g, "last_reference", q->last_reference);
  attr_double(w, g, "residual", q->residual);
  attr_long(w, g, "iterations", q->iterations);
  attr_long(w, g, "solves", q->solves);
  attr_long(w, g, "force_evaluations", q->force_evaluations);
  attr_long(w, g, "cutbacks", q->cutbacks);
  attr_double(w, g, "dynamic_time", q->dynamic_time);
  attr_long(w, g, "dynamic_phases", q->dynamic_phases);
  attr_long(w, g, "dynamic_steps", q->dynamic_steps);
  group_close(g);

  const peri_thermal *th = s->thermal;
  if (th) {
    g = group_create(w, root, "thermal");
    attr_double(w, g, "time", th->time);
    attr_long(w, g, "growing_next", v->growing_next);
    attr_long(w, g, "every", th->every);
    attr_long(w, g, "substeps", th->substeps);
    doubles_put(w, g, "T", n, 1, v->T);
    if (th->own_cut) dataset_put(w, g, "cut", H5T_STD_U8LE, H5T_NATIVE_UINT8, (hsize_t)v->n_bonds, 0, v->cut);
    group_close(g);
  }
}

/* The view as an HDF5 file `name`, on disk or only in memory; *size (if not NULL) gets the
 * file's size before it is closed. False if any HDF5 call failed. */
static bool build_file(const peri_sim *s, const state_view *v, const char *name, const peri_checkpoint_progress *done,
                       bool in_memory, hsize_t *size) {
  writer w = {.failed = false};
  /* no modification times in the file: the same state gives the same bytes */
  w.dcpl = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_obj_track_times(w.dcpl, 0);
  w.gcpl = H5Pcreate(H5P_GROUP_CREATE);
  H5Pset_obj_track_times(w.gcpl, 0);
  hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
  H5Pset_obj_track_times(fcpl, 0);
  /* the HDF5 1.8 file format: object headers and the superblock carry checksums, so
   * damaged attributes (time, step, ...) are detected too; readable by HDF5 >= 1.8 */
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_libver_bounds(fapl, H5F_LIBVER_V18, H5F_LIBVER_LATEST);
  /* in memory, grown 64 KiB at a time: its size overestimates the file on disk by less */
  if (in_memory) H5Pset_fapl_core(fapl, (size_t)1 << 16, 0);
  w.file = H5Fcreate(name, H5F_ACC_TRUNC, fcpl, fapl);
  H5Pclose(fapl);
  if (w.file < 0) {
    w.failed = true;
  } else {
    write_contents(&w, s, v, done);
    if (size && (w.failed || H5Fget_filesize(w.file, size) < 0)) w.failed = true;
    if (H5Fclose(w.file) < 0) w.failed = true;
  }
  H5Pclose(fcpl);
  H5Pclose(w.dcpl);
  H5Pclose(w.gcpl);
  return !w.failed;
}

/* Allocates `size` bytes of disk for `path` (it holds zeros until HDF5 truncates and writes
 * it); false with errno set when the disk has no room. */
static bool reserve_space(const char *path, hsize_t size) {
  FILE *f = fopen(path, "wb");
  if (!f) return false;
  int err = size > 0 ? posix_fallocate(fileno(f), 0, (off_t)size) : 0;
  if (err == EINVAL || err == EOPNOTSUPP) err = 0; /* a file system that cannot reserve: write as before */
  fclose(f);
  errno = err;
  return err == 0;
}

/* Writes the view to path through path.tmp and a rename (one process: rank 0). An HDF5
 * file whose writes fail (a full disk) cannot be closed, and the library then crashes at
 * exit; so the file is first built in memory to learn its size, that much disk is
 * reserved, and only then does HDF5 write it. */
static int write_file(const peri_sim *s, const state_view *v, const char *path, const peri_checkpoint_progress *done) {
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* our messages, not the library's error stack */
  const size_t len = strlen(path);
  char *tmp = peri_malloc(len + sizeof ".tmp");
  memcpy(tmp, path, len);
  memcpy(tmp + len, ".tmp", sizeof ".tmp");
  int rc = PERI_OK;
  hsize_t size = 0;
  if (!build_file(s, v, tmp, done, true, &size)) {
    peri_error("cannot write checkpoint '%s': HDF5 could not build it in memory (out of memory?)", path);
    rc = PERI_ERR_RUN;
  } else if (!reserve_space(tmp, size)) {
    peri_error("cannot write checkpoint '%s': cannot write '%s' (%llu bytes): %s", path, tmp,
               (unsigned long long)size, strerror(errno));
    remove(tmp);
    rc = PERI_ERR_RUN;
  } else if (!build_file(s, v, tmp, done, false, NULL)) {
    peri_error("cannot write checkpoint '%s': HDF5 write of '%s' failed (disk full?)", path, tmp);
    remove(tmp);
    rc = PERI_ERR_RUN;
  } else if (rename(tmp, path) != 0) {
    peri_error("cannot write checkpoint '%s': %s", path, strerror(errno));
    remove(tmp);
    rc = PERI_ERR_RUN;
  }
  free(tmp);
  return rc;
}

int peri_checkpoint_write(const peri_sim *s, const char *path, const peri_checkpoint_progress *done) {
  state_view v;
  view_of(s, &v); /* MPI ranks: every rank takes part in the gathers */
  const int rc = !s->par.dd || s->par.dd->rank == 0 ? write_file(s, &v, path, done) : PERI_OK;
  view_free(&v);
  return s->par.dd ? peri_comm_max_int(rc) : rc; /* every rank returns rank 0's status */
}

/* ---------------------------------------------------------------- reading */

typedef struct reader {
  hid_t file;
  const char *path;
  bool failed; /* a message was printed */
} reader;

static int bad(reader *r, const char *fmt, const char *what) {
  if (!r->failed) {
    char msg[1024];
    snprintf(msg, sizeof msg, fmt, what);
    peri_error("checkpoint '%s': %s", r->path, msg);
  }
  r->failed = true;
  return PERI_ERR_INPUT;
}

static hid_t group_open(reader *r, const char *name, bool required) {
  if (r->failed) return -1;
  if (H5Lexists(r->file, name, H5P_DEFAULT) <= 0) {
    if (required) bad(r, "no group '%s' (not a peri checkpoint, or damaged)", name);
    return -1;
  }
  hid_t g = H5Gopen2(r->file, name, H5P_DEFAULT);
  if (g < 0) bad(r, "cannot open group '%s' (damaged file)", name);
  return g;
}

/* Whether an attribute or dataset holds exactly one element: reading more into one value
 * would write past it. */
static bool one_value(hid_t obj, bool dataset) {
  hid_t space = dataset ? H5Dget_space(obj) : H5Aget_space(obj);
  if (space < 0) return false;
  const bool one = H5Sget_simple_extent_npoints(space) == 1;
  H5Sclose(space);
  return one;
}

static void attr_get(reader *r, hid_t loc, const char *name, hid_t mem_type, void *out) {
  if (r->failed || loc < 0) return;
  if (H5Aexists(loc, name) <= 0) {
    bad(r, "attribute '%s' is missing (not a peri checkpoint, or damaged)", name);
    return;
  }
  hid_t a = H5Aopen(loc, name, H5P_DEFAULT);
  if (a < 0 || !one_value(a, false)) bad(r, "attribute '%s' is not a single value (damaged file)", name);
  else if (H5Aread(a, mem_type, out) < 0) bad(r, "cannot read attribute '%s' (damaged file)", name);
  if (a >= 0) H5Aclose(a);
}

static double get_double(reader *r, hid_t loc, const char *name) {
  double v = 0.0;
  attr_get(r, loc, name, H5T_NATIVE_DOUBLE, &v);
  return v;
}

static long get_long(reader *r, hid_t loc, const char *name) {
  long long v = 0;
  attr_get(r, loc, name, H5T_NATIVE_LLONG, &v);
  return (long)v;
}

/* A string attribute or a scalar string dataset (dataset = true), newly allocated. */
static char *get_string(reader *r, hid_t loc, const char *name, bool dataset) {
  if (r->failed || loc < 0) return NULL;
  if ((dataset ? H5Lexists(loc, name, H5P_DEFAULT) : H5Aexists(loc, name)) <= 0) {
    bad(r, "'%s' is missing (not a peri checkpoint, or damaged)", name);
    return NULL;
  }
  hid_t obj = dataset ? H5Dopen2(loc, name, H5P_DEFAULT) : H5Aopen(loc, name, H5P_DEFAULT);
  hid_t t = obj < 0 ? -1 : dataset ? H5Dget_type(obj) : H5Aget_type(obj);
  char *out = NULL;
  if (t >= 0 && H5Tget_class(t) == H5T_STRING && !H5Tis_variable_str(t) && one_value(obj, dataset)) {
    const size_t size = H5Tget_size(t);
    out = peri_calloc(size + 1, 1);
    if ((dataset ? H5Dread(obj, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) : H5Aread(obj, t, out)) < 0) {
      free(out);
      out = NULL;
    }
  }
  if (!out) bad(r, "cannot read '%s' (damaged file)", name);
  if (t >= 0) H5Tclose(t);
  if (obj >= 0 && dataset) H5Dclose(obj);
  else if (obj >= 0) H5Aclose(obj);
  return out;
}

/* Whether a dataset's storage is the one the writer makes (dataset_put): chunks of
 * min(rows, 2^20) rows with a Fletcher-32 checksum and nothing else, a file type of the
 * memory type's class and size, and every chunk stored whole with its filter applied.
 * The chunk index (a version 1 B-tree) has no checksum of its own; HDF5 1.10 copies a
 * chunk's full size out of a stored chunk that a damaged index says is shorter, or whose
 * filter the index marks as skipped, reading past its buffer, so this is checked first. */
static bool stored_as_written(hid_t d, hid_t mem_type, size_t elem, hsize_t rows, int ncomp) {
  const int want_rank = ncomp > 1 ? 2 : 1;
  hid_t dcpl = H5Dget_create_plist(d);
  hid_t ftype = H5Dget_type(d);
  bool ok = dcpl >= 0 && ftype >= 0 && H5Tget_class(ftype) == H5Tget_class(mem_type) && H5Tget_size(ftype) == elem;
  hsize_t chunk[2] = {0, 0};
  if (ok) ok = H5Pget_layout(dcpl) == H5D_CHUNKED && H5Pget_chunk(dcpl, 2, chunk) == want_rank;
  const hsize_t chunk_rows = rows < ((hsize_t)1 << 20) ? rows : ((hsize_t)1 << 20);
  if (ok) ok = chunk[0] == chunk_rows && (want_rank == 1 || chunk[1] == (hsize_t)ncomp);
  if (ok && H5Pget_nfilters(dcpl) == 1) {
    unsigned flags = 0, config = 0;
    size_t n_values = 0;
    ok = H5Pget_filter2(dcpl, 0, &flags, &n_values, NULL, 0, NULL, &config) == H5Z_FILTER_FLETCHER32;
  } else {
    ok = false;
  }
  /* the stored chunk: the values and the four bytes of the checksum */
  const hsize_t chunk_bytes = chunk_rows * (hsize_t)(ncomp > 1 ? ncomp : 1) * elem + 4;
  for (hsize_t first = 0; ok && first < rows; first += chunk_rows) {
    hsize_t offset[2] = {first, 0};
    unsigned filter_mask = 1;
    haddr_t address = HADDR_UNDEF;
    hsize_t stored = 0;
    ok = H5Dget_chunk_info_by_coord(d, offset, &filter_mask, &address, &stored) >= 0 && filter_mask == 0 &&
         address != HADDR_UNDEF && stored == chunk_bytes;
  }
  if (ftype >= 0) H5Tclose(ftype);
  if (dcpl >= 0) H5Pclose(dcpl);
  return ok;
}

/* Reads dataset `name` of rows x ncomp values into a new array; NULL when absent and not
 * required. The extent and the storage must be the writer's. */
static void *get_array(reader *r, hid_t loc, const char *name, hid_t mem_type, size_t elem, hsize_t rows, int ncomp,
                       bool required) {
  if (r->failed || loc < 0) return NULL;
  if (H5Lexists(loc, name, H5P_DEFAULT) <= 0) {
    if (required) bad(r, "dataset '%s' is missing (damaged file)", name);
    return NULL;
  }
  hid_t d = H5Dopen2(loc, name, H5P_DEFAULT);
  hid_t space = d < 0 ? -1 : H5Dget_space(d);
  hsize_t dims[2] = {0, 0};
  /* the rank first: the extent of a dataset of more dimensions would not fit in dims */
  const int ndims = space < 0 ? -1 : H5Sget_simple_extent_ndims(space);
  const int rank = ndims < 1 || ndims > 2 ? -1 : H5Sget_simple_extent_dims(space, dims, NULL);
  const int want_rank = ncomp > 1 ? 2 : 1;
  void *out = NULL;
  if (rank != want_rank || dims[0] != rows || (ncomp > 1 && dims[1] != (hsize_t)ncomp)) {
    char what[256];
    snprintf(what, sizeof what, "dataset '%s' has %llu values, expected %llu", name,
             (unsigned long long)(rank == 2 ? dims[0] * dims[1] : rank == 1 ? dims[0] : 0),
             (unsigned long long)(rows * (hsize_t)(ncomp > 1 ? ncomp : 1)));
    bad(r, "%s (damaged file)", what);
  } else {
    const size_t count = (size_t)rows * (size_t)(ncomp > 1 ? ncomp : 1);
    out = peri_malloc(count > 0 ? count * elem : 1);
    if (count > 0 && !stored_as_written(d, mem_type, elem, rows, ncomp)) {
      free(out);
      out = NULL;
      bad(r, "dataset '%s' is not stored as peri writes it (damaged file)", name);
    } else if (count > 0 && H5Dread(d, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) < 0) {
      free(out);
      out = NULL;
      bad(r, "cannot read dataset '%s' (damaged file)", name);
    }
  }
  if (space >= 0) H5Sclose(space);
  if (d >= 0) H5Dclose(d);
  return out;
}

static double *get_doubles(reader *r, hid_t loc, const char *name, size_t n, int ncomp, bool required) {
  return get_array(r, loc, name, H5T_NATIVE_DOUBLE, sizeof(double), n, ncomp, required);
}

/* A model work array: present in the checkpoint exactly when the deck's run has it. */
static double *get_work_array(reader *r, hid_t loc, const char *name, size_t n, bool in_sim) {
  double *a = get_doubles(r, loc, name, n, 1, false);
  if (!r->failed && in_sim != (a != NULL)) {
    bad(r, in_sim ? "has no '%s' array, but the deck's model needs one (was it written with another model or "
                    "critical-stretch form?)"
                  : "has a '%s' array the deck's model does not use (was it written with another model?)",
        name);
  }
  return a;
}

/* A count or index of the checkpoint must lie in 0..max before anything uses it: a damaged
 * or crafted file must not size an allocation or index an array. */
static void check_range(reader *r, const char *attribute, long value, long max, const char *why) {
  if (r->failed || (value >= 0 && value <= max)) return;
  peri_error("checkpoint '%s': attribute %s is %ld, outside 0..%ld (%s): the file is damaged or not a peri checkpoint",
             r->path, attribute, value, max, why);
  r->failed = true;
}

static void check_finite(reader *r, const char *attribute, double value) {
  if (r->failed || isfinite(value)) return;
  peri_error("checkpoint '%s': attribute %s is %g, not a finite number (damaged file)", r->path, attribute, value);
  r->failed = true;
}

/* Reads and checks everything; fills *out. */
static void read_checkpoint(reader *r, const peri_sim *s, struct peri_restart *out) {
  const peri_particles *p = &s->disc.p;
  const size_t n = (size_t)p->n_owned;
  const hid_t root = r->file;
  char *format = get_string(r, root, "format", false);
  if (format && strcmp(format, "peri checkpoint") != 0) bad(r, "format '%s' is not a peri checkpoint", format);
  free(format);
  const long version = get_long(r, root, "format_version");
  if (!r->failed && (version < 1 || version > PERI_CHECKPOINT_FORMAT_VERSION)) {
    char what[128];
    snprintf(what, sizeof what, "%ld", version);
    bad(r, "format version %s is not one this peri reads (1); was it written by a newer peri?", what);
  }
  const long solver = get_long(r, root, "solver");
  if (!r->failed && solver != (long)s->solver.kind) {
    char what[256];
    snprintf(what, sizeof what, "it is from a run with solver type %s, the deck sets solver type %s",
             solver_kind_name((peri_solver_kind)solver), solver_kind_name(s->solver.kind));
    bad(r, "%s", what);
  }
  char *model = get_string(r, root, "model", false);
  if (model && s->mat.model && strcmp(model, s->mat.model->name) != 0) {
    char what[256];
    snprintf(what, sizeof what, "it is from a run with model %s, the deck uses %s", model, s->mat.model->name);
    bad(r, "%s", what);
  }
  free(model);
  const long dim = get_long(r, root, "dimension");
  if (!r->failed && dim != s->disc.geom.dim) {
    char what[128];
    snprintf(what, sizeof what, "it is %ldD, the deck is %dD", dim, s->disc.geom.dim);
    bad(r, "%s", what);
  }

  hid_t g = group_open(r, "discretization", true);
  const long nodes = get_long(r, g, "n_nodes");
  const long bonds = get_long(r, g, "n_bonds");
  unsigned long long hash = 0;
  attr_get(r, g, "bond_hash", H5T_NATIVE_ULLONG, &hash);
  if (!r->failed && nodes != (long)n) {
    peri_error("checkpoint '%s' has %ld nodes, deck builds %zu: it is not from this deck's discretization", r->path,
               nodes, n);
    r->failed = true;
  }
  if (!r->failed && bonds != (long)s->disc.bonds.n_bonds) {
    peri_error("checkpoint '%s' has %ld bonds, deck builds %lld: the horizon or the partial-volume rule differ",
               r->path, bonds, (long long)s->disc.bonds.n_bonds);
    r->failed = true;
  }
  double *x = get_doubles(r, g, "x", n, 3, true);
  for (size_t i = 0; x && !r->failed && i < n; ++i)
    for (int d = 0; d < 3; ++d)
      if (x[3 * i + d] != p->x[3 * i + d]) {
        char what[512];
        snprintf(what, sizeof what, "node %zu is at (%.9g, %.9g, %.9g) in the checkpoint and at (%.9g, %.9g, %.9g) in "
                 "the deck's discretization", i, x[3 * i], x[3 * i + 1], x[3 * i + 2], p->x[3 * i], p->x[3 * i + 1],
                 p->x[3 * i + 2]);
        bad(r, "%s: it is not from this deck", what);
        break;
      }
  free(x);
  if (!r->failed && hash != peri_bonds_hash(&s->disc.bonds, (int32_t)n))
    bad(r, "%s", "the bond families differ from the deck's (another horizon or partial-volume rule)");
  group_close(g);

  g = group_open(r, "state", true);
  out->time = get_double(r, g, "time");
  out->step = get_long(r, g, "step");
  const double dt = get_double(r, g, "dt");
  out->external_work = get_double(r, g, "external_work");
  out->done.frames = get_long(r, g, "frames");
  out->done.history_rows = get_long(r, g, "history_rows");
  group_close(g);
  check_range(r, "/state/step", out->step, LONG_MAX, "a step number");
  if (!r->failed && out->step > s->solver.steps) {
    char what[256];
    snprintf(what, sizeof what, "it is at step %ld, beyond the deck's last step %ld (raise solver.end_time or "
             "solver.steps to continue)", out->step, s->solver.steps);
    bad(r, "%s", what);
  }
  check_finite(r, "/state/time", out->time);
  check_finite(r, "/state/external_work", out->external_work);
  /* the first frame and at most one per step after it */
  check_range(r, "/state/frames", out->done.frames, out->step + 1, "frames written up to the checkpoint's step");
  const bool timed = s->solver.kind == PERI_SOLVER_EXPLICIT || s->solver.kind == PERI_SOLVER_DYNAMIC_RELAXATION ||
                     s->solver.kind == PERI_SOLVER_HEAT; /* the others have no time step */
  if (!r->failed && timed && dt != s->solver.dt)
    peri_warning("checkpoint '%s': written with time step %.17g s, the deck gives %.17g s; continuing with the deck's",
                 r->path, dt, s->solver.dt);

  g = group_open(r, "nodes", true);
  out->n = (int32_t)n;
  out->u = get_doubles(r, g, "u", n, 3, true);
  out->v = get_doubles(r, g, "v", n, 3, true);
  out->f = get_doubles(r, g, "f", n, 3, true);
  out->damage = get_doubles(r, g, "damage", n, 1, true);
  out->theta = get_work_array(r, g, "theta", n, p->theta != NULL);
  out->wvol = get_work_array(r, g, "wvol", n, p->wvol != NULL);
  out->pstate = get_work_array(r, g, "pstate", n, p->pstate != NULL);
  out->smin = get_work_array(r, g, "smin", n, p->smin != NULL);
  out->s0 = get_work_array(r, g, "s0", n, s->mat.s0_node != NULL);
  out->thermal_strain = get_work_array(r, g, "thermal_strain", n, s->state.thermal_strain != NULL);
  out->step_load = get_doubles(r, g, "step_load", n, 3, false);
  if (!r->failed && s->state.plastic_tensor) {
    out->plastic_tensor =
        get_doubles(r, g, "plastic_tensor", n, PERI_TENSOR_COMPONENTS * s->state.plastic_tensor->layers, false);
    if (!r->failed && !out->plastic_tensor)
      bad(r, "%s", "has no /nodes/plastic_tensor of the deck's tensor yield rule (written with another rule?)");
  }
  group_close(g);

  g = group_open(r, "bonds", true);
  out->n_bonds = s->disc.bonds.n_bonds;
  out->broken = get_array(r, g, "broken", H5T_NATIVE_UINT8, 1, (hsize_t)s->disc.bonds.n_bonds, 1, true);
  for (int64_t k = 0; out->broken && !r->failed && k < s->disc.bonds.n_bonds; ++k)
    if (out->broken[k] > 1) bad(r, "%s", "dataset /bonds/broken has flags other than 0 and 1 (damaged file)");
  if (!r->failed) {
    out->plastic = s->state.plastic_stretch ? get_doubles(r, g, "plastic_stretch", (size_t)s->disc.bonds.n_bonds,
                                                          s->state.plastic_layers, false)
                                            : NULL;
    if (!r->failed && s->state.plastic_stretch && !out->plastic)
      bad(r, "%s", "has no /bonds/plastic_stretch of the deck's plastic materials (written without plasticity?)");
  }
  group_close(g);

  g = group_open(r, "indenter", true);
  double *force = get_doubles(r, g, "force", 3, 1, true);
  if (force) memcpy(out->indenter_force, force, sizeof out->indenter_force);
  free(force);
  group_close(g);

  g = group_open(r, "tools", false);
  if (!r->failed && (g >= 0) != (s->tools != NULL))
    bad(r, "%s", g >= 0 ? "it has the state of rigid tools, but the deck has no tools"
                        : "it has no state of rigid tools, but the deck has tools");
  if (g >= 0 && s->tools) {
    out->tools = peri_calloc((size_t)s->tools->count * TOOL_STATE, sizeof(double));
    for (int k = 0; k < s->tools->count && !r->failed; ++k) {
      char name[32];
      snprintf(name, sizeof name, "%d", k);
      hid_t t = H5Lexists(g, name, H5P_DEFAULT) > 0 ? H5Gopen2(g, name, H5P_DEFAULT) : -1;
      if (t < 0) {
        char what[160];
        snprintf(what, sizeof what, "it holds %d rigid tools, the deck has %d", k, s->tools->count);
        bad(r, "%s", what);
        break;
      }
      char *tool_name = get_string(r, t, "name", false);
      if (tool_name && strcmp(tool_name, s->tools->tool[k].name) != 0) {
        char what[256];
        snprintf(what, sizeof what, "its tool %d is '%.100s', the deck's is '%.100s'", k + 1, tool_name,
                 s->tools->tool[k].name);
        bad(r, "%s", what);
      }
      free(tool_name);
      double *state = get_doubles(r, t, "state", TOOL_STATE, 1, true);
      char where[48];
      snprintf(where, sizeof where, "/tools/%d/state", k);
      for (int j = 0; state && j < TOOL_STATE; ++j) check_finite(r, where, state[j]);
      if (state) memcpy(out->tools + (size_t)k * TOOL_STATE, state, sizeof(double) * TOOL_STATE);
      free(state);
      H5Gclose(t);
    }
    char extra[32];
    snprintf(extra, sizeof extra, "%d", s->tools->count);
    if (!r->failed && H5Lexists(g, extra, H5P_DEFAULT) > 0) bad(r, "%s", "it holds more rigid tools than the deck has");
  }
  group_close(g);

  g = group_open(r, "quasi_static", true);
  out->qs.reference = get_double(r, g, "reference");
  out->qs.last_reference = get_double(r, g, "last_reference");
  out->qs.residual = get_double(r, g, "residual");
  out->qs.iterations = get_long(r, g, "iterations");
  out->qs.solves = get_long(r, g, "solves");
  out->qs.force_evaluations = get_long(r, g, "force_evaluations");
  out->qs.cutbacks = get_long(r, g, "cutbacks");
  out->qs.dynamic_time = get_double(r, g, "dynamic_time");
  out->qs.dynamic_phases = get_long(r, g, "dynamic_phases");
  out->qs.dynamic_steps = get_long(r, g, "dynamic_steps");
  group_close(g);
  check_range(r, "/quasi_static/iterations", out->qs.iterations, LONG_MAX, "a count");
  check_range(r, "/quasi_static/solves", out->qs.solves, LONG_MAX, "a count");
  check_range(r, "/quasi_static/force_evaluations", out->qs.force_evaluations, LONG_MAX, "a count");
  check_range(r, "/quasi_static/cutbacks", out->qs.cutbacks, LONG_MAX, "a count");
  check_range(r, "/quasi_static/dynamic_phases", out->qs.dynamic_phases, out->step, "at most one per load step");
  check_range(r, "/quasi_static/dynamic_steps", out->qs.dynamic_steps, LONG_MAX - out->step - 1, "a count");
  /* the first row, at most one per step, and those of dynamic phases (at most one per dynamic step) */
  if (!r->failed)
    check_range(r, "/state/history_rows", out->done.history_rows, out->step + 1 + out->qs.dynamic_steps,
                "history rows written up to the checkpoint's step");

  g = group_open(r, "thermal", false);
  if (!r->failed && (g >= 0) != (s->thermal != NULL))
    bad(r, "%s", g >= 0 ? "it has a temperature field, but the deck has no heat conduction"
                        : "it has no temperature field, but the deck has heat conduction");
  if (g >= 0 && s->thermal) {
    out->thermal = true;
    out->thermal_time = get_double(r, g, "time");
    out->growing_next = get_long(r, g, "growing_next");
    out->every = get_long(r, g, "every");
    out->substeps = get_long(r, g, "substeps");
    check_finite(r, "/thermal/time", out->thermal_time);
    /* 0 for both until the coupling has set them (src/solver/heat.c) */
    check_range(r, "/thermal/every", out->every, 1000000000L, "mechanical steps per heat step");
    check_range(r, "/thermal/substeps", out->substeps, LONG_MAX, "heat steps per mechanical step");
    out->T = get_doubles(r, g, "T", n, 1, true);
    out->cut = get_array(r, g, "cut", H5T_NATIVE_UINT8, 1, (hsize_t)s->disc.bonds.n_bonds, 1, s->thermal->own_cut);
    if (!r->failed && (out->growing_next < 0 || out->growing_next > s->thermal->n_growing_bonds))
      bad(r, "%s", "attribute /thermal/growing_next does not match the deck's growing cracks");
    for (int64_t k = 0; out->cut && !r->failed && k < s->disc.bonds.n_bonds; ++k)
      if (out->cut[k] > 1) bad(r, "%s", "dataset /thermal/cut has flags other than 0 and 1 (damaged file)");
    if (!r->failed) { /* which bonds those cuts were, for the ranks' shares (peri_restart_apply) */
      const size_t cuts = (size_t)out->growing_next;
      out->growing_cut = peri_malloc(sizeof(int64_t) * (cuts > 0 ? cuts : 1));
      if (cuts > 0) memcpy(out->growing_cut, s->thermal->growing_bond, sizeof(int64_t) * cuts);
    }
  }
  group_close(g);
}

static int read_file(peri_sim *s, const char *path, struct peri_restart *out) {
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  FILE *probe = fopen(path, "rb");
  if (!probe) {
    peri_error("cannot read checkpoint '%s': %s", path, strerror(errno));
    return PERI_ERR_INPUT;
  }
  fclose(probe);
  if (H5Fis_hdf5(path) <= 0) {
    peri_error("checkpoint '%s': not an HDF5 file (damaged, truncated, or not a checkpoint)", path);
    return PERI_ERR_INPUT;
  }
  reader r = {.path = path, .failed = false};
  r.file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (r.file < 0) {
    peri_error("checkpoint '%s': cannot open it as HDF5 (damaged or truncated)", path);
    return PERI_ERR_INPUT;
  }
  read_checkpoint(&r, s, out);
  if (!r.failed) {
    /* the deck it was written with, for a note when the deck has changed since */
    char *then = get_string(&r, r.file, "deck_text", true);
    char *now = read_text(s->deck_path);
    if (then && now && strcmp(then, now) != 0)
      peri_warning("checkpoint '%s' was written with a different version of '%s'; continuing with the deck as it "
                   "is now", path, s->deck_path);
    free(then);
    free(now);
  }
  H5Fclose(r.file);
  return r.failed ? PERI_ERR_INPUT : PERI_OK;
}

#else /* no HDF5 */

bool peri_checkpoint_supported(void) { return false; }

int peri_checkpoint_write(const peri_sim *s, const char *path, const peri_checkpoint_progress *done) {
  (void)s, (void)done;
  peri_error("cannot write checkpoint '%s': this peri was built without HDF5 (install libhdf5-dev and rebuild)",
             path);
  return PERI_ERR_RUN;
}

static int read_file(peri_sim *s, const char *path, struct peri_restart *out) {
  (void)s, (void)out, (void)solver_kind_name, (void)read_text;
  peri_error("cannot restart from '%s': this peri was built without HDF5, which checkpoints need (install "
             "libhdf5-dev, e.g. with scripts/install-deps, and rebuild)", path);
  return PERI_ERR_INPUT;
}

#endif

int peri_restart_load(peri_sim *s, const char *path) {
  struct peri_restart *r = peri_calloc(1, sizeof *r);
  r->path = peri_strdup(path);
  int rc = read_file(s, path, r);
  if (rc == PERI_OK)
    rc = peri_restart_read_output(s->out.directory, s->out.basename, r->done.history_rows,
                                  s->out.vtu ? r->done.frames : 0, /* no .pvd without VTU frames */
                                  &r->history, &r->history_rows, &r->history_columns, &r->history_names, &r->frame_times,
                                  &r->frame_files, &r->frames_listed);
  if (rc != PERI_OK) {
    peri_restart_free(r);
    return rc;
  }
  peri_restart_free(s->state.restart);
  s->state.restart = r;
  return PERI_OK;
}
