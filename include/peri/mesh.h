/* Meshes read as peridynamic points: one point per element (its centroid and volume) or
 * per node of a node file, with the mesh's blocks and sets (src/io/mesh.c and one reader per
 * format: nodefile.c, exodus_mesh.c, gmsh_mesh.c, abaqus_mesh.c; docs/deck.md "Meshes"). */
#ifndef PERI_MESH_H
#define PERI_MESH_H
#include <stdbool.h>
#include <stdint.h>
#include "peri/fem_mesh.h"

typedef enum {
  PERI_MESH_TEXT,   /* x y [z] block volume, or a header naming the columns (PeriLab, CSV) */
  PERI_MESH_EXODUS, /* Exodus II: SPHERE elements (Peridigm) or solid elements */
  PERI_MESH_GMSH,   /* Gmsh .msh, read through the Gmsh library */
  PERI_MESH_ABAQUS, /* Abaqus .inp */
} peri_mesh_format;

/* Format names as the deck writes them (mesh_format), in enum order, NULL-terminated. */
extern const char *const peri_mesh_format_names[];

typedef struct peri_mesh_block {
  int64_t id;   /* the file's block id: Exodus block id, Gmsh physical tag, Abaqus ordinal */
  char *name;   /* the file's name for it, or a made-up one ("block_<id>") */
} peri_mesh_block;

typedef struct peri_mesh_set {
  char *name;
  int64_t id;       /* the file's number for it (Exodus node set id, Gmsh physical tag), or 0 */
  const char *kind; /* what it came from, for messages ("node set", "physical group", ...) */
  int32_t count;
  int32_t *points;  /* ascending indices of the mesh's points */
} peri_mesh_set;

typedef struct peri_mesh {
  int dim;
  int32_t n, capacity;
  double *x;       /* [3n] centroids (components beyond dim are 0) */
  double *volume;  /* [n] */
  int32_t *block;  /* [n] index into blocks */
  int64_t *id;     /* [n] the point's number in the file (node files: 1-based line order of
                      nodes; Exodus: element id; Gmsh: element tag; Abaqus: element number) */
  int n_blocks;
  peri_mesh_block *blocks;
  int n_sets;
  peri_mesh_set *sets;
} peri_mesh;

void peri_mesh_init(peri_mesh *m, int dim);
void peri_mesh_free(peri_mesh *m);
/* Appends a point of block index `block`; returns its index. */
int32_t peri_mesh_add_point(peri_mesh *m, const double x[3], double volume, int32_t block, int64_t id);
/* The index of the block with this id, added (named `name`, or "block_<id>") if new. */
int32_t peri_mesh_block_index(peri_mesh *m, int64_t id, const char *name);
/* Adds a set of points (indices need not be sorted or unique); returns it. */
peri_mesh_set *peri_mesh_add_set(peri_mesh *m, const char *name, int64_t id, const char *kind,
                                 const int32_t *points, int32_t count);
/* Adds the set of the points that have a vertex in `vertices` (Peridigm's rule for node sets
 * of a solid mesh: an element belongs to the set when one of its nodes does; for a sphere
 * mesh, the element of each node). Points' vertices are conn[offset[k] .. offset[k+1]-1]. */
peri_mesh_set *peri_mesh_add_vertex_set(peri_mesh *m, const char *name, int64_t id, const char *kind,
                                        const int64_t *offset, const int64_t *conn,
                                        const int64_t *vertices, int64_t n_vertices);
/* The set called `name` (exact, else case-insensitive); NULL when none or several. */
const peri_mesh_set *peri_mesh_find_set(const peri_mesh *m, const char *name);

/* The format a file name's extension stands for: .e .exo .ex2 .exii .g .gen (Exodus), .msh
 * and .geo (Gmsh; a .geo geometry is meshed by Gmsh),
 * .inp (Abaqus), anything else a text node file. */
peri_mesh_format peri_mesh_format_of(const char *path);
/* Whether the build can read the format (Exodus and Gmsh are optional libraries). */
bool peri_mesh_format_available(peri_mesh_format f);

/* Reads a mesh of dimension `dim`. Element volumes: 3D elements' volumes; 2D elements'
 * areas times `thickness`; 1D elements' lengths times `cross_section`. Errors name the file
 * and the entity and return PERI_ERR_INPUT; m is then empty. */
int peri_mesh_read(peri_mesh *m, const char *path, peri_mesh_format f, int dim, double thickness,
                   double cross_section);
int peri_mesh_read_text(peri_mesh *m, const char *path, int dim);
int peri_mesh_read_exodus(peri_mesh *m, const char *path, int dim, double thickness, double cross_section);
int peri_mesh_read_gmsh(peri_mesh *m, const char *path, int dim, double thickness, double cross_section);
int peri_mesh_read_abaqus(peri_mesh *m, const char *path, int dim, double thickness, double cross_section);

/* The finite-element mesh of the FEM part of a coupled model from a Gmsh file
 * (src/io/gmsh_fem_mesh.c, docs/coupling.md "Gmsh meshes"): every element of dimension dim
 * (2-node lines, 3-node triangles and 4-node quadrangles, 8-node hexahedra; lower dimensions
 * skipped) with the file's node and element tags. Errors (a file that is missing or does not
 * parse, an element type of dimension dim peri has no element for or one of a higher
 * dimension, an element naming an undefined node, a node in no element, a coordinate beyond
 * dim) name the file and the entity, are printed, and return PERI_ERR_INPUT; f is then empty. */
int peri_fem_mesh_file_read(const char *path, int dim, peri_fem_mesh_file *f);

/* A node set file: point ids (as in peri_mesh.id), separated by spaces, commas or newlines;
 * '#' comments and a PeriLab "header: global_id" line are skipped. Each id must be a point of
 * the mesh. Returns the ascending point indices in *points (allocated) and their count. */
int peri_node_set_file_read(const peri_mesh *m, const char *path, int32_t **points, int32_t *count);

#endif
