/* The peri command: thin wrapper around the library. */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/run.h"
#include "peri/sim.h"

static void usage(FILE *out) {
  fprintf(out,
          "usage: peri run DECK [--threads N] [--quiet] [--output DIR]\n"
          "       peri check DECK\n"
          "       peri --help | --version\n"
          "\n"
          "  run     reads the YAML deck, builds the particles and bonds, runs the solver and\n"
          "          writes VTU frames (.pvd series), history.csv and a PNG picture (2D)\n"
          "  check   validates the deck, builds the discretization, prints the summary and\n"
          "          the memory estimate, and runs nothing\n"
          "\n"
          "  --threads N   OpenMP threads (default: OMP_NUM_THREADS or all cores)\n"
          "  --quiet       no summary and no progress line\n"
          "  --output DIR  write output into DIR (overrides output.directory)\n"
          "\n"
          "exit status: 0 success, 1 failure during the run, 2 bad input\n"
          "deck reference: docs/deck.md\n");
}

int main(int argc, char **argv) {
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
  if (strcmp(command, "run") && strcmp(command, "check")) {
    peri_error("unknown command '%s' (commands: run, check; see peri --help)", command);
    return PERI_ERR_INPUT;
  }
  const char *deck = NULL, *output = NULL;
  bool quiet = false;
  long threads = 0;
  for (int k = 2; k < argc; ++k) {
    const char *a = argv[k];
    if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      usage(stdout);
      return 0;
    }
    if (!strcmp(a, "--quiet") || !strcmp(a, "-q")) quiet = true;
    else if (!strcmp(a, "--threads") || !strcmp(a, "--output")) {
      if (k + 1 >= argc) {
        peri_error("option %s needs a value", a);
        return PERI_ERR_INPUT;
      }
      const char *value = argv[++k];
      if (!strcmp(a, "--output")) {
        if (!*value) {
          peri_error("option --output: expected a directory, got an empty path");
          return PERI_ERR_INPUT;
        }
        output = value;
      }
      else {
        char *end = NULL;
        threads = strtol(value, &end, 10);
        if (*end || threads < 1 || threads > 4096) {
          peri_error("option --threads: expected an integer from 1 to 4096, got '%s'", value);
          return PERI_ERR_INPUT;
        }
      }
    } else if (a[0] == '-') {
      peri_error("unknown option '%s' (see peri --help)", a);
      return PERI_ERR_INPUT;
    } else if (!deck) deck = a;
    else {
      peri_error("unexpected argument '%s' (one deck per run)", a);
      return PERI_ERR_INPUT;
    }
  }
  if (!deck) {
    peri_error("%s: no deck given (usage: peri %s DECK)", command, command);
    return PERI_ERR_INPUT;
  }
  if (threads > 0) omp_set_num_threads((int)threads);
  peri_sim sim;
  int rc = peri_sim_from_deck(&sim, deck);
  if (rc != PERI_OK) {
    peri_sim_free(&sim);
    return rc;
  }
  sim.quiet = quiet;
  if (output) {
    free(sim.out.directory);
    sim.out.directory = strdup(output);
  }
  if (!quiet || !strcmp(command, "check")) peri_print_summary(&sim, stdout);
  if (!strcmp(command, "run")) {
    fflush(stdout);
    rc = peri_run(&sim);
  }
  peri_sim_free(&sim);
  return rc;
}
