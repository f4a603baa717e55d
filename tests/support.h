/* Test support: build a simulation from a deck given as a string. */
#ifndef PERI_TEST_SUPPORT_H
#define PERI_TEST_SUPPORT_H
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>
#include "peri/setup.h"
#include "peri/sim.h"

/* Writes yaml to a temporary file and builds the simulation from it. Returns the status
 * of peri_sim_from_deck. */
static inline int sim_from_string(peri_sim *s, const char *yaml) {
  char path[] = "/tmp/peri_test_deck_XXXXXX";
  int fd = mkstemp(path);
  if (fd < 0) return -1;
  FILE *f = fdopen(fd, "w");
  fputs(yaml, f);
  fclose(f);
  int rc = peri_sim_from_deck(s, path);
  unlink(path);
  return rc;
}

#endif
