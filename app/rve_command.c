/* peri rve KEY=VALUE ...: Monte-Carlo homogenization of a nanocomposite RVE
 * (docs/microstructures.md section 7). */
#include "rve_command.h"
#include <errno.h>
#include <inttypes.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/output.h"
#include "peri/plot.h"
#include "peri/rve.h"

typedef struct key {
  const char *name;
  double *value; /* or NULL for the integer keys below */
} key;

static int parse_double(const char *name, const char *text, double *out) {
  char *end = NULL;
  errno = 0;
  const double v = strtod(text, &end);
  if (end == text || *end || errno) {
    peri_error("rve: %s: expected a number, got '%s'", name, text);
    return -1;
  }
  *out = v;
  return 0;
}

static int parse_long(const char *name, const char *text, long lo, long hi, long *out) {
  char *end = NULL;
  errno = 0;
  const long v = strtol(text, &end, 10);
  if (end == text || *end || errno || v < lo || v > hi) {
    peri_error("rve: %s: expected an integer from %ld to %ld, got '%s'", name, lo, hi, text);
    return -1;
  }
  *out = v;
  return 0;
}

/* A picture of realization 0 (seed 002 Fig. 3.12): filler nodes 1, matrix nodes 0, the
 * platelets' outlines drawn as phase boundaries. */
static int write_picture(const peri_rve_params *p, const char *path) {
  peri_rve_geometry g = {0};
  if (peri_rve_generate(p, 0, &g)) return -1;
  const int32_t count = g.n * g.n;
  double *x = malloc(3 * (size_t)count * sizeof *x), *value = malloc((size_t)count * sizeof *value);
  int32_t *phase = malloc((size_t)count * sizeof *phase);
  int rc = -1;
  if (x && value && phase) {
    for (int32_t k = 0; k < count; ++k) {
      x[3 * k] = ((k % g.n) + 0.5) * p->spacing, x[3 * k + 1] = ((k / g.n) + 0.5) * p->spacing, x[3 * k + 2] = 0;
      phase[k] = g.platelet[k] >= 0;
      value[k] = phase[k];
    }
    char title[160];
    snprintf(title, sizeof title, "RVE realization 0: %d platelets, filler nodes %.2f%%", g.platelets,
             100.0 * (double)g.filler_nodes / count);
    const peri_png_axes axes = {"x [m]", "y [m]", "filler (1) or matrix (0)", phase, x};
    rc = peri_png_write_field_axes(path, count, x, value, 0, 1, p->spacing, 900, title, &axes) ? -1 : 0;
  } else {
    peri_error("rve: out of memory");
  }
  free(x), free(value), free(phase);
  peri_rve_geometry_free(&g);
  return rc;
}

/* The running mean of the tensile modulus (E11 + E22)/2 against the number of realizations
 * (seed 002 Fig. 3.14). */
static int write_convergence(const peri_rve_moduli *each, long count, const char *path) {
  double *n = malloc((size_t)count * sizeof *n), *mean = malloc((size_t)count * sizeof *mean);
  int rc = -1;
  if (n && mean) {
    double sum = 0;
    for (long k = 0; k < count; ++k) {
      sum += 0.5 * (each[k].E11 + each[k].E22) * 1e-9;
      n[k] = (double)(k + 1), mean[k] = sum / (double)(k + 1);
    }
    rc = peri_plot_write(path, n, mean, (size_t)count, "realizations", "mean tensile modulus (E11 + E22)/2 [GPa]",
                         "Running mean of the homogenized modulus", 900, 600) ? -1 : 0;
  } else {
    peri_error("rve: out of memory");
  }
  free(n), free(mean);
  return rc;
}

int peri_rve_command(int argc, char **argv) {
  peri_rve_params p = peri_rve_params_default();
  long realizations = 10, m = p.m, seed = (long)p.seed, threads = 0;
  const char *csv = NULL, *picture = NULL, *convergence = NULL;
  const key keys[] = {{"side", &p.side},
                      {"spacing", &p.spacing},
                      {"E_matrix", &p.E_matrix},
                      {"E_filler", &p.E_filler},
                      {"rho_matrix", &p.rho_matrix},
                      {"rho_filler", &p.rho_filler},
                      {"weight_fraction", &p.weight_fraction},
                      {"kappa", &p.kappa},
                      {"aspect_mean", &p.aspect_mean},
                      {"aspect_std", &p.aspect_std},
                      {"thickness", &p.thickness},
                      {"max_turn", &p.max_turn},
                      {"strain", &p.strain}};
  for (int a = 0; a < argc; ++a) {
    if (!strcmp(argv[a], "--threads") && a + 1 < argc) {
      if (parse_long("--threads", argv[++a], 1, 4096, &threads)) return 2;
      continue;
    }
    const char *eq = strchr(argv[a], '=');
    if (!eq) {
      peri_error("rve: expected KEY=VALUE, got '%s' (see docs/microstructures.md section 7)", argv[a]);
      return 2;
    }
    const size_t len = (size_t)(eq - argv[a]);
    const char *val = eq + 1;
    int found = 0, bad = 0;
    for (size_t k = 0; k < sizeof keys / sizeof keys[0]; ++k)
      if (strlen(keys[k].name) == len && !strncmp(argv[a], keys[k].name, len)) {
        found = 1, bad = parse_double(keys[k].name, val, keys[k].value);
      }
    if (!found && len == 1 && argv[a][0] == 'm') found = 1, bad = parse_long("m", val, 1, 32, &m);
    if (!found && len == 12 && !strncmp(argv[a], "realizations", 12))
      found = 1, bad = parse_long("realizations", val, 1, 1000000, &realizations);
    if (!found && len == 4 && !strncmp(argv[a], "seed", 4))
      found = 1, bad = parse_long("seed", val, 0, 2147483647L, &seed);
    if (!found && len == 3 && !strncmp(argv[a], "csv", 3)) found = 1, csv = val;
    if (!found && len == 7 && !strncmp(argv[a], "picture", 7)) found = 1, picture = val;
    if (!found && len == 11 && !strncmp(argv[a], "convergence", 11)) found = 1, convergence = val;
    if (!found) {
      peri_error("rve: unknown key '%.*s' (keys: side, spacing, m, E_matrix, E_filler, rho_matrix, "
                 "rho_filler, weight_fraction, kappa, aspect_mean, aspect_std, thickness, max_turn, "
                 "strain, realizations, seed, csv, picture, convergence)",
                 (int)len, argv[a]);
      return 2;
    }
    if (bad) return 2;
  }
  p.m = (int)m, p.seed = (uint64_t)seed;
  if (peri_rve_params_check(&p)) return 2;
  FILE *out = NULL;
  if (csv && !(out = fopen(csv, "w"))) {
    peri_error("rve: cannot write %s: %s", csv, strerror(errno));
    return 2;
  }
  if (threads > 0) omp_set_num_threads((int)threads);
  if (picture && write_picture(&p, picture)) {
    if (out) fclose(out);
    return 1;
  }
  const int n = (int)(p.side / p.spacing + 0.5);
  const double vol = peri_rve_volume_fraction(p.weight_fraction, p.rho_filler, p.rho_matrix);
  printf("rve: side %g m, %d x %d nodes, m = %d, filler volume fraction %.5f (eq. 3.2), kappa %g,\n"
         "     %ld realizations from seed %ld on %d threads\n",
         p.side, n, n, p.m, vol, p.kappa, realizations, seed, omp_get_max_threads());
  fflush(stdout);
  peri_rve_moduli *each = calloc((size_t)realizations, sizeof *each);
  double *v = malloc((size_t)realizations * sizeof(double));
  if (!each || !v || peri_rve_monte_carlo(&p, (int)realizations, each)) {
    if (!each || !v) peri_error("rve: out of memory");
    free(each), free(v);
    if (out) fclose(out);
    return 1;
  }
  const char *names[] = {"E11", "E22", "nu12", "nu21", "platelets", "filler_fraction"};
  for (int q = 0; q < 6; ++q) {
    for (long k = 0; k < realizations; ++k) {
      const peri_rve_moduli *r = &each[k];
      const double vals[] = {r->E11, r->E22, r->nu12, r->nu21, r->platelets, r->filler_fraction};
      v[k] = vals[q];
    }
    double mean, std;
    peri_rve_mean_std(v, (int)realizations, &mean, &std);
    const double scale = q < 2 ? 1e-9 : 1.0;
    printf("%-16s %.6g +- %.3g%s\n", names[q], mean * scale, std * scale, q < 2 ? " GPa" : "");
  }
  int rc = 0;
  if (convergence && write_convergence(each, realizations, convergence)) rc = 1;
  if (out) {
    fprintf(out, "realization,platelets,filler_fraction,E11,E22,nu12,nu21,iterations\n");
    for (long k = 0; k < realizations; ++k) {
      const peri_rve_moduli *r = &each[k];
      fprintf(out, "%ld,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n", k, r->platelets, r->filler_fraction, r->E11,
              r->E22, r->nu12, r->nu21, r->iterations);
    }
    fclose(out);
  }
  free(each), free(v);
  return rc;
}
