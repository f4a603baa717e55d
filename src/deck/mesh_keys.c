/* discretization.mesh, mesh_format, node_file and blocks: the nodes of a mesh file and the
 * materials of its blocks (docs/deck.md, section 6 and "Meshes"). */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "peri/error.h"
#include "setup_parts.h"

void peri_setup_deck_path(const peri_sim *s, const char *path, char *full, size_t cap) {
  const char *slash = strrchr(s->deck_path, '/');
  if (path[0] != '/' && slash)
    snprintf(full, cap, "%.*s/%s", (int)(slash - s->deck_path), s->deck_path, path);
  else
    snprintf(full, cap, "%s", path);
}

/* The block a key of the blocks mapping names: its id, or its name in the mesh. */
static int block_of_key(const peri_mesh *m, const peri_node *key, const char *path) {
  for (int b = 0; b < m->n_blocks; ++b)
    if (strcmp(m->blocks[b].name, key->scalar) == 0) return b;
  char *end;
  long long id = strtoll(key->scalar, &end, 10);
  if (end != key->scalar && !*end)
    for (int b = 0; b < m->n_blocks; ++b)
      if (m->blocks[b].id == id) return b;
  for (int b = 0; b < m->n_blocks; ++b)
    if (strcasecmp(m->blocks[b].name, key->scalar) == 0) return b;
  char list[1024] = "";
  for (int b = 0; b < m->n_blocks; ++b)
    snprintf(list + strlen(list), sizeof list - strlen(list), "%s'%s' (id %lld)", b ? ", " : "",
             m->blocks[b].name, (long long)m->blocks[b].id);
  return -peri_deck_error(key, "key '%s': %s has no such block (its blocks: %s)", key->scalar, path, list);
}

int peri_setup_mesh(peri_sim *s, const peri_node *d, peri_mesh *mesh) {
  const peri_geometry *g = &s->disc.geom;
  const peri_node *node_file = peri_deck_get(d, "node_file");
  const char *path = NULL;
  int rc = peri_deck_string(d, node_file ? "node_file" : "mesh", true, &path);
  if (rc != PERI_OK) return rc;
  char full[PATH_MAX + 256];
  peri_setup_deck_path(s, path, full, sizeof full);
  peri_mesh_format format = node_file ? PERI_MESH_TEXT : peri_mesh_format_of(path);
  const peri_node *fmt = peri_deck_get(d, "mesh_format");
  if (fmt) {
    if (node_file)
      return peri_deck_error(peri_deck_key_node(d, "mesh_format"), "key 'mesh_format': only with 'mesh' "
                             "(a node_file is a text file)");
    int which = 0;
    rc = peri_deck_choice(d, "mesh_format", true, peri_mesh_format_names, &which);
    if (rc != PERI_OK) return rc;
    format = (peri_mesh_format)which;
  }
  if (!peri_mesh_format_available(format))
    return peri_deck_error(peri_deck_get(d, node_file ? "node_file" : "mesh"),
                           "'%s' is a%s %s mesh, and this build of peri reads none: it was built without "
                           "the %s library (install %s, e.g. with scripts/install-deps, and build again)",
                           path, format == PERI_MESH_EXODUS ? "n" : "", peri_mesh_format_names[format],
                           format == PERI_MESH_EXODUS ? "Exodus II" : "Gmsh",
                           format == PERI_MESH_EXODUS ? "libexodusii-dev" : "libgmsh-dev");
  rc = peri_mesh_read(mesh, full, format, g->dim, g->thickness, g->cross_section);
  if (rc != PERI_OK) return rc;

  /* the material of each block: from the list (block id k is item k) or the mapping (block
   * names or ids); a single material may take every block */
  int32_t *material = peri_malloc(sizeof(int32_t) * (size_t)(mesh->n_blocks > 0 ? mesh->n_blocks : 1));
  for (int b = 0; b < mesh->n_blocks; ++b) material[b] = s->mat.n_materials == 1 ? 0 : -1;
  const peri_node *blocks = peri_deck_get(d, "blocks");
  if (blocks && blocks->kind == PERI_NODE_SEQUENCE) {
    for (int k = 0; k < blocks->count && rc == PERI_OK; ++k) {
      int mi = blocks->items[k]->scalar ? peri_setup_find_material(s, blocks->items[k], blocks->items[k]->scalar)
                                        : -peri_deck_error(blocks->items[k], "expected a material name");
      if (mi < 0) rc = -mi;
      for (int b = 0; rc == PERI_OK && b < mesh->n_blocks; ++b)
        if (mesh->blocks[b].id == k + 1) material[b] = mi;
    }
  } else if (blocks && blocks->kind == PERI_NODE_MAPPING) {
    for (int k = 0; k < blocks->count && rc == PERI_OK; ++k) {
      const peri_node *v = blocks->items[k];
      int b = block_of_key(mesh, blocks->keys[k], full);
      if (b < 0) rc = -b;
      int mi = rc != PERI_OK ? 0 : v->scalar ? peri_setup_find_material(s, v, v->scalar)
                                              : -peri_deck_error(v, "expected a material name");
      if (mi < 0) rc = -mi;
      if (rc == PERI_OK) material[b] = mi;
    }
  } else if (blocks) {
    rc = peri_deck_error(blocks, "key 'blocks': expected a list of material names (block 1 first) or a "
                                 "mapping of block names or ids to material names");
  }
  for (int b = 0; b < mesh->n_blocks && rc == PERI_OK; ++b) {
    if (material[b] < 0) {
      rc = peri_deck_error(blocks ? blocks : d, "discretization: block '%s' (id %lld) of %s has no material; "
                           "%s", mesh->blocks[b].name, (long long)mesh->blocks[b].id, full,
                           blocks ? "add it to 'blocks'" : "with several materials, 'blocks' must map the mesh's blocks to materials");
    } else if (mesh->blocks[b].id < 1 || mesh->blocks[b].id > INT32_MAX) {
      rc = peri_deck_error(d, "discretization: block '%s' of %s has id %lld; block ids must be positive "
                           "32-bit integers", mesh->blocks[b].name, full, (long long)mesh->blocks[b].id);
    }
  }
  if (rc == PERI_OK) {
    peri_particles *p = &s->disc.p;
    for (int32_t k = 0; k < mesh->n; ++k) {
      const int b = mesh->block[k];
      peri_particles_add(p, &mesh->x[3 * (size_t)k], mesh->volume[k], material[b], (int32_t)mesh->blocks[b].id);
    }
  }
  free(material);
  return rc;
}
