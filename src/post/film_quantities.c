/* Films on substrates and interfaces between materials (include/peri/film_quantities.h,
 * docs/thin_films.md). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/film_quantities.h"

void peri_interface_flags(const peri_sim *s, int32_t *flag) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    int32_t on = 0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1] && !on; ++k) on = p->material[b->neighbor[k]] != p->material[i];
    flag[i] = on;
  }
}

/* The area of a node's face: dx^2 in 3D, dx times the thickness in 2D (V/dx). */
static double face_area(const peri_sim *s, int32_t i) {
  const double dx = s->disc.family.spacing;
  if (s->disc.geom.dim == 3) return dx * dx;
  return s->disc.p.volume[i] / dx; /* 2D: dx * thickness; 1D: the cross-section */
}

void peri_interface_history(const peri_sim *s, long *broken, double *max_stress) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  long n_broken = 0;
  double largest = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : n_broken) reduction(max : largest)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      if (p->material[j] == p->material[i]) continue;
      if (b->broken[k]) {
        ++n_broken;
        continue;
      }
      double y[3];
      for (int c = 0; c < 3; ++c) y[c] = p->x[3 * j + c] + p->u[3 * j + c] - p->x[3 * i + c] - p->u[3 * i + c];
      const double r = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
      if (!(r > 0.0)) continue;
      const double beta = peri_bonds_beta(b, peri_bond_length(p->x, i, j));
      /* tension only: the bonds that hold the film down and break when it lifts off */
      const double force = s->mat.model->pair_force(s, i, k, r) * beta * p->volume[i] * p->volume[j];
      const double stress = force / face_area(s, i);
      if (stress > largest) largest = stress;
    }
  }
  *broken = peri_comm_sum_long(n_broken);
  *max_stress = peri_comm_max(largest);
}

double peri_region_strain_energy(const peri_sim *s, int region) {
  const peri_particles *p = &s->disc.p;
  const peri_region *r = &s->cond.regions[region];
  double *terms = peri_calloc((size_t)(p->n_owned > 0 ? p->n_owned : 1), sizeof(double)), sum = 0.0;
  for (int32_t a = 0; a < r->count; ++a) {
    const int32_t i = r->nodes[a];
    terms[i] = p->energy[i] * p->volume[i];
  }
  peri_sum_owned(s, terms, 1, &sum); /* fixed-order blocks: the same for any thread or rank count */
  free(terms);
  return sum;
}

typedef struct column {
  double x, top, w; /* column position, reference height of its top node, that node's deflection */
} column;

static int by_x(const void *a, const void *b) {
  const double d = ((const column *)a)->x - ((const column *)b)->x;
  return (d > 0) - (d < 0);
}

/* Amplitude and wavelength of the columns' deflection profile (rank 0). */
static void profile_spectrum(column *col, int n, double dx, double *amplitude, double *wavelength) {
  *amplitude = 0.0;
  *wavelength = 0.0;
  if (n < 4) return;
  qsort(col, (size_t)n, sizeof *col, by_x);
  /* remove the least-squares line: a rigid tilt or a uniform sinking is no wrinkle */
  double sx = 0, sw = 0, sxx = 0, sxw = 0;
  for (int c = 0; c < n; ++c) sx += col[c].x, sw += col[c].w, sxx += col[c].x * col[c].x, sxw += col[c].x * col[c].w;
  const double det = n * sxx - sx * sx;
  const double slope = det > 0 ? (n * sxw - sx * sw) / det : 0.0, mean = (sw - slope * sx) / n;
  /* Hann window against the leakage of a profile that is not periodic in the window */
  double *w = peri_malloc(sizeof(double) * (size_t)n), gain = 0.0;
  for (int c = 0; c < n; ++c) {
    const double hann = 0.5 - 0.5 * cos(2.0 * M_PI * (c + 0.5) / n);
    w[c] = hann * (col[c].w - mean - slope * col[c].x);
    gain += hann;
  }
  const int half = n / 2;
  double *mag = peri_calloc((size_t)half + 2, sizeof(double));
  int peak = 0;
  for (int k = 1; k <= half; ++k) { /* a direct transform: a few hundred columns */
    double re = 0.0, im = 0.0;
    for (int c = 0; c < n; ++c) {
      const double phase = 2.0 * M_PI * (double)k * c / n;
      re += w[c] * cos(phase);
      im -= w[c] * sin(phase);
    }
    mag[k] = sqrt(re * re + im * im);
    if (!peak || mag[k] > mag[peak]) peak = k;
  }
  if (peak && mag[peak] > 0.0) {
    /* Gaussian interpolation through the peak and its neighbours (exact for a Hann-windowed
     * sine to a few per cent of a bin) */
    double kf = peak;
    if (peak > 1 && peak < half && mag[peak - 1] > 0.0 && mag[peak + 1] > 0.0) {
      const double a = log(mag[peak - 1]), b0 = log(mag[peak]), c0 = log(mag[peak + 1]);
      const double denom = a - 2.0 * b0 + c0; /* < 0 at a maximum; the shift is then within half a bin */
      if (denom < 0.0) kf += 0.5 * (a - c0) / denom;
    }
    /* the amplitude of the least-squares sine of that wave number through the detrended
     * profile (the window's scalloping would lower it by up to 15% between bins) */
    const double omega = 2.0 * M_PI * kf / (n * dx);
    double cc = 0, ss = 0, cs = 0, wc = 0, ws = 0;
    for (int c = 0; c < n; ++c) {
      const double co = cos(omega * col[c].x), si = sin(omega * col[c].x), d = col[c].w - mean - slope * col[c].x;
      cc += co * co, ss += si * si, cs += co * si, wc += d * co, ws += d * si;
    }
    const double dd = cc * ss - cs * cs;
    if (dd > 0.0) {
      const double a = (wc * ss - ws * cs) / dd, b = (ws * cc - wc * cs) / dd;
      *amplitude = sqrt(a * a + b * b);
    } else {
      *amplitude = 2.0 * mag[peak] / gain;
    }
    *wavelength = n * dx / kf;
  }
  free(mag);
  free(w);
}

void peri_wrinkle_profile(const peri_sim *s, int region, double *amplitude, double *wavelength) {
  const peri_particles *p = &s->disc.p;
  const peri_region *r = &s->cond.regions[region];
  const int up = s->disc.geom.dim == 3 ? 2 : 1; /* the transverse axis */
  const int64_t all = peri_global_nodes(s);
  const size_t room = (size_t)(p->n_owned > 0 ? p->n_owned : 1), all_room = (size_t)(all > 0 ? all : 1);
  /* per node: x, height, deflection, in the film (1) or not (0) */
  double *local = peri_calloc(4 * room, sizeof(double));
  for (int32_t a = 0; a < r->count; ++a) {
    const int32_t i = r->nodes[a];
    if (p->flags[i] & PERI_NODE_FICTITIOUS) continue;
    local[4 * i] = p->x[3 * i];
    local[4 * i + 1] = p->x[3 * i + up];
    local[4 * i + 2] = p->u[3 * i + up];
    local[4 * i + 3] = 1.0;
  }
  const bool root = peri_comm_rank() == 0;
  double *every = root ? peri_malloc(sizeof(double) * 4 * all_room) : NULL;
  peri_gather_owned(s, local, 4, every);
  double result[2] = {0.0, 0.0};
  if (root) {
    const double dx = s->disc.family.spacing;
    column *col = peri_malloc(sizeof(column) * all_room);
    int n = 0;
    double x0 = INFINITY;
    for (int64_t i = 0; i < all; ++i)
      if (every[4 * i + 3] > 0.0 && every[4 * i] < x0) x0 = every[4 * i];
    /* columns by lattice index; node i joins column round((x - x0)/dx) */
    int64_t n_cols = 0;
    for (int64_t i = 0; i < all; ++i)
      if (every[4 * i + 3] > 0.0) {
        const int64_t c = llround((every[4 * i] - x0) / dx);
        if (c + 1 > n_cols) n_cols = c + 1;
      }
    int *slot = peri_malloc(sizeof(int) * (size_t)(n_cols > 0 ? n_cols : 1));
    for (int64_t c = 0; c < n_cols; ++c) slot[c] = -1;
    for (int64_t i = 0; i < all; ++i) {
      if (!(every[4 * i + 3] > 0.0)) continue;
      const int64_t c = llround((every[4 * i] - x0) / dx);
      if (slot[c] < 0) {
        slot[c] = n++;
        col[slot[c]] = (column){.x = x0 + (double)c * dx, .top = -INFINITY};
      }
      column *cc = &col[slot[c]];
      if (every[4 * i + 1] > cc->top) cc->top = every[4 * i + 1], cc->w = every[4 * i + 2];
    }
    profile_spectrum(col, n, dx, &result[0], &result[1]);
    free(slot);
    free(col);
  }
  peri_comm_broadcast_doubles(result, 2);
  *amplitude = result[0];
  *wavelength = result[1];
  free(every);
  free(local);
}

void peri_wrinkle_onsets(const double *t, const double *energy, const double *broken, int n, int *wrinkling,
                         int *delamination) {
  *wrinkling = *delamination = -1;
  /* rate[k]: over the step that ends at row k (k >= 1) */
  double *rate = peri_malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  for (int k = 1; k < n; ++k) rate[k] = t[k] > t[k - 1] ? (energy[k] - energy[k - 1]) / (t[k] - t[k - 1]) : rate[k - 1];
  for (int k = 2; k + 1 < n && *wrinkling < 0; ++k)
    if (rate[k] > rate[k - 1] && rate[k] >= rate[k + 1]) *wrinkling = k;
  free(rate);
  for (int k = 0; k < n && *delamination < 0; ++k)
    if (broken[k] > 0.0) *delamination = k;
}
