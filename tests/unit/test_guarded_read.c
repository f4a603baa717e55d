/* The guarded reading of a file through a library (src/io/guarded_read.c): what the parent
 * reports when the child's reading loops, crashes, refuses the file or reads it. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "io/guarded_read.h"
#include "peri/error.h"

/* The messages this process reports, one line each. */
static char reported[4096];
static void keep(const char *kind, const char *line, void *ctx) {
  (void)ctx;
  const size_t used = strlen(reported);
  snprintf(reported + used, sizeof reported - used, "%s: %s\n", kind, line);
}
static void take_messages(void) {
  reported[0] = '\0';
  peri_set_message_sink(keep, NULL);
}
static void give_back_messages(void) { peri_set_message_sink(NULL, NULL); }

/* A reading that never ends (a library looping on a damaged file). */
static int loops(void *context) {
  (void)context;
  volatile unsigned long spins = 0;
  for (;;) ++spins;
  return PERI_OK;
}

/* A reading that crashes (an abort: the sanitizers of the unit tests take a segmentation fault
 * over and exit, which the next test's path reports) */
static int crashes(void *context) {
  (void)context;
  abort();
}

/* A reading that refuses the file with its own message. */
static int refuses(void *context) {
  (void)context;
  peri_error("mesh.msh: element 7 names node 99, which the file does not have");
  return PERI_ERR_INPUT;
}

/* A reading that succeeds: counts the readings done in this process. */
static int reads(void *context) {
  ++*(int *)context;
  return PERI_OK;
}

static double seconds_since(const struct timespec *t0) {
  struct timespec t1;
  clock_gettime(CLOCK_MONOTONIC, &t1);
  return (double)(t1.tv_sec - t0->tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0->tv_nsec);
}

TestSuite(guarded_read, .init = take_messages, .fini = give_back_messages);

Test(guarded_read, a_reading_that_loops_ends_at_its_processor_time) {
  struct timespec t0;
  clock_gettime(CLOCK_MONOTONIC, &t0);
  const int rc = peri_guarded_read_within("damaged.msh", "Gmsh", loops, NULL, 1);
  const double took = seconds_since(&t0);
  cr_assert_eq(rc, PERI_ERR_INPUT);
  cr_assert(strstr(reported, "damaged.msh: the Gmsh library did not finish reading it within 1 s of processor "
                             "time: the file is damaged, or not one Gmsh reads"),
            "reported: %s", reported);
  /* one second of processor time; the wall clock of a loaded machine runs ahead of it */
  cr_assert(took >= 0.9 && took < 30.0, "took %g s", took);
}

Test(guarded_read, a_crash_is_reported_as_bad_input) {
  cr_assert_eq(peri_guarded_read("damaged.msh", "Gmsh", crashes, NULL), PERI_ERR_INPUT);
  cr_assert(strstr(reported, "damaged.msh: the Gmsh library crashed reading it (Aborted): the file is damaged, or not one Gmsh reads"), "reported: %s",
            reported);
}

Test(guarded_read, a_refusal_reads_as_the_readers_own_message) {
  cr_assert_eq(peri_guarded_read("mesh.msh", "Gmsh", refuses, NULL), PERI_ERR_INPUT);
  cr_assert_str_eq(reported, "error: peri: error: mesh.msh: element 7 names node 99, which the file does not have\n");
}

Test(guarded_read, a_file_the_child_read_is_read_here_once) {
  int here = 0;
  cr_assert_eq(peri_guarded_read("mesh.msh", "Gmsh", reads, &here), PERI_OK);
  cr_assert_eq(here, 1); /* the child's reading counted in the child's memory only */
  cr_assert_str_eq(reported, "");
}
