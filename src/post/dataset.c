/* Graph datasets (include/peri/dataset.h, docs/datasets.md): the particles as nodes and
 * the directed bonds as edges, with per-frame node fields (u, v, f, b, damage, yield
 * index) and edge fields (stretch, broken, bond force), and the run's constants. On MPI
 * ranks every array is gathered on rank 0 in the global node and bond order, which is the
 * order of a single process, so the file does not depend on the number of ranks. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/damage_index.h"
#include "peri/dataset.h"
#include "peri/dataset_file.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/model.h"
#include "peri/plastic_fields.h"
#include "peri/tensor_plasticity.h"

/* Version of the layout of docs/datasets.md; a reader checks it. */
#define PERI_DATASET_FORMAT_VERSION 1

void peri_dataset_output_free(peri_dataset_output *d) {
  if (!d) return;
  for (int k = 0; k < d->n_tags; ++k) {
    free(d->tags[k].name);
    free(d->tags[k].text);
  }
  free(d->tags);
  free(d->file);
  free(d);
}

void peri_dataset_path(const peri_sim *s, char *out, size_t size) {
  const char *file = s->out.dataset->file;
  if (file[0] == '/') snprintf(out, size, "%s", file);
  else snprintf(out, size, "%s/%s", s->out.directory, file);
}

/* ---------------------------------------------------------------- gathering */

/* Rank 0's copy of ncomp doubles per owned node of every rank (global order); a copy in
 * one process. NULL on the other ranks. Collective. */
static double *nodes_on_root(const peri_sim *s, const double *local, int ncomp) {
  const int64_t n = peri_global_nodes(s);
  double *all = peri_comm_rank() == 0 ? peri_malloc(sizeof(double) * (size_t)ncomp * (size_t)(n > 0 ? n : 1)) : NULL;
  peri_gather_owned(s, local, ncomp, all);
  return all;
}

/* The same for one double per directed bond of the owned families (global bond order). */
static double *bonds_on_root(const peri_sim *s, const double *local) {
  const peri_decomposition *d = s->par.dd;
  const int64_t n_bonds = peri_global_bonds(s);
  double *all = peri_comm_rank() == 0 ? peri_malloc(sizeof(double) * (size_t)(n_bonds > 0 ? n_bonds : 1)) : NULL;
  if (!d) {
    if (n_bonds > 0) memcpy(all, local, sizeof(double) * (size_t)n_bonds);
    return all;
  }
  int64_t *counts = peri_malloc(sizeof(int64_t) * (size_t)d->size);
  for (int r = 0; r < d->size; ++r) counts[r] = d->bond_first[r + 1] - d->bond_first[r];
  peri_comm_gather_doubles(local, s->disc.bonds.n_bonds, counts, all);
  free(counts);
  return all;
}

/* Integers travel as doubles (exact below 2^53) through the same gathers. */
static int32_t *to_ints(double *all, int64_t count) {
  if (!all) return NULL;
  int32_t *out = peri_malloc(sizeof(int32_t) * (size_t)(count > 0 ? count : 1));
  for (int64_t k = 0; k < count; ++k) out[k] = (int32_t)all[k];
  free(all);
  return out;
}

static int32_t global_index(const peri_sim *s, int32_t local) {
  return s->par.dd ? s->par.dd->global_id[local] : local;
}

/* ---------------------------------------------------------------- the file */

static const char *plane_name(peri_plane p) { return p == PERI_PLANE_STRESS ? "stress" : p == PERI_PLANE_STRAIN ? "strain" : "none"; }
static const char *rule_name(peri_partial_volume r) { return r == PERI_PV_LINEAR ? "linear" : r == PERI_PV_LAMMPS ? "lammps" : "none"; }
static const char *influence_name(peri_influence w) {
  return w == PERI_INFLUENCE_INVERSE ? "inverse" : w == PERI_INFLUENCE_GAUSSIAN ? "gaussian" : "constant";
}

/* The whole deck file, or "" when it cannot be read (a record, not an input). */
static char *deck_text(const char *path) {
  FILE *in = fopen(path, "rb");
  if (!in) return peri_strdup("");
  fseek(in, 0, SEEK_END);
  const long size = ftell(in);
  fseek(in, 0, SEEK_SET);
  char *text = peri_calloc((size_t)(size > 0 ? size : 0) + 1, 1);
  if (size > 0 && fread(text, 1, (size_t)size, in) != (size_t)size) text[0] = '\0';
  fclose(in);
  return text;
}

/* The run's constants: /globals, /materials. */
static void write_constants(peri_dataset_file *f, const peri_sim *s) {
  const peri_geometry *g = &s->disc.geom;
  peri_dataset_file_attr_string(f, "/", "format", "peri graph dataset");
  peri_dataset_file_attr_long(f, "/", "format_version", PERI_DATASET_FORMAT_VERSION);
  peri_dataset_file_attr_string(f, "/", "peri_version", PERI_VERSION);
  peri_dataset_file_attr_string(f, "/", "model", s->mat.model->name);
  char *deck = deck_text(s->deck_path);
  const char *text[1] = {deck};
  peri_dataset_file_strings(f, "/deck_text", 1, text);
  free(deck);

  peri_dataset_file_group(f, "/globals");
  peri_dataset_file_attr_long(f, "/globals", "dimension", g->dim);
  peri_dataset_file_attr_string(f, "/globals", "plane", plane_name(g->plane));
  peri_dataset_file_attr_double(f, "/globals", "horizon", g->horizon);
  peri_dataset_file_attr_double(f, "/globals", "spacing", g->spacing);
  peri_dataset_file_attr_double(f, "/globals", "thickness", g->thickness);
  peri_dataset_file_attr_string(f, "/globals", "partial_volume", rule_name(s->disc.family.rule));
  peri_dataset_file_attr_string(f, "/globals", "influence", influence_name(s->disc.family.influence));
  peri_dataset_file_attr_double(f, "/globals", "time_step", s->solver.dt);
  peri_dataset_file_attr_long(f, "/globals", "steps", s->solver.steps);
  peri_dataset_file_attr_long(f, "/globals", "every", s->out.dataset->every);
  peri_dataset_file_group(f, "/globals/tags");
  for (int k = 0; k < s->out.dataset->n_tags; ++k) {
    const peri_dataset_tag *t = &s->out.dataset->tags[k];
    if (t->text) peri_dataset_file_attr_string(f, "/globals/tags", t->name, t->text);
    else peri_dataset_file_attr_double(f, "/globals/tags", t->name, t->value);
  }

  const int m = s->mat.n_materials;
  const char **names = peri_malloc(sizeof(char *) * (size_t)(m > 0 ? m : 1));
  double *col = peri_malloc(sizeof(double) * (size_t)(m > 0 ? m : 1) * PERI_MAX_SUBLAYERS);
  int32_t *layers = peri_calloc((size_t)(m > 0 ? m : 1), sizeof(int32_t));
  peri_dataset_file_group(f, "/materials");
  for (int a = 0; a < m; ++a) names[a] = s->mat.materials[a].name;
  peri_dataset_file_strings(f, "/materials/name", m, names);
#define MATERIAL_COLUMN(NAME, EXPR)                                                 \
  for (int a = 0; a < m; ++a) {                                                     \
    const peri_material *mat = &s->mat.materials[a];                                \
    col[a] = (EXPR);                                                                \
  }                                                                                 \
  peri_dataset_file_doubles(f, "/materials/" NAME, m, 1, col);
  MATERIAL_COLUMN("youngs_modulus", mat->E)
  MATERIAL_COLUMN("poisson_ratio", mat->nu)
  MATERIAL_COLUMN("bulk_modulus", mat->K)
  MATERIAL_COLUMN("shear_modulus", mat->mu)
  MATERIAL_COLUMN("density", mat->density)
  MATERIAL_COLUMN("critical_stretch", mat->critical_stretch)
  MATERIAL_COLUMN("micromodulus", mat->micromodulus)
  MATERIAL_COLUMN("critical_plastic_stretch", mat->sublayers ? mat->sublayers->critical_plastic_stretch : INFINITY)
#undef MATERIAL_COLUMN
  /* the sublayer table (docs/plasticity.md): zero rows beyond a material's count */
  bool any_plastic = false;
  for (int a = 0; a < m; ++a) {
    const peri_sublayers *sl = s->mat.materials[a].sublayers;
    layers[a] = sl ? sl->n : 0;
    any_plastic = any_plastic || sl;
  }
  peri_dataset_file_ints(f, "/materials/sublayer_count", m, 1, layers);
  if (any_plastic) {
    for (int pass = 0; pass < 2; ++pass) {
      for (int a = 0; a < m; ++a)
        for (int k = 0; k < PERI_MAX_SUBLAYERS; ++k) {
          const peri_sublayers *sl = s->mat.materials[a].sublayers;
          col[a * PERI_MAX_SUBLAYERS + k] = sl && k < sl->n ? (pass ? sl->yield[k] : sl->weight[k]) : 0.0;
        }
      peri_dataset_file_doubles(f, pass ? "/materials/sublayer_yield_stretch" : "/materials/sublayer_weight", m,
                                PERI_MAX_SUBLAYERS, col);
    }
  }
  free(layers);
  free(col);
  free(names);
}

/* The nodes' reference data and the edges (rank 0's gathered arrays). */
static void write_graph(peri_dataset_file *f, int64_t n, int64_t n_edges, const double *x, const double *volume,
                        const int32_t *material, const int32_t *body, const int32_t *no_fail, const int32_t *receiver,
                        const int32_t *sender) {
  peri_dataset_file_attr_long(f, "/", "n_nodes", (long)n);
  peri_dataset_file_attr_long(f, "/", "n_edges", (long)n_edges);
  peri_dataset_file_group(f, "/nodes");
  peri_dataset_file_doubles(f, "/nodes/x", n, 3, x);
  peri_dataset_file_doubles(f, "/nodes/volume", n, 1, volume);
  peri_dataset_file_ints(f, "/nodes/material", n, 1, material);
  peri_dataset_file_ints(f, "/nodes/body", n, 1, body);
  peri_dataset_file_ints(f, "/nodes/no_fail", n, 1, no_fail); /* 1: the node's bonds never break */
  peri_dataset_file_group(f, "/edges");
  peri_dataset_file_ints(f, "/edges/receiver", n_edges, 1, receiver);
  peri_dataset_file_ints(f, "/edges/sender", n_edges, 1, sender);
  peri_dataset_file_group(f, "/frames");
}

/* ---------------------------------------------------------------- frames */

/* Stretch and bond force of every directed bond of the owned families: the stretch
 * (|y| - |xi|)/|xi| of the deformed bond, and the force density that the bond puts on its
 * receiver along y/|y|, pair * beta V_sender (0 when broken; include/peri/model.h). */
static void edge_fields(const peri_sim *s, double *stretch, double *force) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      double xi[3], r2 = 0.0;
      const double r0 = peri_bond_xi(p->x, i, j, xi);
      for (int d = 0; d < 3; ++d) {
        const double y = xi[d] + p->u[3 * (size_t)j + d] - p->u[3 * (size_t)i + d];
        r2 += y * y;
      }
      const double r = sqrt(r2);
      stretch[k] = (r - r0) / r0;
      force[k] = b->broken[k] || !(r > 0.0) ? 0.0
                                            : s->mat.model->pair_force(s, i, k, r) * peri_bonds_beta(b, r0) * p->volume[j];
    }
}

static int write_frame(peri_sim *s) {
  peri_dataset_output *ds = s->out.dataset;
  const peri_particles *p = &s->disc.p;
  const int64_t n = peri_global_nodes(s), n_edges = peri_global_bonds(s);
  const size_t owned = (size_t)(p->n_owned > 0 ? p->n_owned : 1), bonds = (size_t)(s->disc.bonds.n_bonds > 0 ? s->disc.bonds.n_bonds : 1);
  double *damage = peri_malloc(sizeof(double) * owned), *yield = NULL;
  peri_damage_index(s, damage);
  if (peri_has_plasticity(s)) {
    yield = peri_malloc(sizeof(double) * owned);
    peri_yield_index(s, yield);
  }
  double *stretch = peri_malloc(sizeof(double) * bonds), *force = peri_malloc(sizeof(double) * bonds);
  edge_fields(s, stretch, force);
  double *all[8] = {nodes_on_root(s, p->u, 3), nodes_on_root(s, p->v, 3), nodes_on_root(s, p->f, 3),
                    nodes_on_root(s, p->b, 3), nodes_on_root(s, damage, 1),
                    yield ? nodes_on_root(s, yield, 1) : NULL, bonds_on_root(s, stretch), bonds_on_root(s, force)};
  uint8_t *broken = peri_comm_rank() == 0 ? peri_malloc((size_t)(n_edges > 0 ? n_edges : 1)) : NULL;
  peri_gather_owned_bonds(s, s->disc.bonds.broken, broken);
  free(damage), free(yield), free(stretch), free(force);
  int rc = PERI_OK;
  if (peri_comm_rank() == 0) {
    char path[8192], group[64], name[128];
    peri_dataset_path(s, path, sizeof path);
    peri_dataset_file *f = peri_dataset_file_open(path, true);
    if (!f) {
      rc = PERI_ERR_RUN;
    } else {
      snprintf(group, sizeof group, "/frames/%06ld", ds->frames);
      peri_dataset_file_group(f, group);
      peri_dataset_file_attr_long(f, group, "step", s->state.step);
      peri_dataset_file_attr_double(f, group, "time", s->state.time);
      static const char *const names[8] = {"u", "v", "f", "b", "damage", "yield_index", "stretch", "bond_force"};
      for (int a = 0; a < 8; ++a) {
        if (!all[a]) continue;
        snprintf(name, sizeof name, "%s/%s", group, names[a]);
        peri_dataset_file_doubles(f, name, a < 6 ? n : n_edges, a < 4 ? 3 : 1, all[a]);
      }
      snprintf(name, sizeof name, "%s/broken", group);
      peri_dataset_file_bytes(f, name, n_edges, broken);
      peri_dataset_file_attr_long(f, "/frames", "count", ds->frames + 1);
      rc = peri_dataset_file_close(f);
    }
  }
  for (int a = 0; a < 8; ++a) free(all[a]);
  free(broken);
  ds->frames++;
  return s->par.dd ? peri_comm_max_int(rc) : rc;
}

int peri_dataset_begin(peri_sim *s) {
  if (!s->out.dataset) return PERI_OK;
  if (s->state.restart) {
    peri_error("output.dataset: a restarted run cannot continue a graph dataset (its first frames are in the "
               "checkpoint's run); run the deck from the start, or drop output.dataset");
    return PERI_ERR_RUN;
  }
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int64_t n = peri_global_nodes(s), n_edges = peri_global_bonds(s);
  const size_t owned = (size_t)(p->n_owned > 0 ? p->n_owned : 1), bonds = (size_t)(b->n_bonds > 0 ? b->n_bonds : 1);
  double *ids = peri_malloc(sizeof(double) * owned * 3), *ends = peri_malloc(sizeof(double) * bonds * 2);
  for (int32_t i = 0; i < p->n_owned; ++i) {
    ids[i] = p->material[i];
    ids[owned + i] = p->block[i];
    ids[2 * owned + i] = (p->flags[i] & PERI_NODE_NO_FAIL) ? 1.0 : 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      ends[k] = global_index(s, i);
      ends[bonds + k] = global_index(s, b->neighbor[k]);
    }
  }
  double *x = nodes_on_root(s, p->x, 3), *volume = nodes_on_root(s, p->volume, 1);
  int32_t *material = to_ints(nodes_on_root(s, ids, 1), n), *body = to_ints(nodes_on_root(s, ids + owned, 1), n);
  int32_t *no_fail = to_ints(nodes_on_root(s, ids + 2 * owned, 1), n);
  int32_t *receiver = to_ints(bonds_on_root(s, ends), n_edges), *sender = to_ints(bonds_on_root(s, ends + bonds), n_edges);
  free(ids), free(ends);
  int rc = PERI_OK;
  if (peri_comm_rank() == 0) {
    char path[8192];
    peri_dataset_path(s, path, sizeof path);
    peri_dataset_file *f = peri_dataset_file_open(path, false);
    if (!f) {
      rc = PERI_ERR_RUN;
    } else {
      write_constants(f, s);
      write_graph(f, n, n_edges, x, volume, material, body, no_fail, receiver, sender);
      rc = peri_dataset_file_close(f);
    }
  }
  free(x), free(volume), free(material), free(body), free(no_fail), free(receiver), free(sender);
  if (s->par.dd) rc = peri_comm_max_int(rc);
  s->out.dataset->frames = 0;
  return rc == PERI_OK ? write_frame(s) : rc;
}

int peri_dataset_after_step(peri_sim *s) {
  return peri_dataset_due(s, s->state.step) ? write_frame(s) : PERI_OK;
}

bool peri_dataset_due(const peri_sim *s, long step) {
  const peri_dataset_output *ds = s->out.dataset;
  return ds && (step % ds->every == 0 || step == s->solver.steps);
}
