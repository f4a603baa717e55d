/* The table of constitutive models: one line per model. */
#include <string.h>
#include "peri/model.h"

extern const peri_model_ops peri_model_pmb;
extern const peri_model_ops peri_model_lps;
extern const peri_model_ops peri_model_osb_mo; /* src/model/osb_mo.c */

static const peri_model_ops *const models[] = {&peri_model_pmb, &peri_model_lps, &peri_model_osb_mo};
#define N_MODELS (sizeof models / sizeof *models)

const peri_model_ops *peri_model_find(const char *name) {
  for (size_t k = 0; k < sizeof models / sizeof *models; ++k)
    if (strcmp(models[k]->name, name) == 0) return models[k];
  return NULL;
}

const char *const *peri_model_names(void) {
  static const char *names[N_MODELS + 1];
  for (size_t k = 0; k < N_MODELS; ++k) names[k] = models[k]->name;
  names[N_MODELS] = NULL;
  return names;
}
