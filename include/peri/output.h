/* Writers. They receive a frame (positions and named fields) and never reach into solver
 * state. */
#ifndef PERI_OUTPUT_H
#define PERI_OUTPUT_H
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

/* A named per-node field: ncomp = 1 (scalar), 3 (vector, stride 3) or 9 (tensor). Exactly one of
 * data / idata is set (idata: int32 per node, written as Int32). */
typedef struct peri_field {
  const char *name;
  int ncomp;
  const double *data;
  const int32_t *idata;
} peri_field;

/* Writes a VTU (VTK XML UnstructuredGrid) file with n points at `points` ([3n]) as
 * VTK_VERTEX cells, and the fields as PointData. Data are base64-encoded binary,
 * zlib-compressed when `compress` (ParaView reads both). Returns 0 or PERI_ERR_RUN with a
 * message naming the path. */
int peri_vtu_write(const char *path, int32_t n, const double *points,
                   const peri_field *fields, int n_fields, bool compress);

/* The same with the frame's time as the FieldData array TimeValue (NaN: none). */
int peri_vtu_write_at(const char *path, double time, int32_t n, const double *points,
                      const peri_field *fields, int n_fields, bool compress);

/* A parallel VTU index (.pvtu) of the pieces written by the ranks of a distributed run
 * (`pieces`: .vtu paths relative to the .pvtu; `fields`: names and types, no data needed). */
int peri_pvtu_write(const char *path, const char *const *pieces, int n_pieces, const peri_field *fields,
                    int n_fields);

/* A ParaView .pvd collection, rewritten whole after each added frame so that a run that
 * stops midway leaves a valid file. */
typedef struct peri_pvd peri_pvd;
peri_pvd *peri_pvd_open(const char *path);
/* `file` is relative to the .pvd's directory. */
int peri_pvd_add(peri_pvd *pvd, double time, const char *file);
void peri_pvd_close(peri_pvd *pvd);

/* history.csv: a header line of column names then one line per call; flushed at every
 * line so a run that stops midway keeps what it wrote. */
typedef struct peri_history peri_history;
peri_history *peri_history_open(const char *path, int n_columns, const char *const *names);
/* Opens <directory>/history.csv with the n column names and frees names (each name and
 * the array), whether or not the file opened. */
peri_history *peri_history_open_in(const char *directory, int n_columns, char **names);
int peri_history_write(peri_history *h, const double *values);
/* Significant digits of the values written from now on (10 unless set; 17 keeps a double). */
void peri_history_set_digits(peri_history *h, int digits);
/* <directory>/history_units.csv beside history.csv: the same header line, then one line with
 * the unit of each column, so that readers of history.csv are unchanged. Returns 0 or
 * PERI_ERR_RUN with a message. */
int peri_history_units_write(const char *directory, int n_columns, char *const *names, const char *const *units);
void peri_history_close(peri_history *h);

/* PNG picture of a scalar field on a 2D node cloud (x,y of `points`, [3n]): each node a
 * filled square of side `dot` (in model units) coloured by value on a perceptual colour map
 * (viridis) between vmin and vmax (if vmin >= vmax the data range is used), white
 * background, a colour bar with min/max labels and a title, drawn with cairo. The image is
 * `width_px` wide and keeps the aspect ratio of the node cloud. Returns 0 or PERI_ERR_RUN. */
int peri_png_write_field(const char *path, int32_t n, const double *points,
                         const double *values, double vmin, double vmax, double dot,
                         int width_px, const char *title);

/* The same with axes: a frame around the node cloud with ticks and values in model units, the
 * axis labels (e.g. "x [m]"), ticks at round values on the colour bar and the value's name
 * and unit under it (e.g. "damage [1]"). NULL axes: as peri_png_write_field. */
typedef struct peri_png_axes {
  const char *x_label, *y_label, *value_label;
  /* Optional (NULL: none): a phase per node (e.g. its material) and the nodes' reference
   * positions [3n] on a grid of spacing `dot`: a black line is drawn between neighbouring grid
   * nodes of different phases (the phase boundaries of a multi-material body). */
  const int32_t *phase;
  const double *reference;
} peri_png_axes;
int peri_png_write_field_axes(const char *path, int32_t n, const double *points, const double *values,
                              double vmin, double vmax, double dot, int width_px, const char *title,
                              const peri_png_axes *axes);

/* Creates a directory and its parents (like mkdir -p). Returns 0 or PERI_ERR_RUN. */
int peri_mkdir_p(const char *path);

#endif
