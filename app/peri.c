/* The peri command: thin wrapper around the library. */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "peri/clock.h"
#include "peri/comm.h"
#include "peri/energies.h"
#include "peri/error.h"
#include "peri/film_quantities.h"
#include "peri/film_series.h"
#include "peri/history_log.h"
#include "peri/implicit.h"
#include "peri/probe.h"
#include "peri/quasistatic.h"
#include "peri/run.h"
#include "peri/setup.h"
#include "peri/sim.h"
#include "peri/gpu.h"
#include "omp_wait.h"
#include "rve_command.h"

static void usage(FILE *out) {
  fprintf(out,
          "usage: peri run DECK [--threads N] [--quiet] [--progress[=SECONDS]] [--output DIR]\n"
          "                [--set KEY=VALUE ...] [--restart FILE] [--device cpu|gpu]\n"
          "       peri check DECK [--set KEY=VALUE ...]\n"
          "       peri sweep DECK --set-list KEY=V1,V2,... [--set-list ...] --quantity NAME [...]\n"
          "                  [--set KEY=VALUE ...] [--threads N]\n"
          "       peri rve [KEY=VALUE ...] [--threads N]\n"
          "       peri --help | --version\n"
          "\n"
          "  run     reads the YAML deck, builds the particles and bonds, runs the solver and\n"
          "          writes VTU frames (.pvd series), history.csv and a PNG picture (2D)\n"
          "  check   validates the deck, builds the discretization, prints the summary and\n"
          "          the memory estimate, and runs nothing\n"
          "  sweep   runs the deck once per value of the --set-list keys (several lists are\n"
          "          taken in step: the k-th run uses the k-th value of each) without writing\n"
          "          output, and prints a Markdown table of the quantities\n"
          "  rve     Monte-Carlo homogenization of a nanocomposite RVE: E11, E22, nu12, nu21,\n"
          "          mean +- standard deviation (keys: docs/microstructures.md section 7)\n"
          "\n"
          "  --threads N         OpenMP threads (default: OMP_NUM_THREADS or all cores)\n"
          "  --quiet             no summary and no progress\n"
          "  --progress[=S]      a progress line every S seconds (default 10) to stderr, also on a\n"
          "                      terminal (which otherwise gets a live line); without the option a\n"
          "                      run whose stderr is not a terminal gets them every 10 s;\n"
          "                      --progress=0: none (the summary stays)\n"
          "  --output DIR        write output into DIR (overrides output.directory)\n"
          "  --restart FILE      continue the run from the checkpoint FILE (output.checkpoint_every;\n"
          "                      docs/restart.md): same deck, history.csv and the .pvd continue\n"
          "  --device cpu|gpu    where the explicit steps run (default cpu); gpu needs a build with\n"
          "                      CUDA and a GPU (docs/gpu.md); a deck the GPU path does not take\n"
          "                      runs on the CPU with a warning saying why\n"
          "  --petsc-options STR PETSc options for solver type implicit, after the deck's\n"
          "                      solver.petsc_options, e.g. \"-snes_monitor -ksp_monitor\"\n"
          "  --set KEY=VALUE     override a deck value before it is read, e.g.\n"
          "                      --set discretization.horizon=1e-3 (repeatable; KEY is a dotted\n"
          "                      path, list items by 0-based index; VALUE is YAML)\n"
          "  --set-list KEY=V1,V2,...  sweep values of one key (commas inside [ ], { } or ( ) do not split)\n"
          "  --quantity NAME     what a sweep tabulates (repeatable): max_von_mises,\n"
          "                      max_displacement, strain_energy, nodes, iterations,\n"
          "                      reaction_REGION_x (total reaction on a region, also _y, _z),\n"
          "                      FIELD@X,Y[,Z] (at the nearest node), mean:FIELD@x=X (mean over\n"
          "                      the grid column nearest to x = X), max:FIELD@x=X (its largest\n"
          "                      value); FIELD is von_mises,\n"
          "                      stress_xx, stress_xy, ..., strain_xx, ..., displacement_x, ...\n"
          "                      films (output.wrinkles, quasi-static): wrinkling_onset,\n"
          "                      delamination_onset (pseudo-time, nan: none),\n"
          "                      wrinkle_wavelength_at_onset, film_regime (0 neither, 1 wrinkling\n"
          "                      only, 2 wrinkling then delamination, 3 delamination first)\n"
          "\n"
          "mpirun -np N peri run DECK   runs an explicit or heat deck on N MPI ranks (%s;\n"
          "                             docs/parallel.md)\n"
          "\n"
          "exit status: 0 success, 1 failure during the run, 2 bad input\n"
          "deck reference: docs/deck.md; solvers and sweeps: docs/solvers.md\n",
#ifdef PERI_HAVE_MPI
          "this build has MPI"
#else
          "this build has no MPI: install libopenmpi-dev and rebuild"
#endif
  );
}

/* A sweep's film quantities (docs/thin_films.md section 8): the onsets that `peri run` writes
 * to wrinkling.csv, found in the film's rows that the sweep records after every load step. */
static const char *const film_quantities[] = {"wrinkling_onset", "delamination_onset", "wrinkle_wavelength_at_onset",
                                              "film_regime", NULL};

static int film_quantity(const char *name) {
  for (int q = 0; film_quantities[q]; ++q)
    if (!strcmp(name, film_quantities[q])) return q;
  return -1;
}

/* The film's row of a load step: its strain energy, wrinkles and broken interface bonds. */
static int record_film_row(peri_sim *s, void *ctx) {
  if (s->solver.qs.phase == PERI_QS_PHASE_DYNAMIC) return 0; /* rows of the load steps only */
  peri_strain_energy(s); /* the densities the film's energy sums */
  double amplitude = 0.0, wavelength = 0.0;
  peri_wrinkle_profile(s, s->out.wrinkle_region, &amplitude, &wavelength);
  peri_film_series_add(ctx, s, amplitude, wavelength);
  return 0;
}

/* Runs the solver of a built simulation without output; with `film`, records the film's
 * rows (the initial state and every load step) as `peri run` does for output.wrinkles. */
static int solve_quietly(peri_sim *s, peri_film_series *film) {
  peri_apply_initial_conditions(s);
  peri_apply_loads(s, s->state.time);
  s->mat.model->force(s);
  if (peri_is_quasi_static(s) && film) {
    record_film_row(s, film);
    return peri_solve_quasi_static(s, record_film_row, film);
  }
  if (peri_is_quasi_static(s)) return peri_solve_quasi_static(s, NULL, NULL);
  if (s->solver.kind == PERI_SOLVER_EXPLICIT) return peri_solve_explicit(s, NULL, NULL);
  peri_error("sweep: solver type heat is not supported (use explicit or a quasi-static solver)");
  return PERI_ERR_INPUT;
}

typedef struct sweep_list {
  char key[512];
  int count;
  char **values;
} sweep_list;

static int split_list(const char *arg, sweep_list *l) {
  const char *eq = strchr(arg, '=');
  if (!eq || eq == arg || !eq[1] || (size_t)(eq - arg) >= sizeof l->key) {
    peri_error("option --set-list: expected KEY=V1,V2,..., got '%s'", arg);
    return PERI_ERR_INPUT;
  }
  memcpy(l->key, arg, (size_t)(eq - arg));
  l->key[eq - arg] = '\0';
  l->count = 0;
  l->values = NULL;
  const char *p = eq + 1;
  for (;;) {
    const char *comma = NULL; /* the next comma outside brackets: values may be lists */
    for (int depth = 0, i = 0; p[i]; ++i) {
      if (p[i] == '[' || p[i] == '{' || p[i] == '(') ++depth; /* ( ): expressions' arguments */
      else if (p[i] == ']' || p[i] == '}' || p[i] == ')') --depth;
      else if (p[i] == ',' && depth == 0) {
        comma = p + i;
        break;
      }
    }
    size_t len = comma ? (size_t)(comma - p) : strlen(p);
    if (len == 0) {
      peri_error("option --set-list %s: empty value in '%s'", l->key, eq + 1);
      return PERI_ERR_INPUT;
    }
    l->values = realloc(l->values, sizeof(char *) * (size_t)(l->count + 1));
    l->values[l->count] = malloc(len + 1);
    memcpy(l->values[l->count], p, len);
    l->values[l->count][len] = '\0';
    l->count++;
    if (!comma) break;
    p = comma + 1;
  }
  return PERI_OK;
}

static int sweep(const char *deck, int n_sets, const char **sets, int n_lists, sweep_list *lists, int n_q,
                 const char **quantities) {
  if (n_lists == 0 || n_q == 0) {
    peri_error("sweep: give at least one --set-list and one --quantity (see peri --help)");
    return PERI_ERR_INPUT;
  }
  for (int l = 1; l < n_lists; ++l)
    if (lists[l].count != lists[0].count) {
      peri_error("sweep: the --set-list options must have the same number of values (%s has %d, %s has %d)",
                 lists[0].key, lists[0].count, lists[l].key, lists[l].count);
      return PERI_ERR_INPUT;
    }
  bool film = false;
  for (int q = 0; q < n_q; ++q) {
    char why[512];
    if (film_quantity(quantities[q]) >= 0) {
      film = true;
      continue;
    }
    if (peri_probe_check(quantities[q], why, sizeof why) != PERI_OK) {
      peri_error("option --quantity: %s", why);
      return PERI_ERR_INPUT;
    }
  }
  /* check every case before running any */
  const int n_all = n_sets + n_lists;
  const char **all = malloc(sizeof(char *) * (size_t)(n_all > 0 ? n_all : 1));
  char **owned = calloc((size_t)n_lists, sizeof(char *));
  for (int k = 0; k < n_sets; ++k) all[k] = sets[k];
  int rc = PERI_OK;
  for (int pass = 0; pass < 2 && rc == PERI_OK; ++pass) {
    if (pass == 1) {
      printf("|");
      for (int l = 0; l < n_lists; ++l) printf(" %s |", lists[l].key);
      for (int q = 0; q < n_q; ++q) printf(" %s |", quantities[q]);
      printf(" seconds |\n|");
      for (int c = 0; c < n_lists + n_q + 1; ++c) printf("---|");
      printf("\n");
      fflush(stdout);
    }
    for (int v = 0; v < lists[0].count && rc == PERI_OK; ++v) {
      for (int l = 0; l < n_lists; ++l) {
        size_t size = strlen(lists[l].key) + strlen(lists[l].values[v]) + 2;
        free(owned[l]);
        owned[l] = malloc(size);
        snprintf(owned[l], size, "%s=%s", lists[l].key, lists[l].values[v]);
        all[n_sets + l] = owned[l];
      }
      peri_sim s;
      double t0 = peri_seconds();
      rc = peri_sim_from_deck_with(&s, deck, n_all, all);
      if (rc == PERI_OK && film && (s.out.wrinkle_region <= 0 || !peri_is_quasi_static(&s))) {
        peri_error("sweep: the quantities %s and %s need a quasi-static solver and output.wrinkles (the film "
                   "region, docs/thin_films.md)", film_quantities[0], film_quantities[3]);
        rc = PERI_ERR_INPUT;
      }
      if (rc == PERI_OK && pass == 1) {
        s.out.quiet = true;
        peri_film_series rows = {0};
        rc = solve_quietly(&s, film ? &rows : NULL);
        double t1 = peri_seconds();
        double onsets[4];
        peri_film_series_onsets(&rows, onsets);
        peri_film_series_free(&rows);
        printf("|");
        for (int l = 0; l < n_lists; ++l) printf(" %s |", lists[l].values[v]);
        for (int q = 0; q < n_q && rc == PERI_OK; ++q) {
          double value = 0.0;
          const int f = film_quantity(quantities[q]);
          if (f >= 0) value = onsets[f];
          else rc = peri_probe(&s, quantities[q], &value);
          printf(" %.6g |", value);
        }
        printf(" %.2f |\n", t1 - t0);
        fflush(stdout);
      }
      peri_sim_free(&s);
    }
  }
  for (int l = 0; l < n_lists; ++l) free(owned[l]);
  free(owned);
  free(all);
  return rc;
}

static int command(int argc, char **argv) {
  if (argc < 2) {
    usage(stderr);
    return PERI_ERR_INPUT;
  }
  if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
    usage(stdout);
    return 0;
  }
  if (!strcmp(argv[1], "--version")) {
    printf("peri %s\n", PERI_VERSION);
    return 0;
  }
  const char *command = argv[1];
  if (!strcmp(command, "rve")) return peri_rve_command(argc - 2, argv + 2);
  if (strcmp(command, "run") && strcmp(command, "check") && strcmp(command, "sweep")) {
    peri_error("unknown command '%s' (commands: run, check, sweep, rve; see peri --help)", command);
    return PERI_ERR_INPUT;
  }
  const bool is_sweep = !strcmp(command, "sweep");
  const char *deck = NULL, *output = NULL;
  const char *restart = NULL; /* --restart FILE (docs/restart.md) */
  bool quiet = false;
  double progress_every = -1.0; /* --progress[=SECONDS]: < 0 not given */
  long threads = 0;
  int device = PERI_DEVICE_CPU;
  char device_name[160] = "";
  const char **sets = calloc((size_t)argc, sizeof(char *));
  const char **quantities = calloc((size_t)argc, sizeof(char *));
  sweep_list *lists = calloc((size_t)argc, sizeof(sweep_list));
  int n_sets = 0, n_q = 0, n_lists = 0, rc = PERI_OK;
  for (int k = 2; k < argc && rc == PERI_OK; ++k) {
    const char *a = argv[k];
    if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      usage(stdout);
      return 0;
    }
    if (!strcmp(a, "--quiet") || !strcmp(a, "-q")) quiet = true;
    else if (!strcmp(a, "--progress")) progress_every = 10.0;
    else if (!strncmp(a, "--progress=", 11)) {
      char *end = NULL;
      progress_every = strtod(a + 11, &end);
      if (end == a + 11 || *end || !(progress_every >= 0.0) || progress_every > 1e9) {
        peri_error("option --progress: expected seconds between lines (a number >= 0), got '%s'", a + 11);
        rc = PERI_ERR_INPUT;
      }
    } else if (!strcmp(a, "--threads") || !strcmp(a, "--output") || !strcmp(a, "--set") ||
             !strcmp(a, "--set-list") || !strcmp(a, "--quantity") || !strcmp(a, "--restart") ||
             !strcmp(a, "--petsc-options") || !strcmp(a, "--device")) {
      if (k + 1 >= argc) {
        peri_error("option %s needs a value", a);
        rc = PERI_ERR_INPUT;
        break;
      }
      const char *value = argv[++k];
      if ((!strcmp(a, "--set-list") || !strcmp(a, "--quantity")) && !is_sweep) {
        peri_error("option %s: only for peri sweep", a);
        rc = PERI_ERR_INPUT;
      } else if (!strcmp(a, "--set")) {
        sets[n_sets++] = value;
      } else if (!strcmp(a, "--set-list")) {
        rc = split_list(value, &lists[n_lists]);
        if (rc == PERI_OK) n_lists++;
      } else if (!strcmp(a, "--quantity")) {
        quantities[n_q++] = value;
      } else if (!strcmp(a, "--petsc-options")) {
        peri_implicit_set_command_line_options(value);
      } else if (!strcmp(a, "--device")) {
        if (is_sweep || !strcmp(value, "cpu")) {
          if (is_sweep) {
            peri_error("option --device: only for peri run and peri check");
            rc = PERI_ERR_INPUT;
          }
        } else if (strcmp(value, "gpu") != 0) {
          peri_error("option --device: expected cpu or gpu, got '%s'", value);
          rc = PERI_ERR_INPUT;
        } else if (!peri_gpu_device(device_name, sizeof device_name)) {
          peri_error("option --device gpu: %s", device_name);
          rc = PERI_ERR_INPUT;
        } else {
          device = PERI_DEVICE_GPU;
        }
      } else if (!strcmp(a, "--restart")) {
        if (strcmp(command, "run") != 0) {
          peri_error("option --restart: only for peri run");
          rc = PERI_ERR_INPUT;
        }
        restart = value;
      } else if (!strcmp(a, "--output")) {
        if (!*value) {
          peri_error("option --output: expected a directory, got an empty path");
          rc = PERI_ERR_INPUT;
        }
        output = value;
      } else {
        char *end = NULL;
        threads = strtol(value, &end, 10);
        if (*end || threads < 1 || threads > 4096) {
          peri_error("option --threads: expected an integer from 1 to 4096, got '%s'", value);
          rc = PERI_ERR_INPUT;
        }
      }
    } else if (a[0] == '-') {
      peri_error("unknown option '%s' (see peri --help)", a);
      rc = PERI_ERR_INPUT;
    } else if (!deck) deck = a;
    else {
      peri_error("unexpected argument '%s' (one deck per run)", a);
      rc = PERI_ERR_INPUT;
    }
  }
  if (rc == PERI_OK && !deck) {
    peri_error("%s: no deck given (usage: peri %s DECK)", command, command);
    rc = PERI_ERR_INPUT;
  }
  if (rc == PERI_OK && threads > 0) omp_set_num_threads((int)threads);
  if (rc == PERI_OK && is_sweep && peri_comm_size() > 1) {
    peri_error("sweep: runs in one process (without mpirun, or mpirun -np 1)");
    rc = PERI_ERR_INPUT;
  } else if (rc == PERI_OK && is_sweep) {
    rc = sweep(deck, n_sets, sets, n_lists, lists, n_q, quantities);
  } else if (rc == PERI_OK) {
    peri_sim sim;
    rc = peri_sim_from_deck_with(&sim, deck, n_sets, sets);
    if (rc == PERI_OK) {
      sim.out.quiet = quiet;
      if (progress_every >= 0.0) { /* --progress: lines even on a terminal; =0: none */
        sim.out.progress_every = progress_every;
        sim.out.progress_lines = progress_every > 0.0;
      }
      if (output) {
        free(sim.out.directory);
        sim.out.directory = strdup(output);
      }
      sim.par.omp_wait = peri_omp_wait_description();
      sim.par.device = device;
      snprintf(sim.par.device_name, sizeof sim.par.device_name, "%s", device_name);
      if (!strcmp(command, "check")) {
        peri_gpu_settle(&sim); /* (run does it in peri_run_prepare) */
        peri_print_summary(&sim, stdout);
        peri_print_threads(&sim, stdout);
      }
      /* the checkpoint, the MPI ranks, the summary and the decomposition (src/run/prepare.c) */
      if (!strcmp(command, "run")) rc = peri_run_prepare(&sim, restart);
      if (rc == PERI_OK && !strcmp(command, "run")) rc = peri_run(&sim);
    }
    peri_sim_free(&sim);
  }
  for (int l = 0; l < n_lists; ++l) {
    for (int v = 0; v < lists[l].count; ++v) free(lists[l].values[v]);
    free(lists[l].values);
  }
  free(lists);
  free(sets);
  free(quantities);
  peri_implicit_finalize(); /* PETSc before MPI (a no-op when no implicit solve ran) */
  return rc;
}

int main(int argc, char **argv) {
  peri_choose_omp_wait(argv); /* a short OpenMP spin unless the user chose (docs/parallel.md) */
  peri_comm_init(&argc, &argv); /* MPI when built with it (docs/parallel.md) */
  int rc = command(argc, argv);
  fflush(stdout);
  peri_comm_finalize();
  return rc;
}
