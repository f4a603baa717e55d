/* The checkpoint keys of the `output` section (docs/restart.md). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/checkpoint.h"
#include "peri/comm.h"
#include "peri/error.h"
#include "peri/output.h"
#include "peri/setup.h"

int peri_checkpoint_parse(peri_sim *s, const peri_node *output) {
  peri_output *o = &s->out;
  const peri_node *every = peri_deck_get(output, "checkpoint_every");
  const peri_node *file = peri_deck_get(output, "checkpoint_file");
  if (peri_deck_int(output, "checkpoint_every", false, &o->checkpoint_every) != PERI_OK) return PERI_ERR_INPUT;
  if (every && o->checkpoint_every < 1) return peri_deck_error(every, "key 'checkpoint_every': must be >= 1 (steps)");
  const char *name = NULL;
  if (peri_deck_string(output, "checkpoint_file", false, &name) != PERI_OK) return PERI_ERR_INPUT;
  if (file && !every)
    return peri_deck_error(file, "key 'checkpoint_file': give 'checkpoint_every' too (steps between checkpoints)");
  if (name && !*name) return peri_deck_error(file, "key 'checkpoint_file': expected a file name, got an empty string");
  if (every && !peri_checkpoint_supported())
    return peri_deck_error(every, "key 'checkpoint_every': this peri was built without HDF5, which checkpoints "
                                  "need (install libhdf5-dev, e.g. with scripts/install-deps, and rebuild)");
  if (name) o->checkpoint_file = peri_strdup(name);
  return PERI_OK;
}
