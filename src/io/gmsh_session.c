/* Opening a mesh file through the Gmsh library (gmsh_session.h). */
#include "gmsh_session.h"

#ifdef PERI_HAVE_GMSH
#include <gmshc.h>
#include <string.h>
#include "guarded_read.h"
#include "peri/error.h"

int peri_gmsh_guarded(const char *path, int (*reader)(void *context), void *context) {
  const char *dot = strrchr(path, '.');
  if (dot && strcmp(dot, ".geo") == 0) return reader(context); /* (meshed here: twice would cost twice) */
  return peri_guarded_read(path, "Gmsh", reader, context);
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
