/* Mesh readers (src/io: the exodus, gmsh and abaqus readers, nodefile.c): each on a small mesh made here, giving the
 * expected number of points and the exact volume of the meshed body (meshes with straight
 * edges and flat or bilinear faces tile the body exactly, so the sum of the element volumes
 * equals it to round-off: tolerance 1e-12 relative), the expected sets, and bad files that
 * are errors naming the file and the entity. */
#include <criterion/criterion.h>
#include "scratch_dir.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "peri/error.h"
#include "peri/mesh.h"
#ifdef PERI_HAVE_EXODUS
#include <exodusII.h>
#endif
#ifdef PERI_HAVE_GMSH
#include <gmshc.h>
#endif


/* Runs f with stderr captured into buf. */
static int captured(char *buf, size_t len, int (*f)(void *), void *arg) {
  fflush(stderr);
  FILE *tmp = tmpfile();
  cr_assert_not_null(tmp);
  int saved = dup(2);
  dup2(fileno(tmp), 2);
  int rc = f(arg);
  fflush(stderr);
  dup2(saved, 2);
  close(saved);
  rewind(tmp);
  size_t n = fread(buf, 1, len - 1, tmp);
  buf[n] = '\0';
  fclose(tmp);
  return rc;
}

typedef struct {
  const char *path;
  peri_mesh_format format;
  int dim;
} read_args;

static int read_it(void *arg) {
  read_args *a = arg;
  peri_mesh m;
  int rc = peri_mesh_read(&m, a->path, a->format, a->dim, 0.1, 1.0);
  peri_mesh_free(&m);
  return rc;
}

/* Expects the read to fail with status 2 and a message holding the path and `entity`. */
static void expect_error(const char *path, peri_mesh_format f, int dim, const char *entity) {
  char msg[2048];
  read_args a = {path, f, dim};
  cr_assert_eq(captured(msg, sizeof msg, read_it, &a), PERI_ERR_INPUT, "%s: %s", path, msg);
  cr_assert(strstr(msg, path), "no file name in: %s", msg);
  cr_assert(strstr(msg, entity), "no '%s' in: %s", entity, msg);
}

static double total_volume(const peri_mesh *m) {
  double v = 0.0;
  for (int32_t k = 0; k < m->n; ++k) v += m->volume[k];
  return v;
}

static const peri_mesh_set *set_of(const peri_mesh *m, const char *name) {
  const peri_mesh_set *s = peri_mesh_find_set(m, name);
  cr_assert_not_null(s, "no set '%s'", name);
  return s;
}

/* ---------------------------------------------------------------- text node files */

Test(mesh_text, perilab_header_and_csv, .init = make_tmpdir, .fini = remove_tmpdir) {
  char path[128];
  snprintf(path, sizeof path, "%s/perilab.txt", tmpdir);
  /* PeriLab's header, columns in another order, an extra column; a 2 x 1 x 1 body of 8 cubes */
  FILE *f = fopen(path, "w");
  fprintf(f, "header: x y z volume block_id horizon\n");
  for (int k = 0; k < 8; ++k)
    fprintf(f, "%g %g %g 0.25 %d 0.3\n", 0.25 + 0.5 * (k % 4), 0.25 + 0.5 * ((k / 4) % 2), 0.5, 1 + (k % 4 >= 2));
  fclose(f);
  peri_mesh m;
  cr_assert_eq(peri_mesh_read(&m, path, PERI_MESH_TEXT, 3, 1, 1), PERI_OK);
  cr_assert_eq(m.n, 8);
  cr_assert_float_eq(total_volume(&m), 2.0, 1e-12);
  cr_assert_eq(m.n_blocks, 2);
  cr_assert_eq(m.blocks[m.block[2]].id, 2);
  cr_assert_eq(m.id[7], 8); /* node ids: 1-based line order */
  peri_mesh_free(&m);

  snprintf(path, sizeof path, "%s/nodes.csv", tmpdir);
  write_file(path, "\"x\",\"y\",\"block_id\",\"volume\"\n0.5,0.5,1,1.0\n1.5,0.5,1,1.0\n2.5,0.5,3,0.5\n");
  cr_assert_eq(peri_mesh_read(&m, path, peri_mesh_format_of(path), 2, 1, 1), PERI_OK);
  cr_assert_eq(m.n, 3);
  cr_assert_float_eq(total_volume(&m), 2.5, 1e-15);
  cr_assert_eq(m.x[3 * 2], 2.5);
  peri_mesh_free(&m);

  write_file(path, "x,y,block_id\n0.5,0.5,1\n");
  expect_error(path, PERI_MESH_TEXT, 2, "no column 'volume'");
  write_file(path, "x,y,block_id,volume\n0.5,0.5,1\n");
  expect_error(path, PERI_MESH_TEXT, 2, ":2: expected 4 numbers (x y block_id volume), got 3");
}

/* ---------------------------------------------------------------- Abaqus */

static const char *abaqus_3d =
    "*HEADING\n"
    "** two unit cubes side by side, a tetrahedron and a wedge on top, a pyramid below\n"
    "*NODE, NSET=NALL\n"
    "1, 0, 0, 0\n2, 1, 0, 0\n3, 2, 0, 0\n4, 0, 1, 0\n5, 1, 1, 0\n6, 2, 1, 0\n"
    "7, 0, 0, 1\n8, 1, 0, 1\n9, 2, 0, 1\n10, 0, 1, 1\n11, 1, 1, 1\n12, 2, 1, 1\n"
    "13, 0, 0, 2\n14, 1, 0, 2\n15, 2, 0, 2\n16, 1, 1, 2\n17, 0.5, 0.5, -1\n"
    "*Element, type=C3D8R, elset=Bricks\n"
    "1, 1, 2, 5, 4,\n  7, 8, 11, 10\n"
    "2, 2, 3, 6, 5, 8, 9, 12, 11\n"
    "*ELEMENT, TYPE=C3D4, ELSET=TETS\n"
    "3, 7, 8, 10, 13\n"
    "*ELEMENT, TYPE=C3D6, ELSET=WEDGES\n"
    "4, 8, 9, 11, 14, 15, 16\n"
    "*ELEMENT, TYPE=C3D5, ELSET=PYRAMIDS\n"
    "5, 1, 2, 5, 4, 17\n"
    "*NSET, NSET=LEFT\n1, 4, 7, 10\n"
    "*NSET, NSET=GEN, GENERATE\n1, 3, 1\n"
    "*ELSET, ELSET=TOP\nTETS, 4\n"
    "*MATERIAL, NAME=STEEL\n*ELASTIC\n200e9, 0.3\n";

Test(mesh_abaqus, three_dimensional, .init = make_tmpdir, .fini = remove_tmpdir) {
  char path[128];
  snprintf(path, sizeof path, "%s/body.inp", tmpdir);
  write_file(path, abaqus_3d);
  peri_mesh m;
  cr_assert_eq(peri_mesh_format_of(path), PERI_MESH_ABAQUS);
  cr_assert_eq(peri_mesh_read(&m, path, PERI_MESH_ABAQUS, 3, 1, 1), PERI_OK);
  cr_assert_eq(m.n, 5);
  /* two unit cubes, a tetrahedron of volume 1/6, a wedge of volume 1/2, a pyramid of 1/3 */
  cr_assert_float_eq(total_volume(&m), 2.0 + 1.0 / 6.0 + 0.5 + 1.0 / 3.0, 1e-12);
  cr_assert_float_eq(m.volume[4], 1.0 / 3.0, 1e-15);
  cr_assert_float_eq(m.x[3 * 4 + 2], -0.25, 1e-15); /* a pyramid's centroid: a quarter up from the base */
  cr_assert_eq(m.n_blocks, 4);
  cr_assert_str_eq(m.blocks[m.block[0]].name, "Bricks");
  cr_assert_eq(m.blocks[m.block[3]].id, 3);
  cr_assert_float_eq(m.x[0], 0.5, 1e-15); /* the first cube's centroid */
  cr_assert_float_eq(m.x[3 * 2 + 2], 1.25, 1e-15); /* the tetrahedron's */
  cr_assert_eq(set_of(&m, "LEFT")->count, 3);      /* cube 1, the tetrahedron and the pyramid touch x = 0 */
  cr_assert_eq(set_of(&m, "GEN")->count, 3);       /* nodes 1-3: the two cubes and the pyramid */
  cr_assert_eq(set_of(&m, "TOP")->count, 2);
  cr_assert_eq(set_of(&m, "bricks")->count, 2);    /* names are case-insensitive */
  peri_mesh_free(&m);
}

Test(mesh_abaqus, two_dimensional, .init = make_tmpdir, .fini = remove_tmpdir) {
  char path[128];
  snprintf(path, sizeof path, "%s/plate.inp", tmpdir);
  write_file(path, "*NODE\n1, 0, 0\n2, 1, 0\n3, 2, 0\n4, 0, 1\n5, 1, 1\n"
                   "*ELEMENT, TYPE=CPS4, ELSET=SQUARE\n1, 1, 2, 5, 4\n"
                   "*ELEMENT, TYPE=CPS3, ELSET=TRIANGLE\n2, 2, 3, 5\n"
                   "*ELEMENT, TYPE=T3D2, ELSET=EDGE\n3, 1, 4\n");
  peri_mesh m;
  cr_assert_eq(peri_mesh_read(&m, path, PERI_MESH_ABAQUS, 2, 0.1, 1), PERI_OK);
  cr_assert_eq(m.n, 2); /* the edge element is no point */
  cr_assert_float_eq(total_volume(&m), (1.0 + 0.5) * 0.1, 1e-15);
  cr_assert_eq(set_of(&m, "EDGE")->count, 1); /* the square, which has a node on the edge */
  peri_mesh_free(&m);
}

Test(mesh_abaqus, errors, .init = make_tmpdir, .fini = remove_tmpdir) {
  char path[128];
  snprintf(path, sizeof path, "%s/bad.inp", tmpdir);
  write_file(path, "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n"
                   "*NSET, NSET=CLAMP\n1, 99\n");
  expect_error(path, PERI_MESH_ABAQUS, 3, "NSET 'CLAMP' names node 99, which does not exist");
  write_file(path, "*NODE\n1, 0, 0, 0\n*ELEMENT, TYPE=XYZ9\n1, 1\n");
  expect_error(path, PERI_MESH_ABAQUS, 3, "unknown element type 'XYZ9'");
  write_file(path, "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 7\n");
  expect_error(path, PERI_MESH_ABAQUS, 3, "element 1 names node 7");
  write_file(path, "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n*ELEMENT, TYPE=C3D8\n1, 1, 2, 3,\n"); /* truncated */
  expect_error(path, PERI_MESH_ABAQUS, 3, "element 1 has too few nodes");
  snprintf(path, sizeof path, "%s/missing.inp", tmpdir);
  expect_error(path, PERI_MESH_ABAQUS, 3, "missing.inp");
}

/* ---------------------------------------------------------------- Exodus II */

#ifdef PERI_HAVE_EXODUS
enum { SIDE = 4 };
static const double EDGE = 2e-3; /* the cube's edge; spheres of volume (EDGE / SIDE)^3 */

/* Peridigm's sphere mesh of a cube: SIDE^3 SPHERE elements, one node each, attributes
 * (radius, volume); blocks 1 (z below the middle) and 2; node set 10 (unnamed) the bottom
 * layer, node set 20 "top" the top layer. `volume_attrs` 0 leaves the volumes out;
 * `bad_node` names a node beyond the mesh in set 20; `type` the element type. */
static void write_sphere_mesh(const char *path, int volume_attrs, int bad_node, const char *type) {
  int cpu = 8, io = 8;
  int exoid = ex_create(path, EX_CLOBBER, &cpu, &io);
  cr_assert_geq(exoid, 0);
  const int n = SIDE * SIDE * SIDE, half = n / 2;
  const double h = EDGE / SIDE;
  cr_assert_eq(ex_put_init(exoid, "spheres", 3, n, n, 2, 2, 0), 0);
  double x[SIDE * SIDE * SIDE], y[SIDE * SIDE * SIDE], z[SIDE * SIDE * SIDE];
  for (int k = 0; k < n; ++k) {
    x[k] = h * (0.5 + k % SIDE);
    y[k] = h * (0.5 + (k / SIDE) % SIDE);
    z[k] = h * (0.5 + k / (SIDE * SIDE));
  }
  cr_assert_eq(ex_put_coord(exoid, x, y, z), 0);
  for (int b = 0; b < 2; ++b) {
    cr_assert_eq(ex_put_elem_block(exoid, b + 1, type, half, 1, volume_attrs ? 2 : 0), 0);
    int conn[SIDE * SIDE * SIDE];
    double attr[2 * SIDE * SIDE * SIDE];
    for (int e = 0; e < half; ++e) {
      conn[e] = b * half + e + 1;
      attr[2 * e] = h * 0.62035049; /* radius of the sphere of volume h^3 (not read) */
      attr[2 * e + 1] = h * h * h;
    }
    cr_assert_eq(ex_put_elem_conn(exoid, b + 1, conn), 0);
    if (volume_attrs) cr_assert_eq(ex_put_elem_attr(exoid, b + 1, attr), 0);
  }
  int bottom[SIDE * SIDE], top[SIDE * SIDE];
  for (int k = 0; k < SIDE * SIDE; ++k) bottom[k] = k + 1, top[k] = n - SIDE * SIDE + k + 1;
  if (bad_node) top[3] = bad_node;
  cr_assert_eq(ex_put_node_set_param(exoid, 10, SIDE * SIDE, 0), 0);
  cr_assert_eq(ex_put_node_set(exoid, 10, bottom), 0);
  cr_assert_eq(ex_put_node_set_param(exoid, 20, SIDE * SIDE, 0), 0);
  cr_assert_eq(ex_put_node_set(exoid, 20, top), 0);
  cr_assert_eq(ex_put_name(exoid, EX_NODE_SET, 20, "top"), 0);
  cr_assert_eq(ex_close(exoid), 0);
}

Test(mesh_exodus, peridigm_sphere_mesh, .init = make_tmpdir, .fini = remove_tmpdir) {
  char path[128];
  snprintf(path, sizeof path, "%s/cube.g", tmpdir);
  write_sphere_mesh(path, 1, 0, "SPHERE");
  peri_mesh m;
  cr_assert_eq(peri_mesh_format_of(path), PERI_MESH_EXODUS);
  cr_assert_eq(peri_mesh_read(&m, path, PERI_MESH_EXODUS, 3, 1, 1), PERI_OK);
  cr_assert_eq(m.n, SIDE * SIDE * SIDE);
  cr_assert_float_eq(total_volume(&m), EDGE * EDGE * EDGE, 1e-12 * EDGE * EDGE * EDGE);
  cr_assert_eq(m.n_blocks, 2);
  cr_assert_eq(m.blocks[m.block[m.n - 1]].id, 2);
  const peri_mesh_set *bottom = set_of(&m, "nodelist_10"); /* Peridigm's name of an unnamed set */
  cr_assert_eq(bottom->count, SIDE * SIDE);
  for (int32_t k = 0; k < bottom->count; ++k) cr_assert_lt(m.x[3 * bottom->points[k] + 2], EDGE / SIDE);
  cr_assert_eq(set_of(&m, "top")->count, SIDE * SIDE);
  peri_mesh_free(&m);
}

/* PeriLab's sphere meshes: no attributes, the volume as the nodal variable "Volume". */
Test(mesh_exodus, perilab_nodal_volume, .init = make_tmpdir, .fini = remove_tmpdir) {
  char path[128];
  snprintf(path, sizeof path, "%s/nodal.e", tmpdir);
  write_sphere_mesh(path, 0, 0, "SPHERE");
  int cpu = 8, io = 8;
  float version;
  int exoid = ex_open(path, EX_WRITE, &cpu, &io, &version);
  cr_assert_geq(exoid, 0);
  char *names[] = {"Volume"};
  cr_assert_eq(ex_put_var_param(exoid, "n", 1), 0);
  cr_assert_eq(ex_put_var_names(exoid, "n", 1, names), 0);
  const double t = 0.0, h = EDGE / SIDE;
  cr_assert_eq(ex_put_time(exoid, 1, &t), 0);
  double v[SIDE * SIDE * SIDE];
  for (int k = 0; k < SIDE * SIDE * SIDE; ++k) v[k] = h * h * h;
  cr_assert_eq(ex_put_nodal_var(exoid, 1, 1, SIDE * SIDE * SIDE, v), 0);
  cr_assert_eq(ex_close(exoid), 0);
  peri_mesh m;
  cr_assert_eq(peri_mesh_read(&m, path, PERI_MESH_EXODUS, 3, 1, 1), PERI_OK);
  cr_assert_eq(m.n, SIDE * SIDE * SIDE);
  cr_assert_float_eq(total_volume(&m), EDGE * EDGE * EDGE, 1e-12 * EDGE * EDGE * EDGE);
  peri_mesh_free(&m);
}

/* A box [0,1] x [0,1] x [0,2] of 2 x 2 x 2 hexahedra whose shared middle node is moved:
 * the trilinear hexahedra still tile the box, so their volumes sum to 2. */
Test(mesh_exodus, hexahedra, .init = make_tmpdir, .fini = remove_tmpdir) {
  char path[128];
  snprintf(path, sizeof path, "%s/box.exo", tmpdir);
  int cpu = 8, io = 8;
  int exoid = ex_create(path, EX_CLOBBER, &cpu, &io);
  cr_assert_geq(exoid, 0);
  cr_assert_eq(ex_put_init(exoid, "box", 3, 27, 8, 1, 0, 0), 0);
  double x[27], y[27], z[27];
  for (int k = 0; k < 27; ++k) x[k] = 0.5 * (k % 3), y[k] = 0.5 * ((k / 3) % 3), z[k] = 1.0 * (k / 9);
  x[13] = 0.6, y[13] = 0.45, z[13] = 1.1; /* the middle node */
  cr_assert_eq(ex_put_coord(exoid, x, y, z), 0);
  int conn[64], e = 0;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i, ++e) {
        const int base = i + 3 * j + 9 * k + 1;
        const int c[8] = {base, base + 1, base + 4, base + 3, base + 9, base + 10, base + 13, base + 12};
        memcpy(&conn[8 * e], c, sizeof c);
      }
  cr_assert_eq(ex_put_elem_block(exoid, 7, "HEX8", 8, 8, 0), 0);
  cr_assert_eq(ex_put_elem_conn(exoid, 7, conn), 0);
  cr_assert_eq(ex_close(exoid), 0);
  peri_mesh m;
  cr_assert_eq(peri_mesh_read(&m, path, PERI_MESH_EXODUS, 3, 1, 1), PERI_OK);
  cr_assert_eq(m.n, 8);
  cr_assert_float_eq(total_volume(&m), 2.0, 1e-12);
  double moment[3] = {0, 0, 0}; /* the centroids weighted by volume: the box's centroid */
  for (int32_t k = 0; k < m.n; ++k)
    for (int d = 0; d < 3; ++d) moment[d] += m.volume[k] * m.x[3 * k + d];
  cr_assert_float_eq(moment[0] / 2.0, 0.5, 1e-12);
  cr_assert_float_eq(moment[1] / 2.0, 0.5, 1e-12);
  cr_assert_float_eq(moment[2] / 2.0, 1.0, 1e-12);
  cr_assert_str_eq(m.blocks[0].name, "block_7");
  peri_mesh_free(&m);
}

Test(mesh_exodus, errors, .init = make_tmpdir, .fini = remove_tmpdir) {
  char path[128], cut[128];
  snprintf(path, sizeof path, "%s/bad.e", tmpdir);
  write_sphere_mesh(path, 0, 0, "SPHERE");
  expect_error(path, PERI_MESH_EXODUS, 3, "block 'block_1' (id 1): SPHERE elements without volumes");
  write_sphere_mesh(path, 1, 999, "SPHERE");
  expect_error(path, PERI_MESH_EXODUS, 3, "node set 'top' (id 20) names node 999, which does not exist");
  write_sphere_mesh(path, 1, 0, "CIRCLE");
  expect_error(path, PERI_MESH_EXODUS, 3, "unknown element type 'CIRCLE'");
  /* a good file cut in its header, and cut in its data (netCDF reads the missing part as
   * zeros: the connectivity then names node 0) */
  write_sphere_mesh(path, 1, 0, "SPHERE");
  snprintf(cut, sizeof cut, "%s/cut.e", tmpdir);
  FILE *in = fopen(path, "rb");
  char buf[65536];
  size_t n = fread(buf, 1, sizeof buf, in);
  fclose(in);
  FILE *out = fopen(cut, "wb");
  fwrite(buf, 1, 200, out);
  fclose(out);
  expect_error(cut, PERI_MESH_EXODUS, 3, "cannot open as an Exodus II file");
  out = fopen(cut, "wb");
  fwrite(buf, 1, n / 2, out);
  fclose(out);
  expect_error(cut, PERI_MESH_EXODUS, 3, "element 1 names node 0, which does not exist");
  /* a header that counts fewer elements than the blocks hold (the blocks' elements were once
   * indexed past the header's count): the dimension num_elem of the classic netCDF header, its
   * name's length, the name and its length (4 bytes, big-endian), set to 4 */
  const char dim_name[] = "\0\0\0\x08num_elem";
  char *at = NULL;
  for (size_t k = 0; !at && k + sizeof dim_name - 1 + 4 <= n; ++k)
    if (memcmp(buf + k, dim_name, sizeof dim_name - 1) == 0) at = buf + k;
  cr_assert_not_null(at, "no dimension num_elem in the header");
  memcpy(at + sizeof dim_name - 1, "\0\0\0\x04", 4);
  out = fopen(cut, "wb");
  fwrite(buf, 1, n, out);
  fclose(out);
  expect_error(cut, PERI_MESH_EXODUS, 3, "gives 32 elements of 1 nodes and 2 attributes, but the header's 4 elements");
  /* a header whose variable name claims 264 characters for "connect2"'s 8: netCDF then parses
   * the rest of the header out of step and allocates and fills tens of GB (the reading runs in a
   * child process with a bound on its memory: refused, in a fraction of a second) */
  memcpy(at + sizeof dim_name - 1, "\0\0\0\x40", 4); /* (num_elem back to 64) */
  const char var_name[] = "\0\0\0\x08" "connect2";
  char *name_at = NULL;
  for (size_t k = 0; !name_at && k + sizeof var_name - 1 <= n; ++k)
    if (memcmp(buf + k, var_name, sizeof var_name - 1) == 0) name_at = buf + k;
  cr_assert_not_null(name_at, "no variable connect2 in the header");
  name_at[2] = 0x01;
  out = fopen(cut, "wb");
  fwrite(buf, 1, n, out);
  fclose(out);
  expect_error(cut, PERI_MESH_EXODUS, 3, "Exodus II");
  /* a node at an infinite coordinate (the bond search would span it) */
  write_sphere_mesh(path, 1, 0, "SPHERE");
  int cpu = 8, io = 8;
  float version;
  int exoid = ex_open(path, EX_WRITE, &cpu, &io, &version);
  cr_assert_geq(exoid, 0);
  double x[SIDE * SIDE * SIDE], y[SIDE * SIDE * SIDE], z[SIDE * SIDE * SIDE];
  cr_assert_eq(ex_get_coord(exoid, x, y, z), 0);
  x[5] = INFINITY;
  cr_assert_eq(ex_put_coord(exoid, x, y, z), 0);
  cr_assert_eq(ex_close(exoid), 0);
  expect_error(path, PERI_MESH_EXODUS, 3, "element 6 (block 'block_1') lies at x = inf; positions must be finite");
  snprintf(path, sizeof path, "%s/missing.e", tmpdir);
  expect_error(path, PERI_MESH_EXODUS, 3, "missing.e");
}
#else
Test(mesh_exodus, unavailable) {
  cr_assert_not(peri_mesh_format_available(PERI_MESH_EXODUS));
  cr_skip_test("built without the Exodus II library");
}
#endif

/* ---------------------------------------------------------------- Gmsh */

#ifdef PERI_HAVE_GMSH
/* An L-shaped plate: a 2 x 1 rectangle of 8 x 4 quadrangles ("plate") and a 1 x 1 square of
 * 4 x 4 x 2 triangles ("square") on its left half; "bottom" is the edge y = 0. */
static const char *l_plate_geo =
    "Point(1) = {0, 0, 0}; Point(2) = {2, 0, 0}; Point(3) = {2, 1, 0}; Point(4) = {1, 1, 0};\n"
    "Point(5) = {0, 1, 0}; Point(6) = {1, 2, 0}; Point(7) = {0, 2, 0};\n"
    "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 1};\n"
    "Line(6) = {4, 6}; Line(7) = {6, 7}; Line(8) = {7, 5};\n"
    "Curve Loop(1) = {1, 2, 3, 4, 5}; Plane Surface(1) = {1};\n"
    "Curve Loop(2) = {-4, 6, 7, 8}; Plane Surface(2) = {2};\n"
    "Transfinite Curve{1} = 9; Transfinite Curve{2, 3, 4, 5, 6, 7, 8} = 5;\n"
    "Transfinite Surface{1} = {1, 2, 3, 5}; Recombine Surface{1}; Transfinite Surface{2};\n"
    "Physical Surface(\"plate\") = {1}; Physical Surface(\"square\") = {2};\n"
    "Physical Curve(\"bottom\") = {1};\n";

/* Two boxes stacked: [0,1]^2 x [0,1] in 2 x 2 x 2 hexahedra ("lower") and [0,1]^2 x [1,3]
 * in 2 x 2 x 4 ("upper"); "base" is the face z = 0. */
static const char *stacked_boxes_geo =
    "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0}; Point(4) = {0, 1, 0};\n"
    "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
    "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
    "Transfinite Curve{1, 2, 3, 4} = 3; Transfinite Surface{1}; Recombine Surface{1};\n"
    "a[] = Extrude {0, 0, 1} { Surface{1}; Layers{2}; Recombine; };\n"
    "b[] = Extrude {0, 0, 2} { Surface{a[0]}; Layers{4}; Recombine; };\n"
    "Physical Volume(\"lower\") = {a[1]}; Physical Volume(\"upper\") = {b[1]};\n"
    "Physical Surface(\"base\") = {1};\n";

/* An unstructured tetrahedral mesh of the box [0,1] x [0,2] x [0,0.5], without physical groups. */
static const char *tet_box_geo =
    "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 2, 0.5};\nMesh.CharacteristicLengthMax = 0.3;\n";

/* Meshes a .geo with the Gmsh library and writes the .msh. */
static void gmsh_mesh(const char *geo_text, int dim, const char *msh) {
  char geo[160];
  snprintf(geo, sizeof geo, "%s.geo", msh);
  write_file(geo, geo_text);
  int ierr = 0;
  char *argv[] = {"test", NULL};
  gmshInitialize(1, argv, 0, &ierr);
  gmshOptionSetNumber("General.Terminal", 0, &ierr);
  gmshOpen(geo, &ierr);
  cr_assert_eq(ierr, 0);
  gmshModelMeshGenerate(dim, &ierr);
  cr_assert_eq(ierr, 0);
  gmshWrite(msh, &ierr);
  cr_assert_eq(ierr, 0);
  gmshFinalize(&ierr);
}

Test(mesh_gmsh, plate_2d, .init = make_tmpdir, .fini = remove_tmpdir) {
  char path[128];
  snprintf(path, sizeof path, "%s/plate.msh", tmpdir);
  gmsh_mesh(l_plate_geo, 2, path);
  peri_mesh m;
  cr_assert_eq(peri_mesh_read(&m, path, peri_mesh_format_of(path), 2, 0.1, 1), PERI_OK);
  cr_assert_eq(m.n, 32 + 32);
  cr_assert_float_eq(total_volume(&m), 3.0 * 0.1, 1e-12);
  cr_assert_eq(m.n_blocks, 2);
  cr_assert_eq(set_of(&m, "plate")->count, 32);
  cr_assert_eq(set_of(&m, "square")->count, 32);
  cr_assert_eq(set_of(&m, "bottom")->count, 8); /* the quadrangles on y = 0 */
  for (int32_t k = 0; k < m.n; ++k) cr_assert_eq(m.x[3 * k + 2], 0.0);
  peri_mesh_free(&m);
}

Test(mesh_gmsh, boxes_3d, .init = make_tmpdir, .fini = remove_tmpdir) {
  char path[128];
  snprintf(path, sizeof path, "%s/boxes.msh", tmpdir);
  gmsh_mesh(stacked_boxes_geo, 3, path);
  peri_mesh m;
  cr_assert_eq(peri_mesh_read(&m, path, PERI_MESH_GMSH, 3, 1, 1), PERI_OK);
  cr_assert_eq(m.n, 8 + 16);
  cr_assert_float_eq(total_volume(&m), 3.0, 1e-12);
  cr_assert_eq(set_of(&m, "lower")->count, 8);
  cr_assert_eq(set_of(&m, "upper")->count, 16);
  cr_assert_eq(set_of(&m, "base")->count, 4);
  peri_mesh_free(&m);

  snprintf(path, sizeof path, "%s/tets.msh", tmpdir);
  gmsh_mesh(tet_box_geo, 3, path);
  cr_assert_eq(peri_mesh_read(&m, path, PERI_MESH_GMSH, 3, 1, 1), PERI_OK);
  cr_assert_gt(m.n, 50);
  /* flat faces tile the box exactly; the nodes on them are placed by evaluating the OpenCASCADE
   * surfaces, a few ulps off the planes, hence a tolerance above round-off (3.4e-12 seen) */
  cr_assert_float_eq(total_volume(&m), 1.0, 1e-10, "volume %.17g", total_volume(&m));
  cr_assert_eq(m.n_blocks, 1);
  peri_mesh_free(&m);
}

Test(mesh_gmsh, errors, .init = make_tmpdir, .fini = remove_tmpdir) {
  char path[128];
  snprintf(path, sizeof path, "%s/plate.msh", tmpdir);
  gmsh_mesh(l_plate_geo, 2, path);
  /* a truncated file */
  FILE *f = fopen(path, "r+");
  fseek(f, 0, SEEK_END);
  long size = ftell(f);
  fclose(f);
  cr_assert_eq(truncate(path, size / 2), 0);
  expect_error(path, PERI_MESH_GMSH, 2, "plate.msh");
  write_file(path, "this is no mesh\n");
  expect_error(path, PERI_MESH_GMSH, 2, "plate.msh");
  snprintf(path, sizeof path, "%s/missing.msh", tmpdir);
  expect_error(path, PERI_MESH_GMSH, 2, "missing.msh");
}
#else
Test(mesh_gmsh, unavailable) {
  cr_assert_not(peri_mesh_format_available(PERI_MESH_GMSH));
  cr_skip_test("built without the Gmsh library");
}
#endif

/* ---------------------------------------------------------------- node set files */

Test(mesh_sets, node_set_file, .init = make_tmpdir, .fini = remove_tmpdir) {
  char path[128], ids[128];
  snprintf(path, sizeof path, "%s/nodes.txt", tmpdir);
  write_file(path, "0 0 1 1\n1 0 1 1\n2 0 1 1\n3 0 1 1\n");
  peri_mesh m;
  cr_assert_eq(peri_mesh_read(&m, path, PERI_MESH_TEXT, 2, 1, 1), PERI_OK);
  snprintf(ids, sizeof ids, "%s/set.txt", tmpdir);
  write_file(ids, "header: global_id\n4\n2 # a comment\n4, 2\n");
  int32_t *points = NULL, count = 0;
  cr_assert_eq(peri_node_set_file_read(&m, ids, &points, &count), PERI_OK);
  cr_assert_eq(count, 2);
  cr_assert_eq(points[0], 1);
  cr_assert_eq(points[1], 3);
  free(points);
  write_file(ids, "1\n5\n");
  char msg[1024];
  fflush(stderr);
  FILE *tmp = tmpfile();
  int saved = dup(2);
  dup2(fileno(tmp), 2);
  int rc = peri_node_set_file_read(&m, ids, &points, &count);
  fflush(stderr);
  dup2(saved, 2);
  close(saved);
  rewind(tmp);
  msg[fread(msg, 1, sizeof msg - 1, tmp)] = '\0';
  fclose(tmp);
  cr_assert_eq(rc, PERI_ERR_INPUT);
  cr_assert(strstr(msg, "set.txt:2: node 5 does not exist"), "%s", msg);
  peri_mesh_free(&m);
}
