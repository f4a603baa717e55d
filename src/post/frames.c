/* Frames: gathers the requested per-node fields and writes the VTU series (VTU + PVD), the
 * Exodus II file (frames_exodus.c) and the end-of-run picture. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/bodies.h"
#include "peri/comm.h"
#include "peri/coupling.h"
#include "peri/indicator.h"
#include "peri/damage.h"
#include "peri/discretize.h"
#include "peri/damage_index.h"
#include "peri/decompose.h"
#include "peri/energies.h"
#include "peri/error.h"
#include "peri/heat_quantities.h"
#include "peri/output.h"
#include "peri/plastic_fields.h"
#include "peri/film_quantities.h"
#include "peri/bodies.h"
#include "peri/frames.h"
#include "peri/horizon_field.h"
#include "peri/stress.h"
#include "peri/thermal.h"
#include "peri/tensor_plasticity.h"
#include "frames_parts.h"

enum { MAX_FRAME_FIELDS = 24, MAX_FRAME_FIELDS_COPY = MAX_FRAME_FIELDS };

struct peri_frames {
  peri_pvd *pvd;                 /* rank 0, output.format vtu or both */
  peri_frames_exodus *exodus;    /* output.format exodus or both */
  int32_t *node_id;              /* [n_owned]: 1 + the node's global index, the Exodus node id */
  int count;
  double *points, *damage, *energy;
  double *stress, *strain, *von_mises, *principal; /* allocated when first asked for */
  double *d2u;
  double *yield_index, *plastic_stretch;           /* (docs/plasticity.md) likewise */
  double *spacing;
  int32_t *interface;            /* the interface nodes (docs/thin_films.md) */
};

/* A frame buffer of one value per owned node, allocated on first use. */
static double *node_buffer(const peri_sim *s, double **buffer) {
  if (!*buffer) *buffer = peri_malloc(sizeof(double) * (size_t)(s->disc.p.n_owned > 0 ? s->disc.p.n_owned : 1));
  return *buffer;
}

/* Each node's spacing, the edge of its volume's cell (a graded grid's zone spacing). */
static void node_spacing(const peri_sim *s, double *out) {
  const peri_geometry *g = &s->disc.geom;
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i)
    out[i] = peri_grid_node_spacing(s->disc.p.volume[i], g->dim, g->thickness, g->cross_section);
}

/* Stress (and its measures) of the current state into the frame buffers. */
static int compute_stress(peri_frames *f, peri_sim *s) {
  const size_t n = (size_t)s->disc.p.n_owned;
  if (!f->stress) {
    f->stress = peri_malloc(sizeof(double) * 9 * n);
    f->von_mises = peri_malloc(sizeof(double) * n);
    f->principal = peri_malloc(sizeof(double) * 3 * n);
  }
  if (s->disc.p.theta && s->disc.p.pstate) { /* LPS pair forces read the ghosts' theta and P (MPI ranks) */
    peri_sim_exchange(s, s->disc.p.theta, 1);
    peri_sim_exchange(s, s->disc.p.pstate, 1);
  }
  int rc = peri_stress(s, f->stress);
  if (rc == PERI_OK) peri_stress_measures(s, f->stress, f->von_mises, f->principal);
  return rc;
}

peri_frames *peri_frames_open(const peri_sim *s) {
  char path[4200];
  /* MPI ranks: rank 0 makes the directory and writes the .pvd; all agree on the outcome */
  int failed = peri_comm_rank() == 0 && peri_mkdir_p(s->out.directory) != PERI_OK;
  snprintf(path, sizeof path, "%s/%s.pvd", s->out.directory, s->out.basename);
  peri_frames *f = peri_calloc(1, sizeof *f);
  if (!failed && peri_comm_rank() == 0 && s->out.vtu) {
    f->pvd = peri_pvd_open(path);
    failed = !f->pvd;
  }
  if (peri_comm_max_int(failed)) {
    peri_pvd_close(f->pvd);
    free(f);
    return NULL;
  }
  if (s->out.exodus) {
    /* a restart writes beside the old file and replaces it once its steps are copied */
    char create[4300];
    snprintf(path, sizeof path, "%s/%s.e", s->out.directory, s->out.basename);
    snprintf(create, sizeof create, "%s%s", path, s->state.restart ? ".restart" : "");
    f->exodus = peri_frames_exodus_open(s, path, create);
    if (!f->exodus) {
      peri_pvd_close(f->pvd);
      free(f);
      return NULL;
    }
  }
  const size_t n_owned = (size_t)s->disc.p.n_owned;
  f->node_id = peri_malloc(sizeof(int32_t) * (n_owned > 0 ? n_owned : 1));
  for (size_t i = 0; i < n_owned; ++i) f->node_id[i] = 1 + (s->par.dd ? s->par.dd->global_id[i] : (int32_t)i);
  f->points = peri_malloc(sizeof(double) * 3 * (size_t)s->disc.p.n);
  f->damage = peri_malloc(sizeof(double) * (size_t)s->disc.p.n);
  return f;
}

peri_frames *peri_frames_buffers(const peri_sim *s) {
  peri_frames *f = peri_calloc(1, sizeof *f);
  f->points = peri_malloc(sizeof(double) * 3 * (size_t)(s->disc.p.n > 0 ? s->disc.p.n : 1));
  f->damage = peri_malloc(sizeof(double) * (size_t)(s->disc.p.n > 0 ? s->disc.p.n : 1));
  return f;
}

static void current_positions(const peri_sim *s, double *points) {
  for (size_t c = 0; c < 3 * (size_t)s->disc.p.n_owned; ++c) points[c] = s->disc.p.x[c] + s->disc.p.u[c];
}

/* Fictitious layer nodes are left out of the VTU frames (docs/deck.md section 10): the points
 * and each field's rows of the body nodes only, in copies that body_only_free releases.
 * Returns the body node count. */
typedef struct body_copy {
  double *points;
  void *rows[MAX_FRAME_FIELDS_COPY];
} body_copy;

static int32_t body_only(const peri_particles *p, double **points, peri_field *fields, int nf, body_copy *c) {
  int32_t n = 0;
  for (int32_t i = 0; i < p->n_owned; ++i) n += !(p->flags[i] & PERI_NODE_FICTITIOUS);
  memset(c, 0, sizeof *c);
  if (n == p->n_owned) return n;
  c->points = peri_malloc(sizeof(double) * 3 * (size_t)(n > 0 ? n : 1));
  for (int32_t i = 0, k = 0; i < p->n_owned; ++i)
    if (!(p->flags[i] & PERI_NODE_FICTITIOUS)) memcpy(&c->points[3 * k++], &(*points)[3 * i], 3 * sizeof(double));
  *points = c->points;
  for (int f = 0; f < nf && f < MAX_FRAME_FIELDS_COPY; ++f) {
    const size_t w = (size_t)fields[f].ncomp, size = fields[f].idata ? sizeof(int32_t) : sizeof(double);
    const char *from = fields[f].idata ? (const char *)fields[f].idata : (const char *)fields[f].data;
    char *to = peri_malloc(size * w * (size_t)(n > 0 ? n : 1));
    for (int32_t i = 0, k = 0; i < p->n_owned; ++i)
      if (!(p->flags[i] & PERI_NODE_FICTITIOUS)) memcpy(to + size * w * (size_t)k++, from + size * w * (size_t)i, size * w);
    c->rows[f] = to;
    if (fields[f].idata) fields[f].idata = (const int32_t *)to;
    else fields[f].data = (const double *)to;
  }
  return n;
}

static void body_only_free(body_copy *c) {
  free(c->points);
  for (int f = 0; f < MAX_FRAME_FIELDS_COPY; ++f) free(c->rows[f]);
}

/* MPI ranks (docs/parallel.md): each rank with nodes writes its piece <base>_<frame>_<rank>.vtu,
 * rank 0 the index <base>_<frame>.pvtu that the .pvd lists. */
static int write_pieces(peri_frames *f, peri_sim *s, const peri_field *fields, int nf, const double *points,
                        int32_t n_body) {
  const peri_decomposition *d = s->par.dd;
  char file[512], path[4700];
  int rc = PERI_OK;
  if (s->disc.p.n_owned > 0) {
    snprintf(file, sizeof file, "%s_%06d_%d.vtu", s->out.basename, f->count, d->rank);
    snprintf(path, sizeof path, "%s/%s", s->out.directory, file);
    rc = peri_vtu_write_at(path, s->state.time, n_body, points, fields, nf, s->out.compress);
  }
  if (d->rank == 0 && rc == PERI_OK) {
    char **pieces = peri_calloc((size_t)d->size, sizeof(char *));
    int n_pieces = 0;
    for (int r = 0; r < d->size; ++r) {
      if (d->owned[r] == 0) continue; /* a rank without nodes writes no piece */
      snprintf(file, sizeof file, "%s_%06d_%d.vtu", s->out.basename, f->count, r);
      pieces[n_pieces++] = peri_strdup(file);
    }
    snprintf(file, sizeof file, "%s_%06d.pvtu", s->out.basename, f->count);
    snprintf(path, sizeof path, "%s/%s", s->out.directory, file);
    rc = peri_pvtu_write(path, (const char *const *)pieces, n_pieces, fields, nf);
    if (rc == PERI_OK) rc = peri_pvd_add(f->pvd, s->state.time, file);
    for (int k = 0; k < n_pieces; ++k) free(pieces[k]);
    free(pieces);
  }
  return peri_comm_max_int(rc);
}

/* One field of output.fields at the current state into *out, pointing at this rank's owned
 * nodes (derived ones computed into the frame's buffers); 1, 0 when this run has no such
 * field (dilatation without LPS, temperature without heat), -1 when the stress could not be
 * recovered. `stress_done`: the stress buffers already hold this state's stress. */
static int frame_field(peri_frames *f, peri_sim *s, const char *name, peri_field *out, bool *stress_done) {
  const peri_particles *p = &s->disc.p;
  peri_field fl = {.name = name, .ncomp = peri_frame_field_components(s, name)};
  if (fl.ncomp == 0) return 0;
  if (!strcmp(name, "displacement")) fl.data = p->u;
  else if (!strcmp(name, "velocity")) fl.data = p->v;
  else if (!strcmp(name, "force")) fl.data = p->f;
  else if (!strcmp(name, "damage")) {
    peri_damage_index(s, f->damage);
    fl.data = f->damage;
  } else if (!strcmp(name, "dilatation")) fl.data = p->theta;
  else if (!strcmp(name, "horizon")) fl.data = s->disc.horizon_field->delta;
  else if (!strcmp(name, "spacing")) {
    if (!f->spacing) f->spacing = peri_malloc(sizeof(double) * (size_t)(p->n_owned > 0 ? p->n_owned : 1));
    node_spacing(s, f->spacing);
    fl.data = f->spacing;
  }
  else if (!strcmp(name, "material")) fl.idata = p->material;
  else if (!strcmp(name, "block")) fl.idata = p->block;
  else if (!strcmp(name, "body")) fl.idata = s->bodies->label; /* 0, 1, ... in list order; -1 outside */
  else if (!strcmp(name, "node_type")) fl.idata = s->coupling->node_type;
  else if (!strcmp(name, "interface")) {
    if (!f->interface) f->interface = peri_malloc(sizeof(int32_t) * (size_t)(p->n_owned > 0 ? p->n_owned : 1));
    peri_interface_flags(s, f->interface);
    fl.idata = f->interface;
  }
  else if (!strcmp(name, "d2u")) { /* D^2(u), eq. 2.115 (docs/coupling.md) */
    if (!f->d2u) f->d2u = peri_malloc(sizeof(double) * (size_t)(p->n_owned > 0 ? p->n_owned : 1));
    peri_second_derivative_indicator(s, f->d2u);
    fl.data = f->d2u;
  }
  else if (!strcmp(name, "volume")) fl.data = p->volume;
  else if (!strcmp(name, "strain_energy_density")) {
    peri_strain_energy(s);
    fl.data = s->disc.p.energy;
  } else if (!strcmp(name, "stress") || !strcmp(name, "von_mises") || !strcmp(name, "principal_stress")) {
    if (!*stress_done && compute_stress(f, s) != PERI_OK) return -1;
    *stress_done = true;
    if (!strcmp(name, "stress")) fl.data = f->stress;
    else if (!strcmp(name, "von_mises")) fl.data = f->von_mises;
    else fl.data = f->principal;
  } else if (!strcmp(name, "temperature")) {
    fl.data = s->thermal->T;
  } else if (!strcmp(name, "heat_flux")) { /* into-flux, Bobaru & Duangpanya 2012 eq. 7 */
    peri_thermal_flux(s);
    fl.data = s->thermal->flux;
  } else if (!strcmp(name, "yield_index") || !strcmp(name, "plastic_stretch")) { /* docs/plasticity.md */
    double *values = node_buffer(s, !strcmp(name, "yield_index") ? &f->yield_index : &f->plastic_stretch);
    if (!strcmp(name, "yield_index")) peri_yield_index(s, values);
    else peri_plastic_stretch_field(s, values);
    fl.data = values;
  } else if (!strcmp(name, "strain")) {
    if (!f->strain) f->strain = peri_malloc(sizeof(double) * 9 * (size_t)p->n_owned);
    peri_strain(s, f->strain);
    fl.data = f->strain;
  } else return 0;
  *out = fl;
  return 1;
}

int peri_frames_field(peri_frames *f, peri_sim *s, const char *name, peri_field *out) {
  bool stress_done = false;
  return frame_field(f, s, name, out, &stress_done);
}

/* The fields of output.fields that this run has; their count, or -1 when the stress could
 * not be recovered. */
static int frame_fields(peri_frames *f, peri_sim *s, peri_field *fields, int capacity) {
  int nf = 0;
  bool stress_done = false;
  for (int k = 0; k < s->out.n_fields && nf < capacity; ++k) {
    const int got = frame_field(f, s, s->out.fields[k], &fields[nf], &stress_done);
    if (got < 0) return -1;
    nf += got;
  }
  return nf;
}


int peri_frames_write(peri_frames *f, peri_sim *s) {
  const peri_particles *p = &s->disc.p;
  peri_field fields[MAX_FRAME_FIELDS];
  int nf = frame_fields(f, s, fields, MAX_FRAME_FIELDS - 2);
  if (nf < 0) return PERI_ERR_RUN;
  int rc = PERI_OK;
  if (f->exodus) rc = peri_frames_exodus_write(f->exodus, s, fields, nf);
  if (rc == PERI_OK && s->out.vtu) {
    /* every VTU frame: the node's id and reference position, so that a node is followed
     * from frame to frame and its motion read without the first frame */
    fields[nf++] = (peri_field){.name = "node_id", .ncomp = 1, .idata = f->node_id};
    fields[nf++] = (peri_field){.name = "reference_position", .ncomp = 3, .data = p->x};
    current_positions(s, f->points);
    double *points = f->points;
    body_copy copy;
    const int32_t n_body = body_only(p, &points, fields, nf, &copy);
    if (s->par.dd) rc = write_pieces(f, s, fields, nf, points, n_body);
    else {
      char file[512], path[4700];
      snprintf(file, sizeof file, "%s_%06d.vtu", s->out.basename, f->count);
      snprintf(path, sizeof path, "%s/%s", s->out.directory, file);
      rc = peri_vtu_write_at(path, s->state.time, n_body, points, fields, nf, s->out.compress);
      if (rc == PERI_OK) rc = peri_pvd_add(f->pvd, s->state.time, file);
    }
    body_only_free(&copy);
  }
  if (rc == PERI_OK) f->count++;
  return rc;
}

void peri_frames_history(peri_frames *f, const double *row) {
  if (f && f->exodus) peri_frames_exodus_history(f->exodus, row);
}

int peri_frames_resume(peri_frames *f, long next, long n_listed, const double *times, char *const *files) {
  f->count = (int)next;
  for (long k = 0; f->pvd && k < n_listed; ++k) /* MPI ranks: rank 0 keeps the .pvd */
    if (peri_pvd_add(f->pvd, times[k], files[k]) != PERI_OK) return PERI_ERR_RUN;
  return f->exodus ? peri_frames_exodus_resume(f->exodus, next) : PERI_OK;
}

long peri_frames_written(const peri_frames *f) { return f->count; }

int peri_frames_picture(peri_frames *f, peri_sim *s, char *path_out, size_t n) {
  const peri_particles *p = &s->disc.p;
  current_positions(s, f->points);
  const char *name = s->out.picture_field;
  double *values = peri_malloc(sizeof(double) * (size_t)p->n_owned);
  double vmin = 0.0, vmax = 0.0;
  if (!strcmp(name, "damage")) {
    peri_damage_index(s, values);
    vmin = 0.0, vmax = 1.0;
  } else if (!strcmp(name, "displacement") || !strcmp(name, "velocity") || !strcmp(name, "force")) {
    const double *v = !strcmp(name, "displacement") ? p->u : !strcmp(name, "velocity") ? p->v : p->f;
    for (int32_t i = 0; i < p->n_owned; ++i)
      values[i] = sqrt(v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
  } else if (!strcmp(name, "dilatation") && p->theta) {
    memcpy(values, p->theta, sizeof(double) * (size_t)p->n_owned);
  } else if (!strcmp(name, "horizon") && s->disc.horizon_field) {
    memcpy(values, s->disc.horizon_field->delta, sizeof(double) * (size_t)p->n_owned);
  } else if (!strcmp(name, "spacing")) {
    node_spacing(s, values);
  } else if (!strcmp(name, "interface")) {
    int32_t *flag = peri_malloc(sizeof(int32_t) * (size_t)(p->n_owned > 0 ? p->n_owned : 1));
    peri_interface_flags(s, flag);
    for (int32_t i = 0; i < p->n_owned; ++i) values[i] = flag[i];
    free(flag);
  } else if (!strcmp(name, "strain_energy_density")) {
    peri_strain_energy(s);
    memcpy(values, p->energy, sizeof(double) * (size_t)p->n_owned);
  } else if (!strcmp(name, "stress") || !strcmp(name, "von_mises") || !strcmp(name, "principal_stress")) {
    if (compute_stress(f, s) != PERI_OK) {
      free(values);
      return PERI_ERR_RUN;
    }
    for (int32_t i = 0; i < p->n_owned; ++i)
      values[i] = !strcmp(name, "principal_stress") ? f->principal[3 * (size_t)i] : f->von_mises[i];
  } else if (!strcmp(name, "strain")) {
    double *e = peri_malloc(sizeof(double) * 9 * (size_t)p->n_owned);
    peri_strain(s, e);
    for (int32_t i = 0; i < p->n_owned; ++i) {
      double sum = 0.0;
      for (int k = 0; k < 9; ++k) sum += e[9 * (size_t)i + k] * e[9 * (size_t)i + k];
      values[i] = sqrt(sum);
    }
    free(e);
  } else if (!strcmp(name, "yield_index") && peri_has_plasticity(s)) {
    peri_yield_index(s, values);
    vmin = 0.0, vmax = 1.0;
  } else if (!strcmp(name, "plastic_stretch") && peri_has_plasticity(s)) {
    peri_plastic_stretch_field(s, values);
  } else if (!strcmp(name, "temperature") && s->thermal) {
    memcpy(values, s->thermal->T, sizeof(double) * (size_t)p->n_owned);
  } else if (!strcmp(name, "heat_flux") && s->thermal) {
    peri_thermal_flux(s);
    const double *q = s->thermal->flux;
    for (int32_t i = 0; i < p->n_owned; ++i)
      values[i] = sqrt(q[3 * i] * q[3 * i] + q[3 * i + 1] * q[3 * i + 1] + q[3 * i + 2] * q[3 * i + 2]);
  } else if (!strcmp(name, "volume")) {
    memcpy(values, p->volume, sizeof(double) * (size_t)p->n_owned);
  } else if (!strcmp(name, "d2u")) {
    peri_second_derivative_indicator(s, values);
  } else {
    const int32_t *v = !strcmp(name, "block") ? p->block : !strcmp(name, "node_type") ? s->coupling->node_type
                     : !strcmp(name, "body")   ? s->bodies->label : p->material;
    for (int32_t i = 0; i < p->n_owned; ++i) values[i] = v[i];
  }
  snprintf(path_out, n, "%s/%s.png", s->out.directory, name);
  /* rank 0 draws every node, gathered in global order (a copy in a single process) */
  const bool root = peri_comm_rank() == 0;
  const size_t all = (size_t)peri_global_nodes(s), room = all > 0 ? all : 1;
  double *points = root ? peri_malloc(sizeof(double) * 3 * room) : NULL;
  double *reference = root ? peri_malloc(sizeof(double) * 3 * room) : NULL;
  double *every = root ? peri_malloc(sizeof(double) * room) : NULL;
  peri_gather_owned(s, f->points, 3, points);
  peri_gather_owned(s, p->x, 3, reference);
  peri_gather_owned(s, values, 1, every);
  /* several materials in 2D: the material of every node, for the phase boundaries */
  const bool phases = s->disc.geom.dim == 2 && s->mat.n_materials > 1;
  int32_t *phase = root && phases ? peri_malloc(sizeof(int32_t) * room) : NULL;
  if (phases) {
    for (int32_t i = 0; i < p->n_owned; ++i) values[i] = p->material[i];
    double *material = root ? peri_malloc(sizeof(double) * room) : NULL;
    peri_gather_owned(s, values, 1, material);
    for (size_t k = 0; root && k < all; ++k) phase[k] = (int32_t)material[k];
    free(material);
  }
  free(values);
  int rc = PERI_OK;
  if (root) {
    const bool magnitude = peri_frame_field_components(s, name) == 3 && strcmp(name, "principal_stress");
    char value_label[160], title[320], x_label[16] = "x [m]", y_label[16] = "y [m]";
    const char *unit = peri_frame_field_unit(name);
    snprintf(value_label, sizeof value_label, "%s%s%s [%s]", magnitude ? "|" : "",
             !strcmp(name, "principal_stress") ? "largest principal stress" : !strcmp(name, "stress") ? "von Mises stress"
             : !strcmp(name, "strain") ? "strain norm" : name, magnitude ? "|" : "", *unit ? unit : "-");
    snprintf(title, sizeof title, "%s  (t = %.4g s)", name, s->state.time);
    int32_t drawn = (int32_t)all;
    if (s->disc.geom.dim == 3) { /* the view of output.picture: a slice or a projection */
      const int a = s->out.picture_normal, u = a == 0 ? 1 : 0, v = a == 2 ? 1 : 2;
      double lo = INFINITY, hi = -INFINITY;
      for (size_t k = 0; k < all; ++k) lo = fmin(lo, reference[3 * k + a]), hi = fmax(hi, reference[3 * k + a]);
      double at = s->out.picture_at_given ? s->out.picture_at : 0.5 * (lo + hi), layer = at;
      for (size_t k = 0; k < all; ++k) /* the lattice layer nearest the plane asked for */
        if (fabs(reference[3 * k + a] - at) < fabs(layer - at) || k == 0) layer = reference[3 * k + a];
      const double half = 0.25 * s->disc.geom.spacing;
      drawn = 0;
      for (size_t k = 0; k < all; ++k) {
        if (!s->out.picture_projection && !(fabs(reference[3 * k + a] - layer) <= half)) continue;
        const double pu = points[3 * k + u], pv = points[3 * k + v];
        points[3 * (size_t)drawn] = pu, points[3 * (size_t)drawn + 1] = pv, points[3 * (size_t)drawn + 2] = 0.0;
        every[drawn++] = every[k];
      }
      x_label[0] = "xyz"[u], y_label[0] = "xyz"[v];
      const size_t len = strlen(title);
      if (s->out.picture_projection)
        snprintf(title + len, sizeof title - len, ", largest along %c", "xyz"[a]);
      else
        snprintf(title + len, sizeof title - len, ", slice %c = %.4g m", "xyz"[a], layer);
    }
    peri_png_axes axes = {.x_label = x_label, .y_label = y_label, .value_label = value_label};
    if (phase) { /* several materials in 2D: their boundaries drawn (docs/microstructures.md) */
      axes.phase = phase;
      axes.reference = reference;
    }
    rc = peri_png_write_field_axes(path_out, drawn, points, every, vmin, vmax, s->disc.geom.spacing,
                                   s->out.picture_width, title, &axes);
  }
  free(points);
  free(reference);
  free(every);
  free(phase);
  return peri_comm_max_int(rc);
}

void peri_frames_close(peri_frames *f) {
  if (!f) return;
  peri_pvd_close(f->pvd);
  peri_frames_exodus_close(f->exodus);
  free(f->node_id);
  free(f->points);
  free(f->damage);
  free(f->stress);
  free(f->strain);
  free(f->d2u);
  free(f->von_mises);
  free(f->principal);
  free(f->yield_index);
  free(f->plastic_stretch);
  free(f->spacing);
  free(f->interface);
  free(f);
}
