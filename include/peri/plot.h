/* Line plots (x-y curves) as PNG, drawn with cairo: used for the force-displacement curve
 * of quasi-static fracture runs (output.plot). */
#ifndef PERI_PLOT_H
#define PERI_PLOT_H
#include <stddef.h>

/* Draws y(x) as a polyline with markers on white, with axes, ticks at "nice" values, axis
 * labels and a title, into a width x height PNG at path (written to path.tmp and renamed).
 * Returns 0 or PERI_ERR_RUN with a message. */
int peri_plot_write(const char *path, const double *x, const double *y, size_t n, const char *xlabel,
                    const char *ylabel, const char *title, int width, int height);

/* The same with the points marks[0 .. n_marks-1] (indices into x, y) ringed in red and
 * labelled with mark_labels (NULL: no labels), e.g. the detected onsets of a film's wrinkling
 * on its energy curve (docs/thin_films.md). */
int peri_plot_write_marked(const char *path, const double *x, const double *y, size_t n, const size_t *marks,
                           size_t n_marks, const char *const *mark_labels, const char *xlabel, const char *ylabel,
                           const char *title, int width, int height);

/* The same with a reference curve yr(xr) of nr points (e.g. a theory) drawn dashed in red
 * over the same axes (nr = 0: none). */
int peri_plot_write_reference(const char *path, const double *x, const double *y, size_t n, const double *xr,
                              const double *yr, size_t nr, const size_t *marks, size_t n_marks,
                              const char *const *mark_labels, const char *xlabel, const char *ylabel,
                              const char *title, int width, int height);

/* A tick step of 1, 2 or 5 times a power of ten giving about `want` intervals of span. */
double peri_plot_nice_step(double span, int want);

#endif
