/* PNG picture of a scalar field on a 2D node cloud, drawn with cairo.
 *
 * Layout, top to bottom: margin, title, plot (node cloud at a uniform scale, y up), gap,
 * horizontal colour bar, min/max labels, margin. With axes (peri_png_write_field_axes): the
 * plot has a frame with ticks and labelled axes on its left and bottom, and the colour bar
 * ticks at round values and the name and unit of the value below it. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <cairo.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/output.h"
#include "peri/plot.h"

/* Matplotlib's viridis (lib/matplotlib/_cm_listed.py, _viridis_data; CC0, by Smith, van der
 * Walt and Firing), every 16th of its 256 entries plus the last, interpolated linearly in
 * between. `index` is the entry's position in the 256-entry table. */
static const struct {
  int index;
  double r, g, b;
} VIRIDIS[] = {
    {0, 0.267004, 0.004874, 0.329415},   {16, 0.282327, 0.094955, 0.417331},
    {32, 0.278826, 0.175490, 0.483397},  {48, 0.258965, 0.251537, 0.524736},
    {64, 0.229739, 0.322361, 0.545706},  {80, 0.199430, 0.387607, 0.554642},
    {96, 0.172719, 0.448791, 0.557885},  {112, 0.149039, 0.508051, 0.557250},
    {128, 0.127568, 0.566949, 0.550556}, {144, 0.120638, 0.625828, 0.533488},
    {160, 0.157851, 0.683765, 0.501686}, {176, 0.246070, 0.738910, 0.452024},
    {192, 0.369214, 0.788888, 0.382914}, {208, 0.515992, 0.831158, 0.294279},
    {224, 0.678489, 0.863742, 0.189503}, {240, 0.845561, 0.887322, 0.099702},
    {255, 0.993248, 0.906157, 0.143936},
};
enum { VIRIDIS_ANCHORS = sizeof VIRIDIS / sizeof VIRIDIS[0], COLOUR_LEVELS = 256 };

/* Nodes are drawn in COLOUR_LEVELS bins plus one for NaN, one fill per bin. */
enum { NAN_BIN = COLOUR_LEVELS, N_BINS = COLOUR_LEVELS + 1 };
static const double NAN_GREY = 0.6;

typedef struct rgb {
  double r, g, b;
} rgb;

/* Colour of level `level` in 0..255. */
static rgb viridis_level(int level) {
  int a = 0;
  while (a + 2 < VIRIDIS_ANCHORS && VIRIDIS[a + 1].index <= level) a++;
  double t = (double)(level - VIRIDIS[a].index) / (VIRIDIS[a + 1].index - VIRIDIS[a].index);
  return (rgb){VIRIDIS[a].r + t * (VIRIDIS[a + 1].r - VIRIDIS[a].r),
               VIRIDIS[a].g + t * (VIRIDIS[a + 1].g - VIRIDIS[a].g),
               VIRIDIS[a].b + t * (VIRIDIS[a + 1].b - VIRIDIS[a].b)};
}

static int colour_bin(double value, double vmin, double vmax) {
  if (isnan(value)) return NAN_BIN;
  double t = (value - vmin) / (vmax - vmin);
  if (!(t > 0)) return 0; /* also -inf */
  if (t >= 1) return COLOUR_LEVELS - 1;
  return (int)(t * (COLOUR_LEVELS - 1) + 0.5);
}

/* vmin >= vmax (or not finite) asks for the data range; constant data get [v, v + 1]. */
static void resolve_range(int32_t n, const double *values, double *vmin, double *vmax) {
  if (isfinite(*vmin) && isfinite(*vmax) && *vmin < *vmax) return;
  double lo = INFINITY, hi = -INFINITY;
  for (int32_t i = 0; i < n; i++) {
    if (!isfinite(values[i])) continue;
    if (values[i] < lo) lo = values[i];
    if (values[i] > hi) hi = values[i];
  }
  if (lo > hi) lo = hi = 0; /* no finite value */
  if (!(lo < hi)) hi = lo + 1;
  *vmin = lo;
  *vmax = hi;
}

typedef struct layout {
  int width, height;
  double margin, font_size;
  double title_baseline;
  double plot_x, plot_y, plot_w, plot_h; /* plot area in pixels */
  double scale;                          /* pixels per model unit */
  double xmin, ymax;                     /* model point drawn at (plot_x, plot_y) */
  double bar_x, bar_y, bar_w, bar_h;
  double label_baseline;
  bool axes;
  double extent_x, extent_y;             /* model extent drawn (with the half-dot pad) */
  double value_label_baseline;
} layout;

static layout compute_layout(int32_t n, const double *points, double dot, int width_px, bool axes) {
  layout L = {.width = width_px, .axes = axes};
  double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
  for (int32_t i = 0; i < n; i++) {
    double x = points[3 * i], y = points[3 * i + 1];
    if (!isfinite(x) || !isfinite(y)) continue;
    xmin = fmin(xmin, x), xmax = fmax(xmax, x);
    ymin = fmin(ymin, y), ymax = fmax(ymax, y);
  }
  if (xmin > xmax) xmin = ymin = 0, xmax = ymax = 1; /* nothing to draw: a unit square */
  /* Squares are centred on nodes: pad by half a dot so edge nodes are drawn whole. */
  double pad = isfinite(dot) && dot > 0 ? dot / 2 : 0;
  xmin -= pad, xmax += pad, ymin -= pad, ymax += pad;
  double extent_x = xmax - xmin, extent_y = ymax - ymin;
  if (!(extent_x > 0) && !(extent_y > 0)) extent_x = extent_y = 1;

  L.margin = fmax(4.0, round(0.04 * width_px));
  L.font_size = fmin(24.0, fmax(8.0, 0.035 * width_px));
  double title_h = 1.6 * L.font_size;
  double gap = L.margin;
  double bar_h = fmax(6.0, L.font_size);
  double label_h = 1.5 * L.font_size;

  /* axes: tick labels and the rotated axis label on the left, tick labels and the axis label
   * below, and a line for the value's name under the colour bar's labels */
  const double axis_left = axes ? 6.5 * L.font_size : 0.0, axis_below = axes ? 3.2 * L.font_size : 0.0;
  if (axes) label_h += 1.6 * L.font_size;
  L.plot_w = fmax(1.0, width_px - 2 * L.margin - axis_left);
  /* Uniform scale; a very tall cloud is capped at 4 widths and centred horizontally. */
  double max_plot_h = 4.0 * L.plot_w;
  if (extent_x > 0)
    L.scale = L.plot_w / extent_x;
  else
    L.scale = max_plot_h / extent_y;
  if (extent_y * L.scale > max_plot_h) L.scale = max_plot_h / extent_y;
  L.plot_h = fmax(1.0, ceil(extent_y * L.scale));

  L.title_baseline = L.margin + 1.2 * L.font_size;
  L.plot_x = L.margin + axis_left + (L.plot_w - extent_x * L.scale) / 2;
  L.plot_y = L.margin + title_h + (L.plot_h - extent_y * L.scale) / 2;
  L.xmin = xmin;
  L.ymax = ymax;
  L.extent_x = extent_x;
  L.extent_y = extent_y;
  L.bar_x = L.margin + axis_left;
  L.bar_w = L.plot_w;
  L.bar_y = L.margin + title_h + L.plot_h + axis_below + gap;
  L.bar_h = bar_h;
  L.label_baseline = L.bar_y + bar_h + 1.2 * L.font_size;
  L.value_label_baseline = L.label_baseline + 1.6 * L.font_size;
  L.height = (int)ceil(L.bar_y + bar_h + label_h + L.margin);
  return L;
}

/* Fills one square per node, batched by colour so that large clouds stay fast. Antialiasing
 * is off so small squares stay crisp and a node's pixels carry its exact colour. */
static void draw_nodes(cairo_t *cr, const layout *L, int32_t n, const double *points,
                       const double *values, double vmin, double vmax, double dot) {
  if (n <= 0) return;
  int *bin_of = peri_malloc((size_t)n * sizeof *bin_of);
  int *bin_start = peri_calloc(N_BINS + 1, sizeof *bin_start);
  for (int32_t i = 0; i < n; i++) {
    bin_of[i] = colour_bin(values[i], vmin, vmax);
    bin_start[bin_of[i] + 1]++;
  }
  for (int b = 0; b < N_BINS; b++) bin_start[b + 1] += bin_start[b];
  int *order = peri_malloc((size_t)n * sizeof *order);
  int *fill_pos = peri_malloc(N_BINS * sizeof *fill_pos);
  memcpy(fill_pos, bin_start, N_BINS * sizeof *fill_pos);
  for (int32_t i = 0; i < n; i++) order[fill_pos[bin_of[i]]++] = i;

  double half_side = isfinite(dot) && dot > 0 ? dot * L->scale / 2 : 0;
  cairo_save(cr);
  cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
  for (int b = 0; b < N_BINS; b++) {
    if (bin_start[b] == bin_start[b + 1]) continue;
    if (b == NAN_BIN) {
      cairo_set_source_rgb(cr, NAN_GREY, NAN_GREY, NAN_GREY);
    } else {
      rgb c = viridis_level(b);
      cairo_set_source_rgb(cr, c.r, c.g, c.b);
    }
    for (int k = bin_start[b]; k < bin_start[b + 1]; k++) {
      const double *p = &points[3 * order[k]];
      if (!isfinite(p[0]) || !isfinite(p[1])) continue;
      double cx = L->plot_x + (p[0] - L->xmin) * L->scale;
      double cy = L->plot_y + (L->ymax - p[1]) * L->scale;
      /* Edges snapped to whole pixels one by one, so nodes one dot apart tile without
       * gaps; at least one pixel so that no node vanishes. */
      double x0 = round(cx - half_side), x1 = round(cx + half_side);
      double y0 = round(cy - half_side), y1 = round(cy + half_side);
      if (x1 - x0 < 1) x0 = floor(cx), x1 = x0 + 1;
      if (y1 - y0 < 1) y0 = floor(cy), y1 = y0 + 1;
      cairo_rectangle(cr, x0, y0, x1 - x0, y1 - y0);
    }
    cairo_fill(cr);
  }
  cairo_restore(cr);
  free(fill_pos);
  free(order);
  free(bin_start);
  free(bin_of);
}

static void draw_colour_bar(cairo_t *cr, const layout *L, double vmin, double vmax) {
  cairo_pattern_t *gradient =
      cairo_pattern_create_linear(L->bar_x, 0, L->bar_x + L->bar_w, 0);
  for (int a = 0; a < VIRIDIS_ANCHORS; a++)
    cairo_pattern_add_color_stop_rgb(gradient, VIRIDIS[a].index / (COLOUR_LEVELS - 1.0),
                                      VIRIDIS[a].r, VIRIDIS[a].g, VIRIDIS[a].b);
  cairo_rectangle(cr, L->bar_x, L->bar_y, L->bar_w, L->bar_h);
  cairo_set_source(cr, gradient);
  cairo_fill_preserve(cr);
  cairo_pattern_destroy(gradient);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 1);
  cairo_stroke(cr);

  char label[64];
  cairo_text_extents_t ext;
  if (L->axes) { /* ticks at round values, labels centred on them and kept inside the image */
    const double step = peri_plot_nice_step(vmax - vmin, 5);
    for (double t = ceil(vmin / step) * step; step > 0 && t <= vmax + 1e-9 * step; t += step) {
      const double v = fabs(t) < 1e-9 * step ? 0.0 : t, x = L->bar_x + (v - vmin) / (vmax - vmin) * L->bar_w;
      cairo_move_to(cr, x, L->bar_y + L->bar_h);
      cairo_line_to(cr, x, L->bar_y + L->bar_h + 0.3 * L->font_size);
      cairo_stroke(cr);
      snprintf(label, sizeof label, "%.4g", v);
      cairo_text_extents(cr, label, &ext);
      double left = fmin(fmax(x - ext.x_advance / 2, 1.0), L->width - ext.x_advance - 1.0);
      cairo_move_to(cr, left, L->label_baseline + 0.2 * L->font_size);
      cairo_show_text(cr, label);
    }
    return;
  }
  snprintf(label, sizeof label, "%.4g", vmin);
  cairo_move_to(cr, L->bar_x, L->label_baseline);
  cairo_show_text(cr, label);
  snprintf(label, sizeof label, "%.4g", vmax);
  cairo_text_extents(cr, label, &ext);
  cairo_move_to(cr, L->bar_x + L->bar_w - ext.x_advance, L->label_baseline);
  cairo_show_text(cr, label);
}

/* A frame around the drawn region, ticks at round model coordinates on its bottom and left
 * edges with their values, the axis labels, and the value's name under the colour bar. */
static void draw_axes(cairo_t *cr, const layout *L, const peri_png_axes *axes) {
  const double x0 = L->plot_x, y0 = L->plot_y, w = L->extent_x * L->scale, h = L->extent_y * L->scale;
  const double fs = L->font_size;
  cairo_set_line_width(cr, 1);
  cairo_rectangle(cr, x0, y0, w, h);
  cairo_stroke(cr);
  char label[64];
  cairo_text_extents_t ext;
  const double xmin = L->xmin, ymin = L->ymax - L->extent_y;
  const int want_x = w > 12 * fs ? 5 : 2, want_y = h > 8 * fs ? 5 : 2;
  const double sx = peri_plot_nice_step(L->extent_x, want_x), sy = peri_plot_nice_step(L->extent_y, want_y);
  /* (a zero extent, a cloud on one line, has no ticks across it) */
  for (double t = ceil(xmin / sx) * sx; sx > 0 && t <= xmin + L->extent_x + 1e-9 * sx; t += sx) {
    const double v = fabs(t) < 1e-9 * sx ? 0.0 : t, x = x0 + (v - xmin) * L->scale;
    cairo_move_to(cr, x, y0 + h);
    cairo_line_to(cr, x, y0 + h + 0.3 * fs);
    cairo_stroke(cr);
    snprintf(label, sizeof label, "%.4g", v);
    cairo_text_extents(cr, label, &ext);
    cairo_move_to(cr, x - ext.x_advance / 2, y0 + h + 1.4 * fs);
    cairo_show_text(cr, label);
  }
  for (double t = ceil(ymin / sy) * sy; sy > 0 && t <= ymin + L->extent_y + 1e-9 * sy; t += sy) {
    const double v = fabs(t) < 1e-9 * sy ? 0.0 : t, y = y0 + (L->ymax - v) * L->scale;
    cairo_move_to(cr, x0, y);
    cairo_line_to(cr, x0 - 0.3 * fs, y);
    cairo_stroke(cr);
    snprintf(label, sizeof label, "%.4g", v);
    cairo_text_extents(cr, label, &ext);
    cairo_move_to(cr, x0 - ext.x_advance - 0.5 * fs, y + 0.35 * fs);
    cairo_show_text(cr, label);
  }
  if (axes->x_label) {
    cairo_text_extents(cr, axes->x_label, &ext);
    cairo_move_to(cr, x0 + (w - ext.x_advance) / 2, y0 + h + 2.9 * fs);
    cairo_show_text(cr, axes->x_label);
  }
  if (axes->y_label) {
    cairo_save(cr);
    cairo_text_extents(cr, axes->y_label, &ext);
    cairo_move_to(cr, L->margin + 1.0 * fs, y0 + (h + ext.x_advance) / 2);
    cairo_rotate(cr, -M_PI / 2);
    cairo_show_text(cr, axes->y_label);
    cairo_restore(cr);
  }
  if (axes->value_label) {
    cairo_text_extents(cr, axes->value_label, &ext);
    cairo_move_to(cr, L->bar_x + (L->bar_w - ext.x_advance) / 2, L->value_label_baseline);
    cairo_show_text(cr, axes->value_label);
  }
}

static void draw_title(cairo_t *cr, const layout *L, const char *title) {
  if (!title || !*title) return;
  cairo_text_extents_t ext;
  cairo_text_extents(cr, title, &ext);
  /* Shrink a long title to fit the width rather than clip it. */
  double room = L->width - 2 * L->margin;
  if (ext.x_advance > room && ext.x_advance > 0) {
    cairo_set_font_size(cr, L->font_size * room / ext.x_advance);
    cairo_text_extents(cr, title, &ext);
  }
  cairo_move_to(cr, (L->width - ext.x_advance) / 2, L->title_baseline);
  cairo_show_text(cr, title);
  cairo_set_font_size(cr, L->font_size);
}

/* Grid cell of a reference position, packed for sorting: neighbours found by binary search. */
typedef struct cell_node {
  int64_t key;
  int32_t node;
} cell_node;

static int compare_cells(const void *a, const void *b) {
  const cell_node *p = a, *q = b;
  return p->key < q->key ? -1 : p->key > q->key ? 1 : (p->node > q->node) - (p->node < q->node);
}

static int64_t cell_key(int64_t ix, int64_t iy) { return ix * 4194304 + iy; } /* 2^22 rows */

static int32_t find_cell(const cell_node *cells, int32_t n, int64_t key) {
  int32_t lo = 0, hi = n;
  while (lo < hi) {
    const int32_t mid = lo + (hi - lo) / 2;
    if (cells[mid].key < key) lo = mid + 1;
    else hi = mid;
  }
  return lo < n && cells[lo].key == key ? cells[lo].node : -1;
}

/* Lines between grid neighbours (right and up, in the reference grid) of different phases,
 * on the shared edge of their squares at the current positions. */
static void draw_phase_boundaries(cairo_t *cr, const layout *L, int32_t n, const double *points,
                                  const peri_png_axes *axes, double dot) {
  if (!axes || !axes->phase || !axes->reference || n <= 0 || !(dot > 0)) return;
  const double *ref = axes->reference;
  double x0 = INFINITY, y0 = INFINITY;
  for (int32_t i = 0; i < n; i++) x0 = fmin(x0, ref[3 * i]), y0 = fmin(y0, ref[3 * i + 1]);
  cell_node *cells = peri_malloc((size_t)n * sizeof *cells);
  int64_t *ix = peri_malloc((size_t)n * sizeof *ix), *iy = peri_malloc((size_t)n * sizeof *iy);
  for (int32_t i = 0; i < n; i++) {
    ix[i] = llround((ref[3 * i] - x0) / dot), iy[i] = llround((ref[3 * i + 1] - y0) / dot);
    cells[i] = (cell_node){cell_key(ix[i], iy[i]), i};
  }
  qsort(cells, (size_t)n, sizeof *cells, compare_cells);
  cairo_save(cr);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, fmax(1.0, 0.2 * dot * L->scale));
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_SQUARE);
  const double half = 0.5 * dot * L->scale;
  for (int32_t i = 0; i < n; i++)
    for (int dir = 0; dir < 2; dir++) {
      const int32_t j = find_cell(cells, n, cell_key(ix[i] + (dir == 0), iy[i] + (dir == 1)));
      if (j < 0 || axes->phase[j] == axes->phase[i]) continue;
      const double cx = L->plot_x + (0.5 * (points[3 * i] + points[3 * j]) - L->xmin) * L->scale;
      const double cy = L->plot_y + (L->ymax - 0.5 * (points[3 * i + 1] + points[3 * j + 1])) * L->scale;
      if (!isfinite(cx) || !isfinite(cy)) continue;
      if (dir == 0) { /* a vertical edge between i and its right neighbour */
        cairo_move_to(cr, cx, cy - half);
        cairo_line_to(cr, cx, cy + half);
      } else {
        cairo_move_to(cr, cx - half, cy);
        cairo_line_to(cr, cx + half, cy);
      }
    }
  cairo_stroke(cr);
  cairo_restore(cr);
  free(cells);
  free(ix);
  free(iy);
}

/* Saves through a temporary and a rename so a viewer never sees a half file. */
static int save_png(cairo_surface_t *surface, const char *path) {
  size_t path_len = strlen(path);
  char *tmp_path = peri_malloc(path_len + sizeof ".tmp");
  memcpy(tmp_path, path, path_len);
  memcpy(tmp_path + path_len, ".tmp", sizeof ".tmp");
  errno = 0;
  cairo_status_t st = cairo_surface_write_to_png(surface, tmp_path);
  int saved_errno = errno;
  if (st == CAIRO_STATUS_SUCCESS && rename(tmp_path, path) != 0) {
    saved_errno = errno;
    st = CAIRO_STATUS_WRITE_ERROR;
  }
  int status = 0;
  if (st != CAIRO_STATUS_SUCCESS) {
    remove(tmp_path);
    /* cairo's own message for a failed fopen/fwrite is vaguer than errno's */
    const char *reason = st == CAIRO_STATUS_WRITE_ERROR && saved_errno
                             ? strerror(saved_errno)
                             : cairo_status_to_string(st);
    peri_error("cannot write '%s': %s", path, reason);
    status = PERI_ERR_RUN;
  }
  free(tmp_path);
  return status;
}

int peri_png_write_field(const char *path, int32_t n, const double *points,
                         const double *values, double vmin, double vmax, double dot,
                         int width_px, const char *title) {
  return peri_png_write_field_axes(path, n, points, values, vmin, vmax, dot, width_px, title, NULL);
}

int peri_png_write_field_axes(const char *path, int32_t n, const double *points, const double *values,
                              double vmin, double vmax, double dot, int width_px, const char *title,
                              const peri_png_axes *axes) {
  if (width_px < 1 || n < 0 || (n > 0 && (!points || !values))) {
    peri_error("cannot write '%s': invalid picture (width %d px, %d nodes)", path, width_px,
               (int)n);
    return PERI_ERR_RUN;
  }
  resolve_range(n, values, &vmin, &vmax);
  layout L = compute_layout(n, points, dot, width_px, axes != NULL);

  cairo_surface_t *surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, L.width, L.height);
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
    peri_error("cannot write '%s': cannot create a %d x %d image: %s", path, L.width, L.height,
               cairo_status_to_string(cairo_surface_status(surface)));
    cairo_surface_destroy(surface);
    return PERI_ERR_RUN;
  }
  cairo_t *cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);

  draw_nodes(cr, &L, n, points, values, vmin, vmax, dot);
  draw_phase_boundaries(cr, &L, n, points, axes, dot);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, L.font_size);
  cairo_set_source_rgb(cr, 0, 0, 0);
  draw_title(cr, &L, title);
  draw_colour_bar(cr, &L, vmin, vmax);
  if (axes) draw_axes(cr, &L, axes);

  cairo_status_t draw_status = cairo_status(cr);
  cairo_destroy(cr);
  int status;
  if (draw_status != CAIRO_STATUS_SUCCESS) {
    peri_error("cannot write '%s': drawing failed: %s", path, cairo_status_to_string(draw_status));
    status = PERI_ERR_RUN;
  } else {
    cairo_surface_flush(surface);
    status = save_png(surface, path);
  }
  cairo_surface_destroy(surface);
  return status;
}
