/* The constitutive model interface. A new model is one file in src/model/ plus one line
 * in the table of src/model/model_table.c. Models never know which solver calls them. */
#ifndef PERI_MODEL_H
#define PERI_MODEL_H
#include <stdint.h>

typedef struct peri_sim peri_sim;

typedef struct peri_model_ops {
  const char *name;
  /* Which elastic constants define it, for messages ("E or K", ...). */
  const char *description;
  /* Poisson ratio fixed by the model (bond-based), or 0 when free. */
  int fixed_poisson;
  /* Derives per-material constants (after elastic constants are resolved) and allocates
   * and fills model work arrays (e.g. weighted volume). Returns 0 or PERI_ERR_INPUT. */
  int (*init)(peri_sim *s);
  /* Overwrites s->p.f of owned nodes with the internal force density at the current
   * displacement. When s->breaking is set, first breaks every intact bond whose stretch
   * exceeds its critical stretch (symmetric in i and j); returns the number of directed
   * bonds broken in this call. */
  long (*force)(peri_sim *s);
  /* Strain energy density W_i of every owned node into W (bonds as they are). */
  void (*energy)(peri_sim *s, double *W);
  /* Scalar pair force density (t_ij + t_ji), N/m^6, of the intact bond k of node i whose
   * deformed length is r, at the state of the last force() call (dilatation, thermal
   * strain). The force on i is pair * beta V_j * (y_j - y_i)/r. Used by stress recovery. */
  double (*pair_force)(const peri_sim *s, int32_t i, int64_t k, double r);
} peri_model_ops;

/* The model table. */
const peri_model_ops *peri_model_find(const char *name);
/* NULL-terminated list of model names (for deck choices). */
const char *const *peri_model_names(void);

#endif
