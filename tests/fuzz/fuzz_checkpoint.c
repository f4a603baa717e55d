/* libFuzzer target: reading a checkpoint (peri_restart_load) for a simulation built from
 * a fixed small deck (checkpoint_deck.yaml), with the fuzz input as the checkpoint file.
 * A fresh simulation per input, as `peri run DECK --restart FILE` builds one. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "peri/checkpoint.h"
#include "peri/setup.h"
#include "peri/sim.h"
#include "quiet.h"

static char work_dir[256];      /* the output directory: empty, so no rows or frames are kept */
static char checkpoint_path[288];
static const char *deck_path;

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  silence_library();
  deck_path = getenv("PERI_FUZZ_CHECKPOINT_DECK");
  if (!deck_path) deck_path = PERI_FUZZ_CHECKPOINT_DECK; /* the source tree's copy */
  fuzz_temp_path(work_dir, sizeof work_dir, "peri-fuzz-ckpt-XXXXXX");
  if (!mkdtemp(work_dir)) abort();
  snprintf(checkpoint_path, sizeof checkpoint_path, "%s/input.h5", work_dir);
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  FILE *f = fopen(checkpoint_path, "wb");
  if (!f) abort();
  if (size && fwrite(data, 1, size, f) != size) abort();
  fclose(f);

  peri_sim sim;
  if (peri_sim_from_deck(&sim, deck_path) != 0) abort(); /* the fixed deck is valid */
  free(sim.out.directory);
  sim.out.directory = strdup(work_dir);
  peri_restart_load(&sim, checkpoint_path);
  peri_sim_free(&sim);
  return 0;
}
