/* mkdir -p. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <errno.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include "peri/error.h"
#include "peri/output.h"

static bool is_directory(const char *path) {
  struct stat info;
  return stat(path, &info) == 0 && S_ISDIR(info.st_mode);
}

/* Creates one directory; an existing directory is fine. Errors name `full` (what the user
 * asked for) and `prefix` when that is the part in the way. */
static int make_one(const char *prefix, const char *full) {
  if (mkdir(prefix, 0777) == 0) return 0;
  int mkdir_errno = errno;
  /* Any failure on a path that is already a directory (EEXIST, but also EROFS or EACCES on
   * some systems) means there is nothing to do. */
  if (is_directory(prefix)) return 0;
  if (mkdir_errno == EEXIST)
    peri_error("cannot create directory '%s': '%s' exists and is not a directory", full, prefix);
  else
    peri_error("cannot create directory '%s': %s", full, strerror(mkdir_errno));
  return PERI_ERR_RUN;
}

int peri_mkdir_p(const char *path) {
  if (!path || !*path) {
    peri_error("cannot create directory '': empty path");
    return PERI_ERR_RUN;
  }
  char *prefix = peri_strdup(path);
  int status = 0;
  /* Cut the path at each separator in turn; runs of '/' and a leading '/' give no component. */
  for (char *sep = prefix + 1; *sep && status == 0; sep++) {
    if (*sep != '/' || sep[-1] == '/') continue;
    *sep = '\0';
    status = make_one(prefix, path);
    *sep = '/';
  }
  if (status == 0) status = make_one(prefix, path);
  free(prefix);
  return status;
}
