/* Reading a mesh: the format from a file's name, the reader of each format, and the checks
 * every mesh passes (include/peri/mesh.h; the readers are exodus_mesh.c, gmsh_mesh.c,
 * abaqus_mesh.c and nodefile.c). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include "peri/error.h"
#include "peri/mesh.h"

const char *const peri_mesh_format_names[] = {"text", "exodus", "gmsh", "abaqus", NULL};

peri_mesh_format peri_mesh_format_of(const char *path) {
  const char *dot = strrchr(path, '.');
  const char *slash = strrchr(path, '/');
  if (!dot || (slash && dot < slash)) return PERI_MESH_TEXT;
  static const char *const exodus[] = {".e", ".exo", ".ex2", ".exii", ".g", ".gen", NULL};
  for (int k = 0; exodus[k]; ++k)
    if (strcasecmp(dot, exodus[k]) == 0) return PERI_MESH_EXODUS;
  if (strcasecmp(dot, ".msh") == 0 || strcmp(dot, ".geo") == 0) return PERI_MESH_GMSH;
  if (strcasecmp(dot, ".inp") == 0) return PERI_MESH_ABAQUS;
  return PERI_MESH_TEXT;
}

bool peri_mesh_format_available(peri_mesh_format f) {
  switch (f) {
#ifndef PERI_HAVE_EXODUS
  case PERI_MESH_EXODUS: return false;
#endif
#ifndef PERI_HAVE_GMSH
  case PERI_MESH_GMSH: return false;
#endif
  default: return true;
  }
}

/* Every point's position finite (a damaged file's overflowed number would be infinite, and
 * the bond search would span it), its volume positive and finite. */
static int check_points(const peri_mesh *m, const char *path) {
  if (m->n == 0) {
    peri_error("%s: the mesh has no elements of dimension %d (nor nodes with volumes)", path, m->dim);
    return PERI_ERR_INPUT;
  }
  for (int32_t k = 0; k < m->n; ++k)
    for (int d = 0; d < 3; ++d)
      if (!isfinite(m->x[3 * k + d])) {
        peri_error("%s: element %lld (block '%s') lies at %c = %g; positions must be finite", path,
                   (long long)m->id[k], m->blocks[m->block[k]].name, "xyz"[d], m->x[3 * k + d]);
        return PERI_ERR_INPUT;
      }
  for (int32_t k = 0; k < m->n; ++k)
    if (!(m->volume[k] > 0.0) || m->volume[k] > 1e300) {
      peri_error("%s: element %lld (block '%s') has volume %g; volumes must be positive", path,
                 (long long)m->id[k], m->blocks[m->block[k]].name, m->volume[k]);
      return PERI_ERR_INPUT;
    }
  return PERI_OK;
}

int peri_mesh_read(peri_mesh *m, const char *path, peri_mesh_format f, int dim, double thickness,
                   double cross_section) {
  peri_mesh_init(m, dim);
  if (!peri_mesh_format_available(f)) {
    peri_error("%s: this build of peri reads no %s meshes: it was built without the %s library "
               "(install %s, e.g. with scripts/install-deps, and build again)", path,
               f == PERI_MESH_EXODUS ? "Exodus II" : "Gmsh", f == PERI_MESH_EXODUS ? "Exodus II" : "Gmsh",
               f == PERI_MESH_EXODUS ? "libexodusii-dev" : "libgmsh-dev");
    return PERI_ERR_INPUT;
  }
  FILE *probe = fopen(path, "rb");
  if (!probe) {
    peri_error("cannot open mesh file '%s': %s", path, strerror(errno));
    return PERI_ERR_INPUT;
  }
  fclose(probe);
  int rc = PERI_OK;
  switch (f) {
  case PERI_MESH_TEXT: rc = peri_mesh_read_text(m, path, dim); break;
  case PERI_MESH_EXODUS: rc = peri_mesh_read_exodus(m, path, dim, thickness, cross_section); break;
  case PERI_MESH_GMSH: rc = peri_mesh_read_gmsh(m, path, dim, thickness, cross_section); break;
  case PERI_MESH_ABAQUS: rc = peri_mesh_read_abaqus(m, path, dim, thickness, cross_section); break;
  }
  if (rc == PERI_OK) rc = check_points(m, path);
  if (rc != PERI_OK) peri_mesh_free(m);
  return rc;
}

