/* libFuzzer target: the deck parser and the whole set-up that `peri check` runs
 * (peri_sim_from_deck, then peri_sim_free) on a deck file holding the fuzz input.
 *
 * Inputs whose grid would be large are skipped: a deck asking for a million nodes is a
 * valid deck, and building it only makes the run slow (a timeout, not a bug). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "peri/deck.h"
#include "peri/setup.h"
#include "peri/shape.h"
#include "peri/sim.h"
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
  const char *dir = getenv("TMPDIR");
  snprintf(deck_path, sizeof deck_path, "%s/peri-fuzz-deck-XXXXXX.yaml", dir && strlen(dir) < 200 ? dir : "/tmp");
  int fd = mkstemps(deck_path, 5);
  if (fd < 0) abort();
  close(fd);
  return 0;
}

/* Grid nodes the fill shapes of a deck ask for, from their bounding boxes (an upper bound
 * of the grid generator's count); 0 when the deck does not say (the set-up then reports
 * the problem itself). Bonds: nodes times the lattice points within a horizon. */
static void estimate_size(const char *text, double *nodes, double *bonds) {
  *nodes = 0.0;
  *bonds = 0.0;
  peri_node *root = peri_deck_parse_string(text, "fuzz.yaml");
  if (!root) return;
  long dim = 0;
  const peri_node *d = peri_deck_get(root, "discretization");
  const peri_node *fill = d ? peri_deck_get(d, "fill") : NULL;
  double spacing = NAN, horizon = NAN, m = NAN;
  if (peri_deck_int(root, "dimension", true, &dim) == 0 && dim >= 1 && dim <= 3 && fill &&
      fill->kind == PERI_NODE_SEQUENCE && peri_deck_double(d, "spacing", true, &spacing) == 0 && spacing > 0.0) {
    static const char *const extra[] = {"material", NULL};
    for (int k = 0; k < fill->count; ++k) {
      peri_shape shape;
      memset(&shape, 0, sizeof shape);
      if (peri_shape_parse(fill->items[k], (int)dim, "fill", extra, &shape) != 0) continue;
      double lo[3], hi[3], count = 1.0;
      if (peri_shape_bounds(&shape, (int)dim, lo, hi))
        for (int a = 0; a < dim; ++a) count *= fabs(hi[a] - lo[a]) / spacing + 2.0;
      peri_shape_free(&shape);
      *nodes += isfinite(count) ? count : 1e300;
    }
    if (peri_deck_double(d, "m", false, &m) == 0 && isnan(m) &&
        peri_deck_double(d, "horizon", false, &horizon) == 0)
      m = horizon / spacing;
    double reach = isfinite(m) ? 2.0 * fabs(m) + 1.0 : 1.0;
    *bonds = *nodes * pow(reach, (double)dim);
  }
  peri_deck_free(root);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char *text = malloc(size + 1);
  memcpy(text, data, size);
  text[size] = '\0';
  double nodes, bonds;
  estimate_size(text, &nodes, &bonds);
  free(text);
  if (!(nodes <= MAX_NODES) || !(bonds <= MAX_BONDS)) return -1; /* not added to the corpus */

  FILE *f = fopen(deck_path, "wb");
  if (!f) abort();
  if (size && fwrite(data, 1, size, f) != size) abort();
  fclose(f);

  peri_sim sim;
  peri_sim_from_deck(&sim, deck_path);
  peri_sim_free(&sim);
  return 0;
}
