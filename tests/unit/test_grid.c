/* Discretization: grid generation, Morton ordering, node files, particle storage. */
#include <criterion/criterion.h>
#include "scratch_dir.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "peri/discretize.h"
#include "peri/error.h"
#include "peri/nodefile.h"

static const double PI = 3.14159265358979323846;

static peri_shape box2(double x0, double y0, double x1, double y1) {
  peri_shape s;
  memset(&s, 0, sizeof s);
  s.kind = PERI_SHAPE_BOX;
  s.min[0] = x0, s.min[1] = y0, s.max[0] = x1, s.max[1] = y1;
  return s;
}

static peri_shape disk(double cx, double cy, double r) {
  peri_shape s;
  memset(&s, 0, sizeof s);
  s.kind = PERI_SHAPE_SPHERE;
  s.center[0] = cx, s.center[1] = cy, s.radius = r;
  return s;
}

/* Runs f with stderr captured into buf. */
static int captured(char *buf, size_t len, int (*f)(void *), void *arg) {
  fflush(stderr);
  FILE *tmp = tmpfile();
  cr_assert_not_null(tmp);
  int saved = dup(2);
  dup2(fileno(tmp), 2);
  int rc = f(arg);
  fflush(stderr);
  dup2(saved, 2);
  close(saved);
  rewind(tmp);
  size_t n = fread(buf, 1, len - 1, tmp);
  buf[n] = '\0';
  fclose(tmp);
  return rc;
}

Test(grid, rectangle_centres) {
  peri_fill fill = {.shape = box2(0, 0, 0.1, 0.04), .material = 3};
  peri_grid_params g = {.dim = 2,
                        .spacing = 1e-3,
                        .placement = PERI_PLACE_CENTERS,
                        .thickness = 2e-3,
                        .n_fill = 1,
                        .fill = &fill};
  peri_particles p;
  cr_assert_eq(peri_grid_generate(&p, &g), 4000);
  cr_assert_eq(p.n, 4000);
  cr_assert_eq(p.n_owned, 4000);
  double lo[2] = {1, 1}, hi[2] = {0, 0};
  for (int32_t i = 0; i < p.n; i++) {
    cr_assert_float_eq(p.volume[i], 1e-6 * 2e-3, 1e-20);
    cr_assert_eq(p.material[i], 3);
    cr_assert_eq(p.block[i], 1);
    cr_assert_eq(p.x[3 * i + 2], 0.0);
    for (int d = 0; d < 2; d++) {
      lo[d] = fmin(lo[d], p.x[3 * i + d]);
      hi[d] = fmax(hi[d], p.x[3 * i + d]);
    }
  }
  cr_assert_float_eq(lo[0], 0.5e-3, 1e-15);
  cr_assert_float_eq(lo[1], 0.5e-3, 1e-15);
  cr_assert_float_eq(hi[0], 0.0995, 1e-15);
  cr_assert_float_eq(hi[1], 0.0395, 1e-15);
  peri_particles_free(&p);
}

Test(grid, hole_removed) {
  const double dx = 1e-3, r = 0.01;
  peri_fill fill = {.shape = box2(0, 0, 0.1, 0.04)};
  peri_shape hole = disk(0.05, 0.02, r);
  peri_grid_params g = {.dim = 2,
                        .spacing = dx,
                        .placement = PERI_PLACE_CENTERS,
                        .thickness = 1,
                        .n_fill = 1,
                        .fill = &fill,
                        .n_remove = 1,
                        .remove = &hole};
  peri_particles p;
  int64_t n = peri_grid_generate(&p, &g);
  cr_assert_lt(n, 4000);
  double area = 0.1 * 0.04 - PI * r * r;
  cr_assert_lt(fabs((double)n * dx * dx - area), 2 * PI * r * dx, "%lld nodes", (long long)n);
  for (int32_t i = 0; i < p.n; i++) {
    double ddx = p.x[3 * i] - 0.05, ddy = p.x[3 * i + 1] - 0.02;
    cr_assert_gt(ddx * ddx + ddy * ddy, r * r * (1 - 1e-6));
  }
  peri_particles_free(&p);
}

Test(grid, polygon_triangle) {
  peri_fill fill;
  memset(&fill, 0, sizeof fill);
  double v[6] = {0, 0, 1, 0, 0, 1};
  fill.shape.kind = PERI_SHAPE_POLYGON;
  fill.shape.n_vertices = 3;
  fill.shape.vertices = v;
  peri_grid_params g = {.dim = 2,
                        .spacing = 0.01,
                        .placement = PERI_PLACE_CENTERS,
                        .thickness = 1,
                        .n_fill = 1,
                        .fill = &fill};
  peri_particles p;
  int64_t n = peri_grid_generate(&p, &g);
  cr_assert_leq(llabs(n - 5000), 50, "%lld nodes", (long long)n);
  peri_particles_free(&p);
}

Test(grid, last_fill_wins_and_lattice) {
  peri_fill fill[2] = {{.shape = box2(0, 0, 4, 2), .material = 0},
                       {.shape = box2(2, 0, 4, 2), .material = 1}};
  peri_grid_params g = {.dim = 2,
                        .spacing = 1,
                        .placement = PERI_PLACE_LATTICE,
                        .thickness = 1,
                        .n_fill = 2,
                        .fill = fill};
  peri_particles p;
  cr_assert_eq(peri_grid_generate(&p, &g), 15);
  for (int32_t i = 0; i < p.n; i++) {
    int right = p.x[3 * i] >= 2;
    cr_assert_eq(p.material[i], right);
    cr_assert_eq(p.block[i], right + 1);
    cr_assert_eq(p.x[3 * i], round(p.x[3 * i]));
  }
  peri_particles_free(&p);
  /* a given origin shifts the lattice */
  g.origin_given = true;
  g.origin[0] = 0.5;
  g.origin[1] = 0.5;
  cr_assert_eq(peri_grid_generate(&p, &g), 8);
  peri_particles_free(&p);
}

Test(grid, one_and_three_d) {
  peri_fill f1 = {.shape = box2(0, 0, 1, 0)};
  peri_grid_params g = {.dim = 1,
                        .spacing = 0.1,
                        .placement = PERI_PLACE_CENTERS,
                        .cross_section = 1e-4,
                        .n_fill = 1,
                        .fill = &f1};
  peri_particles p;
  cr_assert_eq(peri_grid_generate(&p, &g), 10);
  cr_assert_float_eq(p.volume[0], 1e-5, 1e-18);
  cr_assert_eq(p.x[1], 0.0);
  peri_particles_free(&p);

  peri_fill f3;
  memset(&f3, 0, sizeof f3);
  f3.shape.kind = PERI_SHAPE_SPHERE;
  f3.shape.radius = 1;
  g = (peri_grid_params){
      .dim = 3, .spacing = 0.1, .placement = PERI_PLACE_CENTERS, .n_fill = 1, .fill = &f3};
  int64_t n = peri_grid_generate(&p, &g);
  cr_assert_lt(fabs((double)n * 1e-3 - 4.0 / 3.0 * PI), 4 * PI * 0.1, "%lld", (long long)n);
  cr_assert_float_eq(p.volume[0], 1e-3, 1e-15);
  peri_particles_free(&p);
}

static int gen_all(void *arg) {
  peri_particles p;
  int64_t n = peri_grid_generate(&p, arg);
  peri_particles_free(&p);
  return (int)n;
}

Test(grid, unbounded_fill_is_an_error) {
  peri_fill f;
  memset(&f, 0, sizeof f);
  f.shape.kind = PERI_SHAPE_ALL;
  peri_grid_params g = {.dim = 2, .spacing = 1, .n_fill = 1, .fill = &f};
  char msg[512];
  cr_assert_eq(captured(msg, sizeof msg, gen_all, &g), -1);
  cr_assert(strstr(msg, "unbounded"), "%s", msg);
  f.shape = box2(0, 0, 1e6, 1e6);
  g.spacing = 1e-2;
  cr_assert_eq(captured(msg, sizeof msg, gen_all, &g), -1);
  cr_assert(strstr(msg, "2^31"), "%s", msg);
}

Test(sfc, morton_is_local_permutation) {
  const double dx = 1e-3;
  peri_fill fill = {.shape = box2(0, 0, 0.1, 0.04)};
  peri_grid_params g = {.dim = 2,
                        .spacing = dx,
                        .placement = PERI_PLACE_CENTERS,
                        .thickness = 1,
                        .n_fill = 1,
                        .fill = &fill};
  peri_particles p;
  cr_assert_eq(peri_grid_generate(&p, &g), 4000);
  peri_particles_alloc_state(&p);
  for (int32_t i = 0; i < p.n; i++) p.damage[i] = i;
  int32_t *perm = malloc(sizeof(int32_t) * (size_t)p.n);
  peri_sfc_order(&p, dx, perm);
  char *seen = calloc((size_t)p.n, 1);
  for (int32_t k = 0; k < p.n; k++) {
    cr_assert(perm[k] >= 0 && perm[k] < p.n);
    cr_assert(!seen[perm[k]], "index %d twice", perm[k]);
    seen[perm[k]] = 1;
  }
  double *x0 = malloc(sizeof(double) * 3 * (size_t)p.n);
  memcpy(x0, p.x, sizeof(double) * 3 * (size_t)p.n);
  peri_particles_permute(&p, perm);
  double sum = 0;
  for (int32_t k = 0; k < p.n; k++) {
    for (int d = 0; d < 3; d++) cr_assert_eq(p.x[3 * k + d], x0[3 * perm[k] + d]);
    cr_assert_eq(p.damage[k], (double)perm[k]);
    if (k) sum += hypot(p.x[3 * k] - p.x[3 * k - 3], p.x[3 * k + 1] - p.x[3 * k - 2]);
  }
  double mean = sum / (p.n - 1);
  cr_assert_lt(mean, 3 * dx, "mean step %g dx", mean / dx);
  /* deterministic */
  int32_t *perm2 = malloc(sizeof(int32_t) * (size_t)p.n);
  peri_sfc_order(&p, dx, perm2);
  peri_sfc_order(&p, dx, perm);
  cr_assert(!memcmp(perm, perm2, sizeof(int32_t) * (size_t)p.n));
  free(perm2);
  free(x0);
  free(seen);
  free(perm);
  peri_particles_free(&p);
}

/* Rows along the longest axis: on a 30 x 6 x 4 lattice every node but the last of a row
 * is followed by its +x neighbour, so the kernels find runs of translated families. */
Test(sfc, rows_along_longest_axis) {
  const double dx = 1e-3;
  peri_particles p;
  peri_particles_init(&p, 720);
  for (int k = 0; k < 4; k++)
    for (int j = 0; j < 6; j++)
      for (int i = 0; i < 30; i++) {
        const double c[3] = {j * dx, i * dx, k * dx}; /* the long axis is y */
        peri_particles_add(&p, c, 1, 0, 1);
      }
  int32_t *perm = malloc(sizeof(int32_t) * (size_t)p.n);
  peri_sfc_order(&p, dx, perm);
  int steps_along_row = 0;
  for (int32_t k = 1; k < p.n; k++) {
    const double *a = &p.x[3 * perm[k - 1]], *b = &p.x[3 * perm[k]];
    if (a[0] == b[0] && a[2] == b[2] && fabs(b[1] - a[1] - dx) < 1e-12) steps_along_row++;
  }
  cr_assert_eq(steps_along_row, 24 * 29);
  free(perm);
  peri_particles_free(&p);
}

/* Two columns of nodes along z in one cell across the rows (x 0 and 7/16 of the spacing: both
 * round to cell 0), their nodes moved by up to 10^-3 of the spacing as Peridigm's cylinder
 * does, the second column on a boundary of the order's fine cells (sixteenths of the spacing
 * from the smallest x, 0): each column stays one run of consecutive nodes in z order
 * (interleaved, or one column cut in two, no eight consecutive nodes have translated
 * families). */
Test(sfc, columns_in_one_cell_stay_apart) {
  const double dx = 1e-3, jitter = 1e-3 * dx;
  peri_particles p;
  peri_particles_init(&p, 80);
  unsigned seed = 7;
  for (int k = 0; k < 40; k++)
    for (int c = 0; c < 2; c++) {
      seed = seed * 1103515245u + 12345u;
      const double wobble = ((double)(seed >> 8 & 0xffff) / 65535.0 - 0.5) * 2.0 * jitter;
      const double x = c == 0 ? (k == 0 ? 0.0 : fabs(wobble)) : 7.0 / 16.0 * dx + wobble;
      const double c3[3] = {x, 0.0, k * dx + (k % 3 - 1) * jitter};
      peri_particles_add(&p, c3, 1, 0, 1);
    }
  int32_t *perm = malloc(sizeof(int32_t) * (size_t)p.n);
  peri_sfc_order(&p, dx, perm);
  /* the first 40 nodes one column, in z order, then the other */
  for (int32_t k = 0; k < p.n; k++) {
    const int column = k < 40 ? perm[0] % 2 : 1 - perm[0] % 2;
    cr_assert_eq(perm[k] % 2, column, "node %d of the order is in the other column", k);
    if (k % 40) cr_assert_gt(p.x[3 * perm[k] + 2], p.x[3 * perm[k - 1] + 2], "node %d of the order", k);
  }
  free(perm);
  peri_particles_free(&p);
}

Test(sfc, ties_by_index) {
  peri_particles p;
  peri_particles_init(&p, 3);
  const double a[3] = {1, 1, 1}, b[3] = {0, 0, 0};
  peri_particles_add(&p, a, 1, 0, 1);
  peri_particles_add(&p, a, 1, 0, 1);
  peri_particles_add(&p, b, 1, 0, 1);
  int32_t perm[3];
  peri_sfc_order(&p, 1.0, perm);
  cr_assert_eq(perm[0], 2);
  cr_assert_eq(perm[1], 0);
  cr_assert_eq(perm[2], 1);
  peri_particles_free(&p);
}


Test(nodefile, read_2d_and_3d, .init = make_tmpdir, .fini = remove_tmpdir) {
  char path[128];
  snprintf(path, sizeof path, "%s/nodes2.txt", tmpdir);
  write_file(path, "# x y block volume\n"
                   "0 0 1 1e-6\n"
                   "\n"
                   "  1e-3\t0 2 1e-6   # second block\r\n"
                   "2e-3 1e-3 1 2e-6\n");
  const int32_t map[2] = {5, 7};
  peri_particles p;
  cr_assert_eq(peri_nodefile_read(&p, path, 2, map, 2), PERI_OK);
  cr_assert_eq(p.n, 3);
  cr_assert_eq(p.n_owned, 3);
  cr_assert_eq(p.dim, 2);
  cr_assert_eq(p.x[3], 1e-3);
  cr_assert_eq(p.x[7], 1e-3);
  cr_assert_eq(p.x[8], 0.0);
  cr_assert_eq(p.block[1], 2);
  cr_assert_eq(p.material[1], 7);
  cr_assert_eq(p.material[2], 5);
  cr_assert_eq(p.volume[2], 2e-6);
  peri_particles_free(&p);

  snprintf(path, sizeof path, "%s/nodes3.txt", tmpdir);
  write_file(path, "0 0 0 1 1e-9\n0 0 1e-3 1 1e-9\n");
  cr_assert_eq(peri_nodefile_read(&p, path, 3, NULL, 0), PERI_OK);
  cr_assert_eq(p.n, 2);
  cr_assert_eq(p.x[5], 1e-3);
  cr_assert_eq(p.material[0], 0);
  peri_particles_free(&p);
}

typedef struct {
  const char *path;
  int dim;
  int n_blocks;
} read_args;

static int read_it(void *arg) {
  read_args *a = arg;
  const int32_t map[2] = {0, 1};
  peri_particles p;
  int rc = peri_nodefile_read(&p, a->path, a->dim, map, a->n_blocks);
  peri_particles_free(&p);
  return rc;
}

Test(nodefile, errors, .init = make_tmpdir, .fini = remove_tmpdir) {
  char path[128], msg[1024], want[256];
  snprintf(path, sizeof path, "%s/bad.txt", tmpdir);
  read_args a = {path, 3, 2};

  write_file(path, "0 0 0 1 1e-9\n# comment\n0 0 1 1e-9\n");
  cr_assert_eq(captured(msg, sizeof msg, read_it, &a), 2);
  snprintf(want, sizeof want, "%s:3: expected 5 numbers (x y z block volume), got 4", path);
  cr_assert(strstr(msg, want), "%s", msg);

  write_file(path, "0 0 0 1 abc\n");
  cr_assert_eq(captured(msg, sizeof msg, read_it, &a), 2);
  snprintf(want, sizeof want, "%s:1: expected 5 numbers (x y z block volume), got 'abc'", path);
  cr_assert(strstr(msg, want), "%s", msg);

  write_file(path, "0 0 0 3 1e-9\n");
  cr_assert_eq(captured(msg, sizeof msg, read_it, &a), 2);
  snprintf(want, sizeof want, "%s:1:", path);
  cr_assert(strstr(msg, want) && strstr(msg, "block 3"), "%s", msg);

  write_file(path, "0 0 0 1.5 1e-9\n");
  cr_assert_eq(captured(msg, sizeof msg, read_it, &a), 2);

  write_file(path, "0 0 0 1 0\n");
  cr_assert_eq(captured(msg, sizeof msg, read_it, &a), 2);
  cr_assert(strstr(msg, "volume"), "%s", msg);

  write_file(path, "# nothing\n");
  cr_assert_eq(captured(msg, sizeof msg, read_it, &a), 2);

  a.dim = 2;
  write_file(path, "0 0 0 1 1e-9\n");
  cr_assert_eq(captured(msg, sizeof msg, read_it, &a), 2);
  snprintf(want, sizeof want, "%s:1: expected 4 numbers (x y block volume), got 5", path);
  cr_assert(strstr(msg, want), "%s", msg);

  snprintf(path, sizeof path, "%s/missing.txt", tmpdir);
  cr_assert_eq(captured(msg, sizeof msg, read_it, &a), 2);
  cr_assert(strstr(msg, "missing.txt"), "%s", msg);
}

Test(particles, grow_and_state) {
  peri_particles p;
  peri_particles_init(&p, 2);
  for (int i = 0; i < 3000; i++) {
    const double x[3] = {i, -i, 99};
    cr_assert_eq(peri_particles_add(&p, x, 1.0, i % 3, 1), i);
    if (i == 1500) {
      peri_particles_alloc_state(&p);
      p.u[3 * i] = 4.0;
    }
  }
  cr_assert_eq(p.n, 3000);
  cr_assert_geq(p.capacity, 3000);
  cr_assert_eq(p.x[3 * 2999 + 1], -2999.0);
  cr_assert_eq(p.x[3 * 2999 + 2], 0.0); /* beyond dim */
  cr_assert_eq(p.u[3 * 1500], 4.0);
  cr_assert_eq(p.u[3 * 2999], 0.0);
  cr_assert_eq(p.damage[2999], 0.0);
  cr_assert_eq(p.material[2999], 2);
  peri_particles_free(&p);
  cr_assert_eq(p.n, 0);
  cr_assert_null(p.x);
}

/* Exact lattice coordinates (peri_exact_coordinate): on a grid every neighbour offset
 * x_{k+n} - x_k is one number whatever k (each sum and product exact), which the bond loops'
 * offset tables rely on, and each coordinate moves from o + (k + off) dx by less than the
 * rounding of dx/2 to the axis' quantum q = 2^(ilogb(extent) - 51), (2|k| + 2) q, plus the
 * rounding of the formula itself. */
static void check_exact_axis(double x0, double x1, double dx, peri_placement placement) {
  peri_fill fill = {.shape = box2(x0, x0, x1, x1), .material = 0};
  peri_grid_params g = {.dim = 2, .spacing = dx, .placement = placement, .thickness = 1.0, .n_fill = 1, .fill = &fill};
  peri_particles p;
  cr_assert_gt(peri_grid_generate(&p, &g), 0);
  peri_exact_axis axis[3];
  cr_assert(peri_grid_exact_axes(&g, &p, axis));
  const peri_exact_axis *a = &axis[0];
  cr_assert_gt(a->half, 0.0, "an exact form for a grid of %g cells", (x1 - x0) / dx);
  const int n_row = (int)((x1 - x0) / dx + 0.5) + 1;
  double *row = calloc((size_t)n_row, sizeof *row);
  int count = 0;
  double extent = 0.0;
  for (int32_t i = 0; i < p.n && count < n_row; i++)
    if (p.x[3 * (size_t)i + 1] == p.x[1]) row[count++] = p.x[3 * (size_t)i], extent = fmax(extent, fabs(p.x[3 * (size_t)i]));
  extent += 2 * dx;
  const double q = ldexp(1.0, ilogb(extent) - 51);
  for (int k = 0; k < count; k++) {
    const double exact = peri_exact_coordinate(a, row[k]);
    const double kk = fabs((row[k] - a->o) / dx - a->off);
    cr_assert_leq(fabs(exact - row[k]), (2 * kk + 2) * q + 4 * 2.2e-16 * fabs(row[k]), "node %d at %.17g: %.17g", k,
                  row[k], exact);
  }
  for (int n = 1; n <= 4; n++)
    for (int k = 0; k + n < count; k++)
      cr_assert_eq(peri_exact_coordinate(a, row[k + n]) - peri_exact_coordinate(a, row[k]),
                   peri_exact_coordinate(a, row[n]) - peri_exact_coordinate(a, row[0]), "offset %d at node %d", n, k);
  /* a coordinate off the lattice is left as it is */
  cr_assert_eq(peri_exact_coordinate(a, row[0] + 0.25 * dx), row[0] + 0.25 * dx);
  free(row);
  peri_particles_free(&p);
}

Test(grid, exact_lattice_offsets) {
  check_exact_axis(-0.005, 0.005, 1.25e-4, PERI_PLACE_LATTICE);  /* the LAMMPS problem's lattice */
  check_exact_axis(-5.13e-7, 1.007e-6, 1.9e-8, PERI_PLACE_CENTERS); /* the scratch decks' cells */
  check_exact_axis(0.0, 0.1, 1e-3, PERI_PLACE_CENTERS);
}
