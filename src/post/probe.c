/* Named scalar quantities of a solved simulation (include/peri/probe.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/energies.h"
#include "peri/error.h"
#include "peri/phase_stress.h"
#include "peri/probe.h"
#include "peri/stress.h"

typedef struct probe {
  enum { P_MAX_VM, P_MAX_U, P_ENERGY, P_NODES, P_ITERATIONS, P_POINT, P_MEAN, P_REACTION, P_PHASE } kind;
  char region[256];   /* also the material of max_von_mises:MATERIAL, mean_stress:MATERIAL */
  bool phase_mean;    /* mean_stress:MATERIAL instead of max_von_mises:MATERIAL */
  enum { F_VM, F_STRESS, F_STRAIN, F_U } field;
  int a, b;          /* components */
  double point[3];
  int n_coords;
  int axis;          /* mean/max: the fixed coordinate */
  bool column_max;   /* max:FIELD@x=X instead of the mean */
} probe;

static int axis_of(char c) { return c == 'x' ? 0 : c == 'y' ? 1 : c == 'z' ? 2 : -1; }

static int parse_field(const char *f, size_t len, probe *p) {
  if (len == 9 && !strncmp(f, "von_mises", 9)) return p->field = F_VM, 0;
  if (len == 9 && !strncmp(f, "stress_", 7)) {
    p->field = F_STRESS, p->a = axis_of(f[7]), p->b = axis_of(f[8]);
    return p->a < 0 || p->b < 0 ? -1 : 0;
  }
  if (len == 9 && !strncmp(f, "strain_", 7)) {
    p->field = F_STRAIN, p->a = axis_of(f[7]), p->b = axis_of(f[8]);
    return p->a < 0 || p->b < 0 ? -1 : 0;
  }
  if (len == 14 && !strncmp(f, "displacement_", 13)) {
    p->field = F_U, p->a = axis_of(f[13]);
    return p->a < 0 ? -1 : 0;
  }
  return -1;
}

static int parse(const char *name, probe *p, char *why, size_t n) {
  memset(p, 0, sizeof *p);
  static const char *const simple[] = {"max_von_mises", "max_displacement", "strain_energy", "nodes", "iterations"};
  for (int k = 0; k < 5; ++k)
    if (!strcmp(name, simple[k])) return p->kind = k, PERI_OK;
  size_t len = strlen(name);
  const bool phase_max = !strncmp(name, "max_von_mises:", 14), phase_mean = !strncmp(name, "mean_stress:", 12);
  if (phase_max || phase_mean) { /* per material, layers left out (docs/microstructures.md) */
    const char *material = name + (phase_max ? 14 : 12);
    if (!*material || strlen(material) >= sizeof p->region) {
      snprintf(why, n, "quantity '%s': expected max_von_mises:MATERIAL or mean_stress:MATERIAL", name);
      return PERI_ERR_INPUT;
    }
    p->kind = P_PHASE;
    p->phase_mean = phase_mean;
    snprintf(p->region, sizeof p->region, "%s", material);
    return PERI_OK;
  }
  if (!strncmp(name, "reaction_", 9) && len > 11 && name[len - 2] == '_' && axis_of(name[len - 1]) >= 0 &&
      len - 11 < sizeof p->region) {
    p->kind = P_REACTION;
    memcpy(p->region, name + 9, len - 11);
    p->region[len - 11] = '\0';
    p->a = axis_of(name[len - 1]);
    return PERI_OK;
  }
  bool mean = !strncmp(name, "mean:", 5), max = !strncmp(name, "max:", 4);
  p->column_max = max;
  const char *f = mean ? name + 5 : max ? name + 4 : name;
  const char *at = strchr(f, '@');
  if (!at || parse_field(f, (size_t)(at - f), p) != 0) {
    snprintf(why, n, "unknown quantity '%s' (max_von_mises, max_displacement, strain_energy, nodes, "
                     "iterations, reaction_REGION_x, max_von_mises:MATERIAL, mean_stress:MATERIAL, FIELD@X,Y[,Z], mean:FIELD@x=X, max:FIELD@x=X; FIELD: von_mises, stress_xx, strain_xy, "
                     "displacement_x, ...)", name);
    return PERI_ERR_INPUT;
  }
  if (mean || max) {
    p->kind = P_MEAN;
    p->axis = axis_of(at[1]);
    char *end = NULL;
    if (p->axis < 0 || at[2] != '=' || (p->point[0] = strtod(at + 3, &end), end == at + 3 || *end)) {
      snprintf(why, n, "quantity '%s': expected mean:FIELD@x=VALUE or max:FIELD@x=VALUE (or y=, z=)", name);
      return PERI_ERR_INPUT;
    }
    return PERI_OK;
  }
  p->kind = P_POINT;
  const char *c = at + 1;
  while (p->n_coords < 3) {
    char *end = NULL;
    p->point[p->n_coords] = strtod(c, &end);
    if (end == c) break;
    p->n_coords++;
    if (*end != ',') {
      c = end;
      break;
    }
    c = end + 1;
  }
  if (p->n_coords < 1 || *c) {
    snprintf(why, n, "quantity '%s': expected FIELD@X,Y[,Z] with numbers", name);
    return PERI_ERR_INPUT;
  }
  return PERI_OK;
}

int peri_probe_check(const char *name, char *why, size_t n) {
  probe p;
  return parse(name, &p, why, n);
}

static double field_value(const peri_sim *s, const probe *p, const double *sigma, const double *eps, int32_t i) {
  switch (p->field) {
  case F_VM: return peri_von_mises(s, &sigma[9 * (size_t)i], s->mat.materials[s->disc.p.material[i]].nu);
  case F_STRESS: return sigma[9 * (size_t)i + 3 * p->a + p->b];
  case F_STRAIN: return eps[9 * (size_t)i + 3 * p->a + p->b];
  default: return s->disc.p.u[3 * (size_t)i + p->a];
  }
}

int peri_probe(peri_sim *s, const char *name, double *value) {
  probe p;
  char why[512];
  if (parse(name, &p, why, sizeof why) != PERI_OK) {
    peri_error("%s", why);
    return PERI_ERR_RUN;
  }
  const peri_particles *pt = &s->disc.p;
  const int32_t n = pt->n_owned;
  if (p.kind == P_NODES) return *value = n, PERI_OK;
  if (p.kind == P_REACTION) {
    for (int r = 0; r < s->cond.n_regions; ++r)
      if (!strcmp(s->cond.regions[r].name, p.region)) {
        double out[3];
        peri_region_reaction(s, r, out);
        return *value = out[p.a], PERI_OK;
      }
    peri_error("quantity 'reaction_%s_%c': the deck has no region '%s'", p.region, "xyz"[p.a], p.region);
    return PERI_ERR_RUN;
  }
  if (p.kind == P_PHASE) {
    int m = 0;
    while (m < s->mat.n_materials && strcmp(s->mat.materials[m].name, p.region)) ++m;
    if (m == s->mat.n_materials) {
      peri_error("quantity '%s': the deck has no material '%s'", name, p.region);
      return PERI_ERR_RUN;
    }
    peri_phase_stress *phases = peri_malloc(sizeof *phases * (size_t)s->mat.n_materials);
    const int rc = peri_phase_stresses_now(s, phases);
    *value = p.phase_mean ? phases[m].mean_stress : phases[m].max_von_mises > -INFINITY ? phases[m].max_von_mises : NAN;
    free(phases);
    return rc;
  }
  if (p.kind == P_ITERATIONS) return *value = (double)s->solver.qs.iterations, PERI_OK;
  if (p.kind == P_ENERGY) return *value = peri_strain_energy(s), PERI_OK;
  if (p.kind == P_MAX_U) {
    double m = 0.0;
    for (int32_t i = 0; i < n; ++i)
      if (!(pt->flags[i] & PERI_NODE_FICTITIOUS)) /* layers are out of the maxima (docs/deck.md section 10) */
        m = fmax(m, sqrt(pt->u[3 * i] * pt->u[3 * i] + pt->u[3 * i + 1] * pt->u[3 * i + 1] +
                                                     pt->u[3 * i + 2] * pt->u[3 * i + 2]));
    return *value = m, PERI_OK;
  }
  /* the nodes the probe reads: the nearest body node to a point, the column nearest to a
   * plane; only their stress is evaluated (a maximum reads every node) */
  uint8_t *wanted = p.kind == P_MAX_VM ? NULL : peri_calloc((size_t)(n > 0 ? n : 1), 1);
  int32_t best = -1;
  double column = INFINITY;
  const double tol = 1e-9 * s->disc.geom.spacing;
  if (p.kind == P_POINT) {
    double best_d = INFINITY;
    for (int32_t i = 0; i < n; ++i) {
      if (pt->flags[i] & PERI_NODE_FICTITIOUS) continue; /* the nearest body node */
      double d2 = 0.0;
      for (int c = 0; c < p.n_coords; ++c) d2 += (pt->x[3 * i + c] - p.point[c]) * (pt->x[3 * i + c] - p.point[c]);
      if (d2 < best_d) best_d = d2, best = i; /* first of equals: deterministic */
    }
    if (best >= 0) wanted[best] = 1;
  } else if (p.kind != P_MAX_VM) { /* mean over the column nearest to the plane */
    double nearest = INFINITY;
    for (int32_t i = 0; i < n; ++i) nearest = fmin(nearest, fabs(pt->x[3 * i + p.axis] - p.point[0]));
    for (int32_t i = 0; i < n; ++i) /* the lower of two equidistant columns */
      if (fabs(pt->x[3 * i + p.axis] - p.point[0]) <= nearest + tol) column = fmin(column, pt->x[3 * i + p.axis]);
    for (int32_t i = 0; i < n; ++i) wanted[i] = fabs(pt->x[3 * i + p.axis] - column) <= tol;
  }
  double *sigma = peri_malloc(sizeof(double) * 9 * (size_t)n);
  double *eps = NULL;
  int rc = peri_stress_of(s, sigma, wanted);
  if (rc == PERI_OK && p.field == F_STRAIN) {
    eps = peri_malloc(sizeof(double) * 9 * (size_t)n);
    peri_strain(s, eps);
  }
  if (rc == PERI_OK) {
    if (p.kind == P_MAX_VM) {
      double m = 0.0;
      for (int32_t i = 0; i < n; ++i)
        if (!(pt->flags[i] & PERI_NODE_FICTITIOUS)) m = fmax(m, peri_von_mises(s, &sigma[9 * (size_t)i], s->mat.materials[pt->material[i]].nu));
      *value = m;
    } else if (p.kind == P_POINT) {
      *value = best >= 0 ? field_value(s, &p, sigma, eps, best) : NAN;
    } else {
      double sum = 0.0, largest = -INFINITY;
      long count = 0;
      for (int32_t i = 0; i < n; ++i)
        if (wanted[i]) {
          const double v = field_value(s, &p, sigma, eps, i);
          sum += v;
          largest = fmax(largest, v);
          ++count;
        }
      *value = count ? (p.column_max ? largest : sum / count) : NAN;
    }
  }
  free(wanted);
  free(sigma);
  free(eps);
  return rc;
}
