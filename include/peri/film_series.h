/* The film's quantities over a run's history rows and the onsets found in them at the end of
 * the run (output.wrinkles, docs/thin_films.md; src/run/film_series.c). */
#ifndef PERI_FILM_SERIES_H
#define PERI_FILM_SERIES_H
#include <stddef.h>
#include "peri/sim.h"

typedef struct peri_film_series {
  double *rows;                 /* 5 per row: time, film strain energy, wrinkle amplitude,
                                   wavelength, broken interface bonds */
  long n, capacity;
} peri_film_series;

/* Appends the present state's row (collective: every rank calls it at every history row,
 * with s->disc.p.energy holding this state's energy densities). */
void peri_film_series_add(peri_film_series *f, const peri_sim *s, double amplitude, double wavelength);
/* The summary lines of the onsets of wrinkling and delamination. */
void peri_film_series_print(const peri_film_series *f, const peri_sim *s);
/* wrinkling.csv (the onsets) and wrinkling_energy.png (the film's energy against the
 * pseudo-time, the onsets ringed) in the output directory; rank 0 writes them. `path`
 * receives the picture's path for the summary ("" when none). Returns 0 or PERI_ERR_RUN. */
int peri_film_series_write(const peri_film_series *f, const peri_sim *s, char *path, size_t size);
/* The onsets as numbers (peri sweep's film quantities, docs/thin_films.md section 8):
 * out[0] the pseudo-time of wrinkling, out[1] that of delamination (NaN: none), out[2] the
 * wrinkle wavelength one row past the wrinkling onset (NaN: none or past the last row),
 * out[3] the regime: 0 neither, 1 wrinkling only, 2 wrinkling then delamination,
 * 3 delamination first (at or before the wrinkling onset's row, or without one). */
void peri_film_series_onsets(const peri_film_series *f, double out[4]);
void peri_film_series_free(peri_film_series *f);

#endif
