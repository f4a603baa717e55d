/* A scratch directory per test (Criterion .init/.fini) and files written into it, for the
 * tests of file readers. Include after <criterion/criterion.h>. */
#ifndef PERI_TEST_SCRATCH_DIR_H
#define PERI_TEST_SCRATCH_DIR_H
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char tmpdir[64];
static void make_tmpdir(void) {
  strcpy(tmpdir, "/tmp/peri_test_XXXXXX");
  cr_assert_not_null(mkdtemp(tmpdir));
}
static void remove_tmpdir(void) {
  char cmd[128];
  snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
  cr_assert_eq(system(cmd), 0);
}

static void write_file(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  cr_assert_not_null(f);
  fputs(text, f);
  fclose(f);
}

#endif
