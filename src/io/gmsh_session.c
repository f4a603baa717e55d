/* Opening a mesh file through the Gmsh library (gmsh_session.h). */
#include "gmsh_session.h"

#ifdef PERI_HAVE_GMSH
#include <errno.h>
#include <gmshc.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "guarded_read.h"
#include "peri/error.h"

/* A geometry meshed in a child (peri_gmsh_guarded): its mesh, in the temporary file `mesh`,
 * is what peri_gmsh_open opens for it afterwards (the set-up reads meshes one at a time, on
 * one thread). */
static struct {
  const char *geometry;
  char mesh[4096];
} meshed;

static bool is_geometry(const char *path) {
  const char *dot = strrchr(path, '.');
  return dot && strcmp(dot, ".geo") == 0;
}

typedef struct geometry_meshing {
  const char *path, *mesh;
  int dim;
} geometry_meshing;

/* In the child: Gmsh meshes the geometry and writes the mesh, every element and the physical
 * groups, with the nodes' coordinates in binary (the reading here gets the same numbers). */
static int mesh_geometry(void *context) {
  const geometry_meshing *g = context;
  int rc = peri_gmsh_open(g->path, g->dim), ierr = 0;
  if (rc != PERI_OK) return rc;
  gmshOptionSetNumber("Mesh.Binary", 1, &ierr);
  gmshOptionSetNumber("Mesh.SaveAll", 1, &ierr);
  gmshWrite(g->mesh, &ierr);
  if (ierr) rc = peri_gmsh_failed(g->path, "Gmsh could not write the mesh of the geometry");
  gmshFinalize(&ierr);
  return rc;
}

int peri_gmsh_guarded(const char *path, int dim, int (*reader)(void *context), void *context) {
  if (!is_geometry(path)) return peri_guarded_read(path, "Gmsh", reader, context);
  /* a geometry: meshed once, in a child (Gmsh 4.8 crashes meshing some geometries), whose mesh
   * is then read as a .msh file is */
  const char *dir = getenv("TMPDIR");
  if (!dir || !*dir) dir = "/tmp";
  const int n = snprintf(meshed.mesh, sizeof meshed.mesh, "%s/peri-mesh-XXXXXX.msh", dir);
  if (n <= 0 || (size_t)n >= sizeof meshed.mesh) errno = ENAMETOOLONG;
  const int fd = n > 0 && (size_t)n < sizeof meshed.mesh ? mkstemps(meshed.mesh, 4) : -1;
  if (fd < 0) {
    peri_error("%s: cannot create a temporary file for its mesh in %s (%s): set TMPDIR to a writable directory",
               path, dir, strerror(errno));
    return PERI_ERR_INPUT;
  }
  close(fd);
  geometry_meshing g = {path, meshed.mesh, dim};
  int rc = peri_guarded_run(path, "Gmsh", "meshing", mesh_geometry, &g);
  if (rc == PERI_OK) {
    meshed.geometry = path;
    rc = peri_guarded_read(path, "Gmsh", reader, context);
    meshed.geometry = NULL;
  }
  unlink(meshed.mesh);
  return rc;
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
  /* a geometry meshed by peri_gmsh_guarded: its mesh (the messages still name the geometry) */
  const bool premeshed = meshed.geometry && strcmp(path, meshed.geometry) == 0;
  gmshOpen(premeshed ? meshed.mesh : path, &ierr);
  char *last = NULL;
  int ierr2 = 0;
  gmshLoggerGetLastError(&last, &ierr2); /* some bad files log an error without setting ierr */
  if (ierr || (last && *last)) rc = peri_gmsh_failed(path, "cannot read the Gmsh mesh");
  gmshFree(last);
  if (rc == PERI_OK && !premeshed && is_geometry(path)) { /* a geometry: Gmsh meshes it */
    gmshModelMeshGenerate(dim, &ierr);
    if (ierr) rc = peri_gmsh_failed(path, "Gmsh could not mesh the geometry");
  }
  if (rc != PERI_OK) gmshFinalize(&ierr);
  return rc;
}
#endif
