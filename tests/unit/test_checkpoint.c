/* Checkpoints (docs/restart.md): a state written and read back is the same bit for bit;
 * a checkpoint of another discretization or model is refused; the history.csv and .pvd
 * readers give back exactly what the writers wrote. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <criterion/criterion.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "peri/checkpoint.h"
#include "peri/checkpoint_schedule.h"
#include "peri/error.h"
#include "peri/output.h"
#include "peri/setup.h"
#include "peri/solver.h"
#include "peri/thermal.h"
#include "support.h"

/* 2D LPS with every optional array: dilatation, weighted volume, P, the compression-
 * dependent critical stretch (smin, s0) and one-way heat conduction (T, its own cut flags,
 * thermal strain). 12 x 8 nodes. */
static const char *deck =
    "dimension: 2\n"
    "plane: stress\n"
    "materials:\n"
    "  m: {model: lps, density: 2440, youngs_modulus: 72e9, poisson_ratio: 0.22,\n"
    "      critical_stretch: {s00: 0.0005, alpha: 0.25}, conductivity: 1.4, specific_heat: 800,\n"
    "      thermal_expansion: 8e-6}\n"
    "discretization: {spacing: %s, m: 3, thickness: 0.001,\n"
    "                 fill: [{shape: rectangle, min: [0, 0], max: [0.012, 0.008]}]}\n"
    "thermal: {initial_temperature: 300, coupling: one_way}\n"
    "solver: {type: explicit, steps: 100}\n"
    "output: {picture: false}\n";

static void build(peri_sim *s, const char *spacing) {
  char text[2048];
  snprintf(text, sizeof text, deck, spacing);
  cr_assert_eq(sim_from_string(s, text), PERI_OK, "deck:\n%s", text);
}

static char scratch[64];
static char path[128];

static void setup(void) {
  strcpy(scratch, "/tmp/peri_test_checkpoint_XXXXXX");
  cr_assert_not_null(mkdtemp(scratch));
  snprintf(path, sizeof path, "%s/state.h5", scratch);
}

static void teardown(void) {
  char cmd[160];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", scratch);
  cr_assert_eq(system(cmd), 0);
}

/* Deterministic values that use every bit of the mantissa (xorshift64). */
static uint64_t rng = 88172645463325252ULL;
static double noise(void) {
  rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
  return ((double)(rng >> 11) / 9007199254740992.0 - 0.5) * 1e-3;
}

static void fill(double *a, size_t n) {
  for (size_t k = 0; k < n; ++k) a[k] = noise();
}

static void scramble(peri_sim *s) {
  const size_t n = (size_t)s->disc.p.n_owned;
  peri_particles *p = &s->disc.p;
  double *arrays1[] = {p->damage, p->theta, p->wvol, p->pstate, p->smin, s->mat.s0_node, s->state.thermal_strain,
                       s->thermal->T};
  for (size_t k = 0; k < sizeof arrays1 / sizeof arrays1[0]; ++k) {
    cr_assert_not_null(arrays1[k], "array %zu missing: the deck should allocate it", k);
    fill(arrays1[k], n);
  }
  fill(p->u, 3 * n);
  fill(p->v, 3 * n);
  fill(p->f, 3 * n);
  s->state.step_load = peri_malloc(sizeof(double) * 3 * n);
  fill(s->state.step_load, 3 * n);
  for (int64_t k = 0; k < s->disc.bonds.n_bonds; ++k) {
    s->disc.bonds.broken[k] = (uint8_t)((rng = rng * 6364136223846793005ULL + 1) >> 63);
    s->thermal->cut[k] = (uint8_t)((rng = rng * 6364136223846793005ULL + 1) >> 63);
  }
  s->state.time = 1.2345678901234567e-5;
  s->state.step = 77;
  s->state.external_work = noise();
  for (int d = 0; d < 3; ++d) s->cond.indenter.force[d] = noise();
  s->solver.qs.reference = noise(), s->solver.qs.last_reference = noise(), s->solver.qs.residual = noise();
  s->solver.qs.iterations = 12345, s->solver.qs.solves = 67, s->solver.qs.force_evaluations = 8910, s->solver.qs.cutbacks = 3;
  s->thermal->time = 1.1e-5;
  s->thermal->every = 7;
  s->thermal->substeps = 2;
}

static void expect_same(const double *a, const double *b, size_t n, const char *what) {
  cr_assert_not_null(a);
  cr_assert_not_null(b);
  cr_expect_eq(memcmp(a, b, sizeof(double) * n), 0, "%s differs after the round trip", what);
}

Test(checkpoint, round_trip_is_bitwise, .init = setup, .fini = teardown) {
  if (!peri_checkpoint_supported()) cr_skip_test("built without HDF5");
  peri_sim a, b;
  build(&a, "0.001");
  build(&b, "0.001");
  cr_assert(a.thermal && a.thermal->own_cut, "one-way coupling keeps its own cut flags");
  scramble(&a);
  const peri_checkpoint_progress done = {0, 0}; /* no output to continue */
  cr_assert_eq(peri_checkpoint_write(&a, path, &done), PERI_OK);
  cr_assert_eq(access(path, F_OK), 0);
  char tmp[160];
  snprintf(tmp, sizeof tmp, "%s.tmp", path);
  cr_expect_neq(access(tmp, F_OK), 0, "the temporary file is renamed away");

  cr_assert_eq(peri_restart_load(&b, path), PERI_OK);
  peri_apply_initial_conditions(&b);
  peri_restart_apply(&b);
  const size_t n = (size_t)a.disc.p.n_owned, nb = (size_t)a.disc.bonds.n_bonds;
  expect_same(a.disc.p.u, b.disc.p.u, 3 * n, "u");
  expect_same(a.disc.p.v, b.disc.p.v, 3 * n, "v");
  expect_same(a.disc.p.f, b.disc.p.f, 3 * n, "f");
  expect_same(a.state.step_load, b.state.step_load, 3 * n, "step_load");
  expect_same(a.disc.p.damage, b.disc.p.damage, n, "damage");
  expect_same(a.disc.p.theta, b.disc.p.theta, n, "theta");
  expect_same(a.disc.p.wvol, b.disc.p.wvol, n, "wvol");
  expect_same(a.disc.p.pstate, b.disc.p.pstate, n, "pstate");
  expect_same(a.disc.p.smin, b.disc.p.smin, n, "smin");
  expect_same(a.mat.s0_node, b.mat.s0_node, n, "s0");
  expect_same(a.state.thermal_strain, b.state.thermal_strain, n, "thermal strain");
  expect_same(a.thermal->T, b.thermal->T, n, "T");
  expect_same(a.cond.indenter.force, b.cond.indenter.force, 3, "indenter force");
  cr_expect_eq(memcmp(a.disc.bonds.broken, b.disc.bonds.broken, nb), 0, "broken flags differ");
  cr_expect_eq(memcmp(a.thermal->cut, b.thermal->cut, nb), 0, "cut flags differ");
  cr_expect_eq(a.state.time, b.state.time);
  cr_expect_eq(a.state.step, b.state.step);
  cr_expect_eq(a.state.external_work, b.state.external_work);
  cr_expect_eq(a.solver.qs.reference, b.solver.qs.reference);
  cr_expect_eq(a.solver.qs.last_reference, b.solver.qs.last_reference);
  cr_expect_eq(a.solver.qs.residual, b.solver.qs.residual);
  cr_expect_eq(a.solver.qs.iterations, b.solver.qs.iterations);
  cr_expect_eq(a.solver.qs.solves, b.solver.qs.solves);
  cr_expect_eq(a.solver.qs.force_evaluations, b.solver.qs.force_evaluations);
  cr_expect_eq(a.solver.qs.cutbacks, b.solver.qs.cutbacks);
  cr_expect_eq(a.thermal->time, b.thermal->time);
  cr_expect_eq(a.thermal->every, b.thermal->every);
  cr_expect_eq(a.thermal->substeps, b.thermal->substeps);
  peri_sim_free(&a);
  peri_sim_free(&b);
}

Test(checkpoint, same_state_same_bytes, .init = setup, .fini = teardown) {
  if (!peri_checkpoint_supported()) cr_skip_test("built without HDF5");
  peri_sim a;
  build(&a, "0.001");
  scramble(&a);
  const peri_checkpoint_progress done = {3, 40};
  char second[160];
  snprintf(second, sizeof second, "%s/again.h5", scratch);
  cr_assert_eq(peri_checkpoint_write(&a, path, &done), PERI_OK);
  cr_assert_eq(peri_checkpoint_write(&a, second, &done), PERI_OK);
  char cmd[400];
  snprintf(cmd, sizeof cmd, "cmp -s '%s' '%s'", path, second);
  cr_expect_eq(system(cmd), 0, "two checkpoints of one state differ (time stamps in the file?)");
  peri_sim_free(&a);
}

Test(checkpoint, other_discretization_is_refused, .init = setup, .fini = teardown) {
  if (!peri_checkpoint_supported()) cr_skip_test("built without HDF5");
  peri_sim a, b;
  build(&a, "0.001");
  build(&b, "0.0008"); /* 15 x 10 nodes */
  cr_assert_eq(peri_checkpoint_write(&a, path, NULL), PERI_OK);
  cr_expect_eq(peri_restart_load(&b, path), PERI_ERR_INPUT);
  cr_expect_null(b.state.restart);
  peri_sim_free(&a);
  peri_sim_free(&b);
}

Test(checkpoint, missing_or_foreign_file_is_refused, .init = setup, .fini = teardown) {
  peri_sim s;
  build(&s, "0.001");
  cr_expect_eq(peri_restart_load(&s, path), PERI_ERR_INPUT, "no file");
  FILE *f = fopen(path, "w");
  cr_assert_not_null(f);
  fputs("time,step\n0,0\n", f);
  fclose(f);
  cr_expect_eq(peri_restart_load(&s, path), PERI_ERR_INPUT, "not HDF5");
  peri_sim_free(&s);
}

/* history.csv and .pvd as the writers leave them, read back for a restart: the rows up to
 * the checkpoint with the values the writer printed (10 significant digits), the frames
 * with their times (9 digits) and file names. */
Test(checkpoint, output_readers_return_what_was_written, .init = setup, .fini = teardown) {
  const char *names[] = {"time", "step", "a,b \"quoted\""};
  char csv[160], pvd[160];
  snprintf(csv, sizeof csv, "%s/history.csv", scratch);
  snprintf(pvd, sizeof pvd, "%s/run.pvd", scratch);
  peri_history *h = peri_history_open(csv, 3, names);
  cr_assert_not_null(h);
  double rows[6][3];
  for (int r = 0; r < 6; ++r) {
    rows[r][0] = 1e-7 * r + noise();
    rows[r][1] = r;
    rows[r][2] = noise() * 1e9;
    cr_assert_eq(peri_history_write(h, rows[r]), PERI_OK);
  }
  peri_history_close(h);
  peri_pvd *p = peri_pvd_open(pvd);
  cr_assert_not_null(p);
  const char *files[] = {"run_000000.vtu", "run&<1>.vtu", "run_000002.vtu"};
  const double times[] = {0.0, 1.234567891234e-6, 2.5e-6};
  for (int k = 0; k < 3; ++k) cr_assert_eq(peri_pvd_add(p, times[k], files[k]), PERI_OK);
  peri_pvd_close(p);

  double *history = NULL, *frame_times = NULL;
  char **frame_files = NULL, **column_names = NULL;
  long n_rows = 0, n_frames = 0;
  int n_columns = 0;
  cr_assert_eq(peri_restart_read_output(scratch, "run", 4, 2, &history, &n_rows, &n_columns, &column_names,
                                        &frame_times, &frame_files, &n_frames), PERI_OK);
  cr_assert_eq(n_columns, 3);
  for (int c = 0; c < 3; ++c) {
    cr_expect_str_eq(column_names[c], names[c]);
    free(column_names[c]);
  }
  free(column_names);
  cr_assert_eq(n_rows, 4);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 3; ++c) {
      char want[64], got[64];
      snprintf(want, sizeof want, "%.10g", rows[r][c]);
      snprintf(got, sizeof got, "%.10g", history[3 * r + c]);
      cr_expect_str_eq(got, want, "row %d column %d", r, c);
    }
  cr_assert_eq(n_frames, 2);
  cr_expect_str_eq(frame_files[1], files[1]);
  char want[64], got[64];
  snprintf(want, sizeof want, "%.9g", times[1]);
  snprintf(got, sizeof got, "%.9g", frame_times[1]);
  cr_expect_str_eq(got, want);
  free(history);
  free(frame_times);
  for (long k = 0; k < n_frames; ++k) free(frame_files[k]);
  free(frame_files);
}

/* When a checkpoint is due: every checkpoint_every steps and at the last step, never inside
 * a dynamic phase of a quasi-static run (its load step is not finished); "{step}" names
 * each one. */
Test(checkpoint, written_when_due, .init = setup, .fini = teardown) {
  if (!peri_checkpoint_supported()) cr_skip_test("built without HDF5");
  peri_sim s;
  build(&s, "0.001");
  free(s.out.directory);
  s.out.directory = peri_strdup(scratch);
  s.out.checkpoint_every = 5;
  s.out.checkpoint_file = peri_strdup("c_{step}.h5");
  const peri_checkpoint_progress done = {1, 2};
  char file[160];
  const long steps[] = {7, 10, 15, 100};
  const bool dynamic[] = {false, true, false, false};
  const bool expected[] = {false, false, true, true}; /* 100 = s.solver.steps, the last step */
  for (int k = 0; k < 4; ++k) {
    s.state.step = steps[k];
    s.solver.qs.phase = dynamic[k] ? PERI_QS_PHASE_DYNAMIC : PERI_QS_PHASE_STATIC;
    cr_assert_eq(peri_checkpoint_after_step(&s, &done), PERI_OK);
    snprintf(file, sizeof file, "%s/c_%06ld.h5", scratch, steps[k]);
    cr_expect_eq(access(file, F_OK) == 0, expected[k], "step %ld%s: checkpoint %s", steps[k],
                 dynamic[k] ? " (dynamic phase)" : "", expected[k] ? "missing" : "written");
  }
  peri_sim_free(&s);
}

/* A checkpoint that records more history rows or frames than the output directory holds
 * (2^61 once sized the arrays they were read into, and overflowed them) is refused, and
 * what was read is handed back to be freed; the arrays grow with what the files hold. */
Test(checkpoint, output_readers_refuse_more_than_the_files_hold, .init = setup, .fini = teardown) {
  const char *names[] = {"time", "step"};
  char csv[160], pvd[160];
  snprintf(csv, sizeof csv, "%s/history.csv", scratch);
  snprintf(pvd, sizeof pvd, "%s/run.pvd", scratch);
  peri_history *h = peri_history_open(csv, 2, names);
  cr_assert_not_null(h);
  for (int r = 0; r < 3; ++r) cr_assert_eq(peri_history_write(h, (double[]){0.5 * r, r}), PERI_OK);
  peri_history_close(h);
  peri_pvd *p = peri_pvd_open(pvd);
  cr_assert_not_null(p);
  cr_assert_eq(peri_pvd_add(p, 0.0, "run_000000.vtu"), PERI_OK);
  peri_pvd_close(p);
  const long claims[][2] = {{(long)1 << 61, 1}, {3, (long)1 << 61}, {4, 1}, {3, 2}, {3, 1}};
  const int expected[] = {PERI_ERR_INPUT, PERI_ERR_INPUT, PERI_ERR_INPUT, PERI_ERR_INPUT, PERI_OK};
  for (int k = 0; k < 5; ++k) {
    double *history = NULL, *frame_times = NULL;
    char **frame_files = NULL, **column_names = NULL;
    long n_rows = 0, n_frames = 0;
    int n_columns = 0;
    cr_expect_eq(peri_restart_read_output(scratch, "run", claims[k][0], claims[k][1], &history, &n_rows, &n_columns,
                                          &column_names, &frame_times, &frame_files, &n_frames),
                 expected[k], "%ld rows and %ld frames claimed", claims[k][0], claims[k][1]);
    cr_expect_leq(n_rows, 3);
    cr_expect_leq(n_frames, 1);
    free(history);
    free(frame_times);
    for (long f = 0; f < n_frames; ++f) free(frame_files[f]);
    free(frame_files);
    for (int c = 0; c < n_columns; ++c) free(column_names[c]);
    free(column_names);
  }
}
