/* The size a fuzzed deck asks for, estimated before it is built (fuzz_deck.c, fuzz_run.c):
 * inputs whose grid would be large are skipped, since a deck asking for a million nodes is a
 * valid deck and building it only makes the run slow (a timeout, not a bug). */
#ifndef PERI_FUZZ_DECK_SIZE_H
#define PERI_FUZZ_DECK_SIZE_H
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "peri/deck.h"
#include "peri/expr.h"
#include "peri/setup.h"
#include "peri/shape.h"

/* The largest |horizon| of an expression over the box lo..hi, sampled at 17 points a side
 * (a bound for the size estimate, not the set-up's check); 0 when it does not parse. */
static inline double horizon_expression_bound(const char *text, int dim, const double lo[3], const double hi[3]) {
  char err[256];
  peri_expr *e = peri_expr_parse(text, err, sizeof err);
  if (!e) return 0.0;
  enum { SAMPLES = 17 };
  double largest = 0.0;
  for (int i = 0; i < SAMPLES; ++i)
    for (int j = 0; j < (dim > 1 ? SAMPLES : 1); ++j)
      for (int k = 0; k < (dim > 2 ? SAMPLES : 1); ++k) {
        const int at[3] = {i, j, k};
        double x[3] = {0, 0, 0};
        for (int a = 0; a < dim; ++a) x[a] = lo[a] + (hi[a] - lo[a]) * at[a] / (SAMPLES - 1);
        const double h = fabs(peri_expr_eval(e, x[0], x[1], x[2], 0.0));
        if (h > largest) largest = h; /* (NaN is not larger) */
      }
  peri_expr_free(e);
  return largest;
}

/* Grid nodes the fill shapes of a deck ask for, from their bounding boxes (an upper bound
 * of the grid generator's count); 0 when the deck does not say (the set-up then reports
 * the problem itself). Bonds: nodes times the lattice points within a horizon. */
static inline void estimate_size(const char *text, double *nodes, double *bonds) {
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
    static const char *const extra[] = {"material", "spacing", NULL}; /* (setup.c's fill keys) */
    const peri_node *horizon_node = peri_deck_get(d, "horizon");
    const char *horizon_text = horizon_node && horizon_node->scalar ? horizon_node->scalar : NULL;
    double horizon_bound = 0.0; /* a horizon given as an expression: its largest sampled value */
    for (int k = 0; k < fill->count; ++k) {
      peri_shape shape;
      memset(&shape, 0, sizeof shape);
      if (peri_shape_parse(fill->items[k], (int)dim, "fill", extra, &shape) != 0) continue;
      /* an item's own spacing (graded grids) counts its nodes */
      double own = spacing;
      if (peri_deck_double(fill->items[k], "spacing", false, &own) != 0 || !(own > 0.0)) own = spacing;
      double lo[3], hi[3], count = 1.0;
      if (peri_shape_bounds(&shape, (int)dim, lo, hi)) {
        for (int a = 0; a < dim; ++a) count *= fabs(hi[a] - lo[a]) / own + 2.0;
        if (horizon_text) horizon_bound = fmax(horizon_bound, horizon_expression_bound(horizon_text, (int)dim, lo, hi));
      }
      peri_shape_free(&shape);
      *nodes += isfinite(count) ? count : 1e300;
    }
    if (peri_deck_double(d, "m", false, &m) == 0 && isnan(m)) {
      if (peri_deck_double(d, "horizon", false, &horizon) == 0 && !isnan(horizon))
        m = horizon / spacing;
      else if (horizon_bound > 0.0)
        m = horizon_bound / spacing;
    }
    double reach = isfinite(m) ? 2.0 * fabs(m) + 1.0 : 1.0;
    *bonds = *nodes * pow(reach, (double)dim);
  }
  peri_deck_free(root);
}

/* The input as deck text (NUL-terminated, for the caller to free), or NULL when its grid would
 * have more than max_nodes nodes or max_bonds bonds. */
static inline char *deck_text_within(const uint8_t *data, size_t size, double max_nodes, double max_bonds) {
  char *text = malloc(size + 1);
  memcpy(text, data, size);
  text[size] = '\0';
  double nodes, bonds;
  estimate_size(text, &nodes, &bonds);
  if (nodes <= max_nodes && bonds <= max_bonds) return text;
  free(text);
  return NULL;
}

#endif
