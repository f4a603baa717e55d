/* Line plot of a curve as PNG (include/peri/plot.h). */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <cairo.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/plot.h"

double peri_plot_nice_step(double span, int want) {
  if (!(span > 0.0) || !isfinite(span) || want < 1) return 0.0; /* no ticks */
  double raw = span / want, p = pow(10.0, floor(log10(raw))), f = raw / p;
  return (f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0) * p;
}

static void range(const double *v, size_t n, double *lo, double *hi) {
  *lo = INFINITY, *hi = -INFINITY;
  for (size_t k = 0; k < n; ++k)
    if (isfinite(v[k])) *lo = fmin(*lo, v[k]), *hi = fmax(*hi, v[k]);
  if (!(*lo <= *hi)) *lo = 0.0, *hi = 1.0;
  if (*lo > 0.0 && *lo < 0.5 * *hi) *lo = 0.0; /* include the origin when near */
  if (*hi < 0.0 && *hi > 0.5 * *lo) *hi = 0.0;
  if (*hi - *lo <= 1e-300 * fmax(1.0, fabs(*hi))) *lo -= 0.5, *hi += 0.5;
  double pad = 0.04 * (*hi - *lo);
  *hi += pad;
  if (*lo != 0.0) *lo -= pad;
}

int peri_plot_write(const char *path, const double *x, const double *y, size_t n, const char *xlabel,
                    const char *ylabel, const char *title, int width, int height) {
  return peri_plot_write_marked(path, x, y, n, NULL, 0, NULL, xlabel, ylabel, title, width, height);
}

int peri_plot_write_marked(const char *path, const double *x, const double *y, size_t n, const size_t *marks,
                           size_t n_marks, const char *const *mark_labels, const char *xlabel, const char *ylabel,
                           const char *title, int width, int height) {
  return peri_plot_write_reference(path, x, y, n, NULL, NULL, 0, marks, n_marks, mark_labels, xlabel, ylabel, title,
                                   width, height);
}

/* The range of two series together (the reference curve must fit in the frame too). */
static void range2(const double *a, size_t na, const double *b, size_t nb, double *lo, double *hi) {
  double *all = peri_malloc(sizeof(double) * (na + nb + 1));
  for (size_t k = 0; k < na; ++k) all[k] = a[k];
  for (size_t k = 0; k < nb; ++k) all[na + k] = b[k];
  range(all, na + nb, lo, hi);
  free(all);
}

int peri_plot_write_reference(const char *path, const double *x, const double *y, size_t n, const double *xr,
                              const double *yr, size_t nr, const size_t *marks, size_t n_marks,
                              const char *const *mark_labels, const char *xlabel, const char *ylabel,
                              const char *title, int width, int height) {
  cairo_surface_t *surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
    peri_error("cannot draw %s: %s", path, cairo_status_to_string(cairo_surface_status(surface)));
    cairo_surface_destroy(surface);
    return PERI_ERR_RUN;
  }
  cairo_t *cr = cairo_create(surface);
  const double fs = height / 36.0;
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, fs);
  const double left = 7.5 * fs, right = width - 2.0 * fs, top = 3.0 * fs, bottom = height - 4.0 * fs;
  double x0, x1, y0, y1;
  range2(x, n, xr, nr, &x0, &x1);
  range2(y, n, yr, nr, &y0, &y1);
#define PX(v) (left + ((v) - x0) / (x1 - x0) * (right - left))
#define PY(v) (bottom - ((v) - y0) / (y1 - y0) * (bottom - top))
  cairo_text_extents_t ext;
  char label[64];
  /* grid, ticks and tick labels */
  cairo_set_line_width(cr, 1.0);
  double sx = peri_plot_nice_step(x1 - x0, 6), sy = peri_plot_nice_step(y1 - y0, 6);
  for (double t = ceil(x0 / sx) * sx; t <= x1 + 1e-9 * sx; t += sx) {
    double v = fabs(t) < 1e-9 * sx ? 0.0 : t;
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, PX(v), top);
    cairo_line_to(cr, PX(v), bottom);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    snprintf(label, sizeof label, "%g", v);
    cairo_text_extents(cr, label, &ext);
    cairo_move_to(cr, PX(v) - ext.x_advance / 2, bottom + 1.4 * fs);
    cairo_show_text(cr, label);
  }
  for (double t = ceil(y0 / sy) * sy; t <= y1 + 1e-9 * sy; t += sy) {
    double v = fabs(t) < 1e-9 * sy ? 0.0 : t;
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, left, PY(v));
    cairo_line_to(cr, right, PY(v));
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    snprintf(label, sizeof label, "%g", v);
    cairo_text_extents(cr, label, &ext);
    cairo_move_to(cr, left - ext.x_advance - 0.5 * fs, PY(v) + 0.35 * fs);
    cairo_show_text(cr, label);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_rectangle(cr, left, top, right - left, bottom - top);
  cairo_stroke(cr);
  /* labels and title */
  cairo_text_extents(cr, xlabel, &ext);
  cairo_move_to(cr, (left + right - ext.x_advance) / 2, height - 1.2 * fs);
  cairo_show_text(cr, xlabel);
  cairo_save(cr);
  cairo_text_extents(cr, ylabel, &ext);
  cairo_move_to(cr, 1.6 * fs, (top + bottom + ext.x_advance) / 2);
  cairo_rotate(cr, -M_PI / 2);
  cairo_show_text(cr, ylabel);
  cairo_restore(cr);
  cairo_set_font_size(cr, 1.2 * fs);
  cairo_text_extents(cr, title, &ext);
  cairo_move_to(cr, (width - ext.x_advance) / 2, 1.9 * fs);
  cairo_show_text(cr, title);
  /* the curve */
  cairo_rectangle(cr, left, top, right - left, bottom - top);
  cairo_clip(cr);
  cairo_set_source_rgb(cr, 0.12, 0.35, 0.70);
  cairo_set_line_width(cr, 2.0);
  bool pen = false;
  for (size_t k = 0; k < n; ++k) {
    if (!isfinite(x[k]) || !isfinite(y[k])) {
      pen = false;
      continue;
    }
    if (pen) cairo_line_to(cr, PX(x[k]), PY(y[k]));
    else cairo_move_to(cr, PX(x[k]), PY(y[k]));
    pen = true;
  }
  cairo_stroke(cr);
  /* the reference curve: dashed red, under the markers */
  if (nr > 1) {
    const double dash[] = {0.6 * fs, 0.4 * fs};
    cairo_save(cr);
    cairo_set_source_rgb(cr, 0.85, 0.10, 0.10);
    cairo_set_dash(cr, dash, 2, 0.0);
    pen = false;
    for (size_t k = 0; k < nr; ++k) {
      if (!isfinite(xr[k]) || !isfinite(yr[k])) {
        pen = false;
        continue;
      }
      if (pen) cairo_line_to(cr, PX(xr[k]), PY(yr[k]));
      else cairo_move_to(cr, PX(xr[k]), PY(yr[k]));
      pen = true;
    }
    cairo_stroke(cr);
    cairo_restore(cr);
    cairo_set_source_rgb(cr, 0.12, 0.35, 0.70);
  }
  if (n <= 200)
    for (size_t k = 0; k < n; ++k) {
      if (!isfinite(x[k]) || !isfinite(y[k])) continue;
      cairo_arc(cr, PX(x[k]), PY(y[k]), 0.18 * fs, 0, 2 * M_PI);
      cairo_fill(cr);
    }
  /* the marked points: a red ring and a label above each */
  cairo_set_font_size(cr, fs);
  for (size_t m = 0; m < n_marks; ++m) {
    const size_t k = marks[m];
    if (k >= n || !isfinite(x[k]) || !isfinite(y[k])) continue;
    cairo_set_source_rgb(cr, 0.85, 0.10, 0.10);
    cairo_set_line_width(cr, 3.0);
    cairo_new_sub_path(cr);
    cairo_arc(cr, PX(x[k]), PY(y[k]), 0.6 * fs, 0, 2 * M_PI);
    cairo_stroke(cr);
    if (mark_labels && mark_labels[m]) {
      cairo_text_extents(cr, mark_labels[m], &ext);
      double tx = PX(x[k]) - ext.x_advance / 2;
      if (tx + ext.x_advance > right) tx = right - ext.x_advance - 0.3 * fs;
      if (tx < left) tx = left + 0.3 * fs;
      double ty = PY(y[k]) - 1.0 * fs;
      if (ty < top + 1.2 * fs) ty = PY(y[k]) + 1.8 * fs;
      cairo_move_to(cr, tx, ty);
      cairo_show_text(cr, mark_labels[m]);
    }
  }
#undef PX
#undef PY
  cairo_destroy(cr);
  size_t len = strlen(path) + 8;
  char *tmp = peri_malloc(len);
  snprintf(tmp, len, "%s.tmp", path);
  cairo_status_t st = cairo_surface_write_to_png(surface, tmp);
  cairo_surface_destroy(surface);
  int rc = PERI_OK;
  if (st != CAIRO_STATUS_SUCCESS || rename(tmp, path) != 0) {
    peri_error("cannot write %s: %s", path, st != CAIRO_STATUS_SUCCESS ? cairo_status_to_string(st) : "rename failed");
    remove(tmp);
    rc = PERI_ERR_RUN;
  }
  free(tmp);
  return rc;
}
