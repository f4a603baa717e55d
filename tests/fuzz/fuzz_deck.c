/* libFuzzer target: the deck parser and the whole set-up that `peri check` runs
 * (peri_sim_from_deck, then peri_sim_free) on a deck file holding the fuzz input.
 *
 * Inputs whose grid would be large are skipped: a deck asking for a million nodes is a
 * valid deck, and building it only makes the run slow (a timeout, not a bug). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>
#include "peri/deck.h"
#include "peri/setup.h"
#include "peri/sim.h"
#include "deck_size.h"
#include "quiet.h"

/* Largest grid and bond count an input may ask for: the seeds have at most 1000 nodes. */
enum { MAX_NODES = 5000 };
static const double MAX_BONDS = 5.0e5;

static char deck_path[256];

/* Quiet library (errors go to stderr on every rejected deck) and one deck file reused for
 * every input. */
int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  silence_library();
  fuzz_temp_path(deck_path, sizeof deck_path, "peri-fuzz-deck-XXXXXX.yaml");
  int fd = mkstemps(deck_path, 5);
  if (fd < 0) abort();
  close(fd);
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char *text = deck_text_within(data, size, MAX_NODES, MAX_BONDS);
  if (!text) return -1; /* not added to the corpus */
  free(text);

  FILE *f = fopen(deck_path, "wb");
  if (!f) abort();
  if (size && fwrite(data, 1, size, f) != size) abort();
  fclose(f);

  peri_sim sim;
  peri_sim_from_deck(&sim, deck_path);
  peri_sim_free(&sim);
  return 0;
}
