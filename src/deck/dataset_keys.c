/* output.dataset: the graph dataset of the run (docs/datasets.md). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/dataset.h"
#include "peri/dataset_file.h"
#include "peri/error.h"
#include "peri/setup.h"

/* A tag's value: a number when the whole scalar reads as one, else its text. */
static int parse_tag(const peri_node *key, const peri_node *value, peri_dataset_tag *tag) {
  if (value->kind != PERI_NODE_SCALAR)
    return peri_deck_error(value, "output.dataset.tags: tag '%s' must be a number or a text, got %s", key->scalar,
                           peri_deck_kind_name(value));
  tag->name = peri_strdup(key->scalar);
  char *end = NULL;
  const double v = strtod(value->scalar, &end);
  if (end != value->scalar && *end == '\0') tag->value = v;
  else tag->text = peri_strdup(value->scalar);
  return PERI_OK;
}

int peri_dataset_parse(peri_sim *s, const peri_node *output) {
  const peri_node *it = peri_deck_get(output, "dataset");
  if (!it) return PERI_OK;
  if (it->kind != PERI_NODE_MAPPING)
    return peri_deck_error(it, "key 'dataset': expected a mapping such as {every: 10, file: graph.h5}");
  static const char *const keys[] = {"every", "file", "tags", NULL};
  if (peri_deck_allow(it, "output.dataset", keys) != PERI_OK) return PERI_ERR_INPUT;
  if (!peri_dataset_file_supported())
    return peri_deck_error(it, "key 'dataset': this peri was built without HDF5, which graph datasets need "
                               "(install libhdf5-dev, e.g. with scripts/install-deps, and rebuild)");
  if (s->solver.kind == PERI_SOLVER_HEAT)
    return peri_deck_error(it, "key 'dataset': a heat conduction run (solver: heat) has no bonds' mechanics to "
                               "write; graph datasets are for mechanical runs");
  long every = 0;
  const char *file = NULL;
  if (peri_deck_int(it, "every", true, &every) != PERI_OK) return PERI_ERR_INPUT;
  if (every < 1) return peri_deck_error(peri_deck_get(it, "every"), "key 'every': must be >= 1 (steps between graph frames)");
  if (peri_deck_string(it, "file", false, &file) != PERI_OK) return PERI_ERR_INPUT;
  if (file && !*file) return peri_deck_error(peri_deck_get(it, "file"), "key 'file': expected a file name, got an empty string");
  const peri_node *tags = peri_deck_get(it, "tags");
  if (tags && tags->kind != PERI_NODE_MAPPING)
    return peri_deck_error(tags, "key 'tags': expected a mapping of names to numbers or texts, e.g. {load: 2e6, defect: hole}");
  peri_dataset_output *d = peri_calloc(1, sizeof *d);
  d->every = every;
  if (file) {
    d->file = peri_strdup(file);
  } else {
    const size_t size = strlen(s->out.basename) + sizeof "_graph.h5";
    d->file = peri_malloc(size);
    snprintf(d->file, size, "%s_graph.h5", s->out.basename);
  }
  s->out.dataset = d;
  if (tags) {
    d->tags = peri_calloc((size_t)(tags->count > 0 ? tags->count : 1), sizeof *d->tags);
    for (int k = 0; k < tags->count; ++k) {
      if (parse_tag(tags->keys[k], tags->items[k], &d->tags[k]) != PERI_OK) return PERI_ERR_INPUT;
      d->n_tags++;
    }
  }
  return PERI_OK;
}
