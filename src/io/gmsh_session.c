/* Opening a mesh file through the Gmsh library (gmsh_session.h). */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* strsignal */
#endif
#include "gmsh_session.h"

#ifdef PERI_HAVE_GMSH
#include <errno.h>
#include <fcntl.h>
#include <gmshc.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include "peri/error.h"

int peri_gmsh_guarded(const char *path, int (*reader)(void *context), void *context) {
  const char *dot = strrchr(path, '.');
  if (dot && strcmp(dot, ".geo") == 0) return reader(context);
  fflush(stdout), fflush(stderr); /* (nothing buffered here is written twice) */
  const pid_t child = fork();
  if (child == 0) {
    const struct rlimit no_core = {0, 0}; /* a crash here is expected of a damaged file: no core file */
    setrlimit(RLIMIT_CORE, &no_core);
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0) dup2(null, STDOUT_FILENO), dup2(null, STDERR_FILENO);
    reader(context);
    _exit(0);
  }
  if (child > 0) {
    int status = 0;
    while (waitpid(child, &status, 0) < 0)
      if (errno != EINTR) break;
    if (WIFSIGNALED(status)) {
      peri_error("%s: the Gmsh library crashed reading it (%s): the file is damaged, or not a mesh Gmsh reads", path,
                 strsignal(WTERMSIG(status)));
      return PERI_ERR_INPUT;
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) != 0) { /* (the child returns 0: the library ended it) */
      peri_error("%s: the Gmsh library ended the process reading it (exit status %d): the file is damaged, or not a "
                 "mesh Gmsh reads",
                 path, WEXITSTATUS(status));
      return PERI_ERR_INPUT;
    }
  }
  /* (no child: the reading runs unguarded) */
  return reader(context);
}

int peri_gmsh_failed(const char *path, const char *what) {
  char *last = NULL;
  int ierr = 0;
  gmshLoggerGetLastError(&last, &ierr);
  peri_error("%s: %s%s%s", path, what, last && *last ? ": " : "", last ? last : "");
  gmshFree(last);
  return PERI_ERR_INPUT;
}

int peri_gmsh_open(const char *path, int dim) {
  int ierr = 0;
  char *argv[] = {"peri", NULL}, why[512];
  if (peri_gmsh_load(why, sizeof why) != 0) {
    peri_error("%s: %s", path, why);
    return PERI_ERR_INPUT;
  }
  gmshInitialize(1, argv, 0, &ierr);
  if (ierr) {
    peri_error("%s: the Gmsh library failed to start", path);
    return PERI_ERR_INPUT;
  }
  gmshOptionSetNumber("General.Terminal", 0, &ierr); /* its messages: only through the logger */
  gmshOptionSetNumber("General.Verbosity", 1, &ierr);
  gmshLoggerStart(&ierr);
  int rc = PERI_OK;
  gmshOpen(path, &ierr);
  char *last = NULL;
  int ierr2 = 0;
  gmshLoggerGetLastError(&last, &ierr2); /* some bad files log an error without setting ierr */
  if (ierr || (last && *last)) rc = peri_gmsh_failed(path, "cannot read the Gmsh mesh");
  gmshFree(last);
  const char *dot = strrchr(path, '.');
  if (rc == PERI_OK && dot && strcmp(dot, ".geo") == 0) { /* a geometry: Gmsh meshes it */
    gmshModelMeshGenerate(dim, &ierr);
    if (ierr) rc = peri_gmsh_failed(path, "Gmsh could not mesh the geometry");
  }
  if (rc != PERI_OK) gmshFinalize(&ierr);
  return rc;
}
#endif
