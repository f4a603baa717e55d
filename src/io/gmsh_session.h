/* Opening a mesh file through the Gmsh library, shared by the readers of PD meshes
 * (gmsh_mesh.c) and of the FEM part of a coupling (gmsh_fem_mesh.c). Only with PERI_HAVE_GMSH. */
#ifndef PERI_IO_GMSH_SESSION_H
#define PERI_IO_GMSH_SESSION_H

/* Opens the Gmsh library (gmsh_library.c: loaded on first use, not linked). 0, or -1 with a
 * message in why (size n). */
#include <stddef.h>
int peri_gmsh_load(char *why, size_t n);

/* Reports "PATH: WHAT: <Gmsh's last logged error>" and returns PERI_ERR_INPUT. */
int peri_gmsh_failed(const char *path, const char *what);

/* Starts the library quietly (messages only through its logger), reads PATH (.msh of any
 * version Gmsh reads) and, for a .geo geometry, meshes it in dimension DIM. On PERI_OK the
 * model is open and the caller reads it, then calls gmshFinalize; on an error the library has
 * been closed again. */
int peri_gmsh_open(const char *path, int dim);

/* Runs reader(context), the whole reading of the mesh file PATH (open, queries, gmshFinalize),
 * through peri_guarded_read (guarded_read.h): Gmsh 4.8 crashes on some damaged .msh files (an
 * element with a negative node tag) instead of reporting them (docs/deck.md, "Meshes"). A
 * geometry (.geo) is first meshed in dimension DIM in a child process of its own (Gmsh 4.8 also
 * crashes meshing some geometries: a quadrangle algorithm), which writes the mesh to a temporary
 * .msh file; the reading then opens that file for PATH, so the geometry is meshed once. */
int peri_gmsh_guarded(const char *path, int dim, int (*reader)(void *context), void *context);

#endif
