/* A finite-element mesh from a file joined to the PD grid (src/fem/file_mesh.c,
 * docs/coupling.md "Gmsh meshes"), on a grid of spacing 1 with nodes at (i, j), i = 0..4,
 * j = 0..2, and a mesh of: four lattice cells over [0, 2] x [0, 2]; a trapezoid (2,0) (4,0)
 * (4,2) (2,1) and a triangle (2,1) (4,2) (2,2) over [2, 4] x [0, 2], whose lattice points
 * (3,0), (4,1), (3,2) (on their sides) and (3,1) (inside) are no mesh nodes; and a triangle
 * (0,0) (0,1) (-0.7,1) with a node off the grid. From the geometry alone: the 11 mesh nodes on
 * the grid become its nodes, the off-grid node is added (volume: a third of its triangle's area
 * 0.35), the four holes' grid nodes are left out (12 nodes remain), a node of the coarse
 * elements gets its share of their areas ((4,2): 3/4 + 1/3), one of lattice cells only keeps
 * its grid volume, and a node is fem_only exactly when a hole or the off-grid node lies within
 * the reach 1.5 (tagged with that element or node). Inverted elements and coincident nodes are
 * errors naming the file and the tags. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>
#include "peri/error.h"
#include "peri/fem_mesh.h"

enum { GRID_X = 5, GRID_Y = 3 };

static void grid(peri_particles *p) {
  peri_particles_init(p, 2);
  for (int j = 0; j < GRID_Y; ++j)
    for (int i = 0; i < GRID_X; ++i) {
      const double x[3] = {i, j, 0};
      peri_particles_add(p, x, 1.0, 0, 1);
    }
}

/* The mesh of the header; node tags 10 + 5 j + i on the grid, 99 off it. */
static void mesh(peri_fem_mesh_file *f) {
  static const double xy[][2] = {{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}, {0, 2}, {1, 2}, {2, 2}, {4, 0}, {4, 2}, {-0.7, 1}};
  static const int32_t corners[] = {0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7, /* cells */
                                    2, 9, 10, 5, /* trapezoid */ 5, 10, 8, /* triangle */ 0, 3, 11};
  static const int64_t offset[] = {0, 4, 8, 12, 16, 20, 23, 26};
  memset(f, 0, sizeof *f);
  f->path = peri_strdup("test.msh");
  f->dim = 2;
  f->n_nodes = 12;
  f->node_tag = malloc(sizeof(int64_t) * 12);
  f->x = calloc(36, sizeof(double));
  for (int a = 0; a < 12; ++a) {
    f->x[3 * a] = xy[a][0], f->x[3 * a + 1] = xy[a][1];
    f->node_tag[a] = a == 11 ? 99 : 10 + 5 * (int64_t)xy[a][1] + (int64_t)xy[a][0];
  }
  f->n_elements = 7;
  f->element_tag = malloc(sizeof(int64_t) * 7);
  for (int e = 0; e < 7; ++e) f->element_tag[e] = e + 1;
  f->offset = malloc(sizeof offset);
  memcpy(f->offset, offset, sizeof offset);
  f->corner = malloc(sizeof corners);
  memcpy(f->corner, corners, sizeof corners);
}

static int32_t node_at(const peri_particles *p, double x, double y) {
  for (int32_t i = 0; i < p->n; ++i)
    if (fabs(p->x[3 * (size_t)i] - x) < 1e-12 && fabs(p->x[3 * (size_t)i + 1] - y) < 1e-12) return i;
  return -1;
}

Test(file_mesh, joins_the_grid) {
  peri_particles p;
  grid(&p);
  peri_fem_mesh_file f;
  mesh(&f);
  peri_fem_mesh m;
  char why[512] = "";
  cr_assert_eq(peri_fem_mesh_from_file(&p, 1.0, 1.5, 1.0, 0, &f, &m, why, sizeof why), PERI_OK, "%s", why);
  cr_expect_eq(p.n, 12, "11 grid nodes and the added one, got %d", p.n);
  cr_expect_eq(m.n_nodes, 12);
  cr_expect_eq(m.removed, 4, "the holes (3,0) (3,1) (4,1) (3,2), got %d", m.removed);
  const double holes[4][2] = {{3, 0}, {3, 1}, {4, 1}, {3, 2}};
  for (int k = 0; k < 4; ++k) cr_expect_lt(node_at(&p, holes[k][0], holes[k][1]), 0, "hole %d kept", k);
  cr_expect_eq(m.n_elements, 7);
  for (int64_t q = 0; q < m.offset[m.n_elements]; ++q) /* each corner is the node at the file's position */
    for (int d = 0; d < 2; ++d)
      cr_expect(fabs(p.x[3 * (size_t)m.nodes[q] + d] - f.x[3 * (size_t)f.corner[q] + d]) < 1e-12);
  const int32_t added = node_at(&p, -0.7, 1.0), corner = node_at(&p, 4, 2), inner = node_at(&p, 1, 1);
  cr_assert(added >= 0 && corner >= 0 && inner >= 0);
  cr_expect(fabs(p.volume[added] - 0.35 / 3.0) < 1e-15, "added node's volume %g", p.volume[added]);
  cr_expect(fabs(p.volume[corner] - (3.0 / 4.0 + 1.0 / 3.0)) < 1e-14, "(4,2): %g", p.volume[corner]);
  cr_expect_eq(p.volume[inner], 1.0, "(1,1) is in lattice cells only");
  cr_expect_eq(m.node_tag[added], 99);
  cr_expect_eq(m.node_tag[inner], 16);
  /* fem_only: a hole or the off-grid node within 1.5 */
  for (int32_t i = 0; i < p.n; ++i) {
    const double x = p.x[3 * (size_t)i], y = p.x[3 * (size_t)i + 1];
    bool near = i == added || hypot(x + 0.7, y - 1.0) <= 1.5;
    for (int k = 0; k < 4; ++k) near = near || hypot(x - holes[k][0], y - holes[k][1]) <= 1.5;
    cr_expect_eq(m.fem_only[i], near, "node at (%g, %g): fem_only %d", x, y, m.fem_only[i]);
  }
  cr_expect_eq(m.fem_only_tag[node_at(&p, 0, 0)], 99, "(0,0) sees the off-grid node");
  cr_expect_eq(m.fem_only_tag[node_at(&p, 2, 1)], -5, "(2,1) sees a hole of the trapezoid (element 5)");
  peri_fem_mesh_free(&m);
  peri_fem_mesh_file_free(&f);
  peri_particles_free(&p);
}

Test(file_mesh, inverted_and_coincident) {
  peri_particles p;
  grid(&p);
  peri_fem_mesh_file f;
  mesh(&f);
  const int32_t swap = f.corner[1]; /* the first cell clockwise */
  f.corner[1] = f.corner[3], f.corner[3] = swap;
  peri_fem_mesh m;
  char why[512] = "";
  cr_expect_eq(peri_fem_mesh_from_file(&p, 1.0, 1.5, 1.0, 0, &f, &m, why, sizeof why), PERI_ERR_INPUT);
  cr_expect(strstr(why, "test.msh: element 1") && strstr(why, "inverted"), "%s", why);
  f.corner[3] = f.corner[1], f.corner[1] = swap;
  f.x[3 * 11] = 1.0, f.x[3 * 11 + 1] = 1.0; /* node 99 onto the grid node (1,1), tag 16 */
  f.corner[24] = 11, f.corner[25] = 3;         /* its triangle counter-clockwise again */
  cr_expect_eq(peri_fem_mesh_from_file(&p, 1.0, 1.5, 1.0, 0, &f, &m, why, sizeof why), PERI_ERR_INPUT);
  cr_expect(strstr(why, "nodes 16 and 99 coincide"), "%s", why);
  cr_expect_eq(p.n, GRID_X * GRID_Y, "the grid is left as it was");
  peri_fem_mesh_file_free(&f);
  peri_particles_free(&p);
}
