/* The Gmsh library, loaded when a mesh is first read rather than linked (gmsh_session.h).
 * libgmsh brings OpenCASCADE and the rest of its dependencies: linked, they cost every peri
 * process about 44 MB of resident memory and 0.16 s of dynamic linking at start, whether or
 * not the deck reads a mesh. Here the entry points of gmshc.h that peri uses forward to the
 * library opened by name (its SONAME, found at configure time) on the first use. */
#include "gmsh_session.h"

#ifdef PERI_HAVE_GMSH
#include <dlfcn.h>
#include <gmshc.h>
#include <stdio.h>
#include <stdlib.h>

#ifndef PERI_GMSH_SONAME
#define PERI_GMSH_SONAME "libgmsh.so"
#endif

static void *library;

int peri_gmsh_load(char *why, size_t n) {
  if (library) return 0;
  library = dlopen(PERI_GMSH_SONAME, RTLD_NOW | RTLD_LOCAL);
  if (!library) {
    const char *err = dlerror();
    snprintf(why, n, "cannot load the Gmsh library (%s): %s", PERI_GMSH_SONAME, err ? err : "not found");
    return -1;
  }
  return 0;
}

/* The library's entry `name` (the library opened first if need be); NULL when it cannot be
 * opened or lacks the entry. */
static void *entry(const char *name) {
  char why[512];
  return library || peri_gmsh_load(why, sizeof why) == 0 ? dlsym(library, name) : NULL;
}

/* Each forwarder looks its entry up once; a missing one reports an error through ierr. */
#define FORWARD(name, params, args)                        \
  void name params {                                       \
    static void(*fn) params;                               \
    if (!fn) *(void **)&fn = entry(#name);                 \
    if (!fn) {                                             \
      *ierr = 1;                                           \
      return;                                              \
    }                                                      \
    fn args;                                               \
  }

FORWARD(gmshInitialize, (int argc, char **argv, const int readConfigFiles, int *ierr),
        (argc, argv, readConfigFiles, ierr))
FORWARD(gmshFinalize, (int *ierr), (ierr))
FORWARD(gmshOpen, (const char *fileName, int *ierr), (fileName, ierr))
FORWARD(gmshWrite, (const char *fileName, int *ierr), (fileName, ierr))
FORWARD(gmshOptionSetNumber, (const char *name, const double value, int *ierr), (name, value, ierr))
FORWARD(gmshLoggerStart, (int *ierr), (ierr))
FORWARD(gmshLoggerGetLastError, (char **error, int *ierr), (error, ierr))
FORWARD(gmshModelGetEntities, (int **dimTags, size_t *dimTags_n, const int dim, int *ierr),
        (dimTags, dimTags_n, dim, ierr))
FORWARD(gmshModelGetEntitiesForPhysicalGroup, (const int dim, const int tag, int **tags, size_t *tags_n, int *ierr),
        (dim, tag, tags, tags_n, ierr))
FORWARD(gmshModelGetPhysicalGroups, (int **dimTags, size_t *dimTags_n, const int dim, int *ierr),
        (dimTags, dimTags_n, dim, ierr))
FORWARD(gmshModelGetPhysicalGroupsForEntity,
        (const int dim, const int tag, int **physicalTags, size_t *physicalTags_n, int *ierr),
        (dim, tag, physicalTags, physicalTags_n, ierr))
FORWARD(gmshModelGetPhysicalName, (const int dim, const int tag, char **name, int *ierr), (dim, tag, name, ierr))
FORWARD(gmshModelMeshGenerate, (const int dim, int *ierr), (dim, ierr))
FORWARD(gmshModelMeshGetElementProperties,
        (const int elementType, char **elementName, int *dim, int *order, int *numNodes, double **localNodeCoord,
         size_t *localNodeCoord_n, int *numPrimaryNodes, int *ierr),
        (elementType, elementName, dim, order, numNodes, localNodeCoord, localNodeCoord_n, numPrimaryNodes, ierr))
FORWARD(gmshModelMeshGetElements,
        (int **elementTypes, size_t *elementTypes_n, size_t ***elementTags, size_t **elementTags_n,
         size_t *elementTags_nn, size_t ***nodeTags, size_t **nodeTags_n, size_t *nodeTags_nn, const int dim,
         const int tag, int *ierr),
        (elementTypes, elementTypes_n, elementTags, elementTags_n, elementTags_nn, nodeTags, nodeTags_n, nodeTags_nn,
         dim, tag, ierr))
FORWARD(gmshModelMeshGetIntegrationPoints,
        (const int elementType, const char *integrationType, double **localCoord, size_t *localCoord_n,
         double **weights, size_t *weights_n, int *ierr),
        (elementType, integrationType, localCoord, localCoord_n, weights, weights_n, ierr))
FORWARD(gmshModelMeshGetJacobians,
        (const int elementType, double *localCoord, size_t localCoord_n, double **jacobians, size_t *jacobians_n,
         double **determinants, size_t *determinants_n, double **coord, size_t *coord_n, const int tag,
         const size_t task, const size_t numTasks, int *ierr),
        (elementType, localCoord, localCoord_n, jacobians, jacobians_n, determinants, determinants_n, coord, coord_n,
         tag, task, numTasks, ierr))
FORWARD(gmshModelMeshGetNodes,
        (size_t **nodeTags, size_t *nodeTags_n, double **coord, size_t *coord_n, double **parametricCoord,
         size_t *parametricCoord_n, const int dim, const int tag, const int includeBoundary,
         const int returnParametricCoord, int *ierr),
        (nodeTags, nodeTags_n, coord, coord_n, parametricCoord, parametricCoord_n, dim, tag, includeBoundary,
         returnParametricCoord, ierr))
FORWARD(gmshModelMeshGetNodesForPhysicalGroup,
        (const int dim, const int tag, size_t **nodeTags, size_t *nodeTags_n, double **coord, size_t *coord_n,
         int *ierr),
        (dim, tag, nodeTags, nodeTags_n, coord, coord_n, ierr))

/* gmshFree releases what the library allocated with the C library's malloc (gmshc.h's
 * gmshMalloc is malloc), so free() is its match even before a lookup. */
void gmshFree(void *p) {
  static void (*fn)(void *);
  if (!fn) *(void **)&fn = entry("gmshFree");
  if (fn) fn(p);
  else free(p);
}
#endif
