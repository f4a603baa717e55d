/* The film's series and its onsets (include/peri/film_series.h, docs/thin_films.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "peri/comm.h"
#include "peri/error.h"
#include "peri/film_quantities.h"
#include "peri/film_series.h"
#include "peri/plot.h"

enum { FILM_ROW = 5 };

void peri_film_series_add(peri_film_series *c, const peri_sim *s, double amplitude, double wavelength) {
  if (c->n == c->capacity) {
    c->capacity = c->capacity ? 2 * c->capacity : 64;
    c->rows = peri_realloc(c->rows, sizeof(double) * FILM_ROW * (size_t)c->capacity);
  }
  long broken = 0;
  double stress = 0.0;
  peri_interface_history(s, &broken, &stress);
  double *row = &c->rows[FILM_ROW * c->n++];
  row[0] = s->state.time, row[1] = peri_region_strain_energy(s, s->out.wrinkle_region);
  row[2] = amplitude, row[3] = wavelength, row[4] = (double)broken;
}

/* The onsets of wrinkling and of delamination (peri_wrinkle_onsets, docs/thin_films.md): rows
 * of the film series, -1 where there is none. */
static void film_onsets(const peri_film_series *c, int *wrinkling, int *delamination) {
  const long n = c->n;
  const size_t room = (size_t)(n > 0 ? n : 1);
  double *t = peri_malloc(sizeof(double) * room), *energy = peri_malloc(sizeof(double) * room),
         *broken = peri_malloc(sizeof(double) * room);
  for (long k = 0; k < n; ++k) {
    const double *row = &c->rows[FILM_ROW * k];
    t[k] = row[0], energy[k] = row[1], broken[k] = row[4];
  }
  peri_wrinkle_onsets(t, energy, broken, (int)n, wrinkling, delamination);
  free(t);
  free(energy);
  free(broken);
}

void peri_film_series_print(const peri_film_series *c, const peri_sim *s) {
  int at[2];
  film_onsets(c, &at[0], &at[1]);
  static const char *const what[] = {"wrinkling", "wrinkling with delamination"};
  for (int m = 0; m < 2; ++m) {
    if (at[m] < 0) {
      printf("  onset        %s: none (%s)\n", what[m], m ? "no interface bond broke" : "no local maximum of the film's energy rate");
      continue;
    }
    const double *row = &c->rows[FILM_ROW * at[m]];
    printf("  onset        %s at t = %.6g (load step %d): strain energy of '%s' %.6g J, wrinkle amplitude %.4g m, wavelength %.4g m\n",
           what[m], row[0], at[m], s->cond.regions[s->out.wrinkle_region].name, row[1], row[2], row[3]);
  }
}

int peri_film_series_write(const peri_film_series *c, const peri_sim *s, char *path, size_t size) {
  path[0] = '\0';
  if (peri_comm_rank() != 0) return PERI_OK;
  int at[2];
  film_onsets(c, &at[0], &at[1]);
  char file[4300];
  snprintf(file, sizeof file, "%s/wrinkling.csv", s->out.directory);
  FILE *f = fopen(file, "w");
  if (!f) {
    peri_error("cannot write %s", file);
    return PERI_ERR_RUN;
  }
  fprintf(f, "onset,time,load_step,strain_energy,wrinkle_amplitude,wrinkle_wavelength\n");
  static const char *const names[] = {"wrinkling", "delamination"};
  for (int m = 0; m < 2; ++m) {
    if (at[m] < 0) continue; /* none found: no row */
    const double *row = &c->rows[FILM_ROW * at[m]];
    fprintf(f, "%s,%.10g,%d,%.10g,%.10g,%.10g\n", names[m], row[0], at[m], row[1], row[2], row[3]);
  }
  if (fclose(f) != 0) {
    peri_error("cannot write %s", file);
    return PERI_ERR_RUN;
  }
  const long n = c->n;
  double *t = peri_malloc(sizeof(double) * (size_t)(n > 0 ? n : 1)), *u = peri_malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  for (long k = 0; k < n; ++k) t[k] = c->rows[FILM_ROW * k], u[k] = c->rows[FILM_ROW * k + 1];
  size_t marks[2];
  const char *labels[2];
  size_t n_marks = 0;
  for (int m = 0; m < 2; ++m)
    if (at[m] >= 0) marks[n_marks] = (size_t)at[m], labels[n_marks++] = m ? "wrinkling + delamination" : "wrinkling";
  char ylabel[300], title[600];
  snprintf(ylabel, sizeof ylabel, "strain_energy_%s [J]", s->cond.regions[s->out.wrinkle_region].name);
  snprintf(title, sizeof title, "%s: energy criterion", s->out.basename);
  snprintf(path, size, "%s/wrinkling_energy.png", s->out.directory);
  const int rc = n > 0 ? peri_plot_write_marked(path, t, u, (size_t)n, marks, n_marks, labels, "time = applied strain [1]",
                                                ylabel, title, 1200, 800)
                       : PERI_OK;
  if (rc != PERI_OK || n == 0) path[0] = '\0';
  free(t);
  free(u);
  return rc;
}

void peri_film_series_onsets(const peri_film_series *c, double out[4]) {
  int at[2];
  film_onsets(c, &at[0], &at[1]);
  out[0] = at[0] >= 0 ? c->rows[FILM_ROW * at[0]] : NAN;
  out[1] = at[1] >= 0 ? c->rows[FILM_ROW * at[1]] : NAN;
  out[2] = at[0] >= 0 && at[0] + 1 < c->n ? c->rows[FILM_ROW * (at[0] + 1) + 3] : NAN;
  out[3] = at[1] < 0 ? (at[0] < 0 ? 0.0 : 1.0) : (at[0] >= 0 && at[0] < at[1] ? 2.0 : 3.0);
}

void peri_film_series_free(peri_film_series *f) {
  free(f->rows);
  *f = (peri_film_series){0};
}
