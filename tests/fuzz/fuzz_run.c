/* libFuzzer target: a deck that the set-up accepts, run for a few steps. The input goes through
 * the C API as `peri run` takes a deck (peri_api_open_string, the output in a directory of its
 * own without frames or pictures, peri_api_step): the models' force loops, breaking, contact,
 * plasticity, the tools, boundary conditions and the history rows of explicit dynamics on
 * whatever odd but valid deck the mutations make; quasi-static decks with their solves bounded
 * (one load step, 20 iterations, a tolerance of 1e-4, 1 re-solve, no cut-back: a valid solve
 * may otherwise take long, a timeout and not a bug). Heat-only decks stop after the set-up
 * (they run whole), and grids larger than the seeds' are skipped. */
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include "peri/api.h"
#include "deck_size.h"
#include "quiet.h"

/* Largest grid and bond count an input may ask for (the seeds have at most 1000 nodes), and
 * the steps of each run. */
enum { MAX_NODES = 2000, STEPS = 4, LOAD_STEPS = 1 };
static const double MAX_BONDS = 5.0e5; /* (deck_size.h's bound: about 3 times the bonds in 3D) */

static char output_dir[256], deck_name[1100];

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  silence_library();
  fuzz_temp_path(output_dir, sizeof output_dir, "peri-fuzz-run-XXXXXX");
  if (!mkdtemp(output_dir)) abort();
  /* the name the messages give the deck, and the folder of its relative paths: the examples'
   * (their images; nothing is written there, the output goes to output_dir) */
  const char *examples = getenv("PERI_FUZZ_EXAMPLES");
  snprintf(deck_name, sizeof deck_name, "%s/fuzz.yaml", examples ? examples : PERI_FUZZ_EXAMPLES);
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char *text = deck_text_within(data, size, MAX_NODES, MAX_BONDS);
  if (!text) return -1; /* not added to the corpus */
  /* a quasi-static deck is opened again with its solves bounded: few iterations, re-solves and
   * cut-backs (a solve that does not converge in them ends the run with its message) */
  static const char *const sets[] = {"output.frames=0",          "output.picture=false",
                                     "solver.max_iterations=20", "solver.max_fracture_iterations=1",
                                     "solver.max_cutbacks=0", "solver.tolerance=1e-4"};
  peri_api *run = NULL;
  bool quasi_static = false;
  if (peri_api_open_string(text, deck_name, 2, sets, &run) == PERI_API_OK && peri_api_is_quasi_static(run)) {
    peri_api_close(run);
    run = NULL;
    peri_api_open_string(text, deck_name, 6, sets, &run);
    quasi_static = true;
  }
  if (run && peri_api_set_output(run, output_dir) == PERI_API_OK)
    peri_api_step(run, quasi_static ? LOAD_STEPS : STEPS); /* (a heat-only deck refuses: it runs whole) */
  if (run) peri_api_close(run);
  free(text);
  return 0;
}
