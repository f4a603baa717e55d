/* Regions from the deck (src/deck/region_keys.c, src/core/region.c): booleans, blocks,
 * materials, mesh sets and node set files, each counted against the exact number of nodes. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include "peri/error.h"
#include "peri/region.h"
#include "support.h"

/* A 10 x 10 grid of unit cells (nodes at x, y = 0.5 .. 9.5): columns x < 8 are material a
 * (fill shape 1), x > 8 material b (fill shape 2). */
static const char *grid_deck =
    "dimension: 2\n"
    "materials:\n"
    "  a: {model: pmb, density: 1000, youngs_modulus: 1e9}\n"
    "  b: {model: pmb, density: 1000, youngs_modulus: 2e9}\n"
    "discretization:\n"
    "  spacing: 1\n"
    "  m: 3\n"
    "  fill:\n"
    "    - {shape: rectangle, min: [0, 0], max: [8, 10], material: a}\n"
    "    - {shape: rectangle, min: [8, 0], max: [10, 10], material: b}\n"
    "regions:\n"
    "  both:    {union: [left, low]}           # names a region defined below\n"
    "  left:    {shape: rectangle, min: [0, 0], max: [5, 10]}\n"
    "  low:     {shape: rectangle, min: [0, 0], max: [10, 3]}\n"
    "  corner:  {intersection: [left, low]}\n"
    "  upper_left: {difference: [left, low]}\n"
    "  ring:    {difference: [all, {shape: rectangle, min: [1, 1], max: [9, 9]}]}\n"
    "  soft:    {material: a}\n"
    "  blk2:    {block: 2}\n"
    "  mixed:   {union: [blk2, {intersection: [soft, low]}], no_fail: true}\n"
    "  three:   {intersection: [all, left, low, {material: [a, b]}]}\n"
    "solver: {type: explicit, steps: 1}\n"
    "output: {picture: false}\n";

static const peri_region *region(const peri_sim *s, const char *name) {
  for (int r = 0; r < s->cond.n_regions; ++r)
    if (strcmp(s->cond.regions[r].name, name) == 0) return &s->cond.regions[r];
  cr_assert_fail("no region %s", name);
  return NULL;
}

Test(regions, booleans_blocks_materials) {
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, grid_deck), PERI_OK);
  cr_assert_eq(s.disc.p.n, 100);
  cr_assert_eq(region(&s, "left")->count, 50);      /* 5 columns of 10 */
  cr_assert_eq(region(&s, "low")->count, 30);       /* 3 rows of 10 */
  cr_assert_eq(region(&s, "both")->count, 65);      /* 50 + 30 - 15 */
  cr_assert_eq(region(&s, "corner")->count, 15);
  cr_assert_eq(region(&s, "upper_left")->count, 35);
  cr_assert_eq(region(&s, "ring")->count, 100 - 64);
  cr_assert_eq(region(&s, "soft")->count, 80);
  cr_assert_eq(region(&s, "blk2")->count, 20);
  cr_assert_eq(region(&s, "mixed")->count, 20 + 24);
  cr_assert_eq(region(&s, "three")->count, 15);
  const peri_region *both = region(&s, "both");
  for (int32_t a = 1; a < both->count; ++a) cr_assert_lt(both->nodes[a - 1], both->nodes[a]);
  int32_t no_fail = 0;
  for (int32_t i = 0; i < s.disc.p.n; ++i) no_fail += (s.disc.p.flags[i] & PERI_NODE_NO_FAIL) != 0;
  cr_assert_eq(no_fail, 44);
  peri_sim_free(&s);
}

typedef struct {
  const char *yaml;
} deck_arg;

static int build_it(void *arg) {
  peri_sim s;
  int rc = sim_from_string(&s, ((deck_arg *)arg)->yaml);
  peri_sim_free(&s);
  return rc;
}

static void expect_deck_error(const char *regions, const char *want) {
  char yaml[4096], msg[2048];
  const char *cut = strstr(grid_deck, "regions:\n");
  const char *after = strstr(grid_deck, "solver:");
  snprintf(yaml, sizeof yaml, "%.*sregions:\n%s%s", (int)(cut - grid_deck), grid_deck, regions, after);
  deck_arg a = {yaml};
  fflush(stderr);
  FILE *tmp = tmpfile();
  int saved = dup(2);
  dup2(fileno(tmp), 2);
  int rc = build_it(&a);
  fflush(stderr);
  dup2(saved, 2);
  close(saved);
  rewind(tmp);
  msg[fread(msg, 1, sizeof msg - 1, tmp)] = '\0';
  fclose(tmp);
  cr_assert_eq(rc, PERI_ERR_INPUT, "%s", msg);
  cr_assert(strstr(msg, want), "no '%s' in: %s", want, msg);
}

Test(regions, errors) {
  expect_deck_error("  a: {union: [b]}\n  b: {union: [a, a]}\n", "at least two regions");
}

Test(regions, error_messages) {
  expect_deck_error("  a: {union: [b, all]}\n  b: {intersection: [a, all]}\n", "is defined through itself");
  expect_deck_error("  a: {union: [lefft, all]}\n", "unknown region 'lefft'");
  expect_deck_error("  a: {block: 7}\n", "no node is in block '7'");
  expect_deck_error("  a: {material: c}\n", "unknown material 'c'");
  expect_deck_error("  a: {node_set: top}\n", "no mesh file");
  expect_deck_error("  a: {block: 1, material: a}\n", "give exactly one of");
}

/* node_set and node_set_file regions on a node file, and on an Abaqus mesh. */
Test(regions, mesh_sets_and_files) {
  char dir[] = "/tmp/peri_regions_XXXXXX";
  cr_assert_not_null(mkdtemp(dir));
  char path[256], yaml[2048];
  snprintf(path, sizeof path, "%s/nodes.txt", dir);
  FILE *f = fopen(path, "w");
  fprintf(f, "header: x y block_id volume\n");
  for (int k = 0; k < 12; ++k) fprintf(f, "%d.5 0.5 %d 1\n", k, k < 4 ? 1 : 2);
  fclose(f);
  snprintf(path, sizeof path, "%s/ends.txt", dir);
  f = fopen(path, "w");
  fprintf(f, "header: global_id\n1\n12\n2\n");
  fclose(f);
  snprintf(path, sizeof path, "%s/body.inp", dir);
  f = fopen(path, "w");
  fprintf(f, "*NODE\n");
  for (int k = 0; k < 11; ++k) fprintf(f, "%d, %d, 0\n%d, %d, 1\n", 2 * k + 1, k, 2 * k + 2, k);
  fprintf(f, "*ELEMENT, TYPE=CPS4, ELSET=BAR\n");
  for (int k = 0; k < 10; ++k) fprintf(f, "%d, %d, %d, %d, %d\n", k + 1, 2 * k + 1, 2 * k + 3, 2 * k + 4, 2 * k + 2);
  fprintf(f, "*NSET, NSET=CLAMP\n1, 2\n*NSET, NSET=MIDDLE\n11, 12\n");
  fclose(f);

  const char *common = "dimension: 2\nmaterials:\n  a: {model: pmb, density: 1000, youngs_modulus: 1e9}\n"
                       "solver: {type: explicit, steps: 1}\noutput: {picture: false}\n";
  peri_sim s;
  snprintf(yaml, sizeof yaml, "%sdiscretization: {node_file: %s/nodes.txt, m: 3}\nregions:\n"
           "  ends: {node_set_file: ends.txt}\n  second: {block: 2}\n"
           "  end_of_second: {intersection: [ends, second]}\n", common, dir);
  /* the deck lives in dir: node_set_file is relative to it */
  snprintf(path, sizeof path, "%s/deck.yaml", dir);
  f = fopen(path, "w");
  fputs(yaml, f);
  fclose(f);
  cr_assert_eq(peri_sim_from_deck(&s, path), PERI_OK);
  cr_assert_eq(region(&s, "ends")->count, 3);
  cr_assert_eq(region(&s, "second")->count, 8);
  cr_assert_eq(region(&s, "end_of_second")->count, 1);
  const peri_region *e = region(&s, "end_of_second");
  cr_assert_float_eq(s.disc.p.x[3 * e->nodes[0]], 11.5, 1e-15); /* node 12 */
  peri_sim_free(&s);

  snprintf(yaml, sizeof yaml, "%sdiscretization: {mesh: body.inp, m: 3, thickness: 0.1}\nregions:\n"
           "  clamp: {node_set: CLAMP}\n  middle: {node_set: middle}\n  bar: {node_set: BAR}\n"
           "  inner: {difference: [bar, clamp, middle]}\n", common);
  f = fopen(path, "w");
  fputs(yaml, f);
  fclose(f);
  cr_assert_eq(peri_sim_from_deck(&s, path), PERI_OK);
  cr_assert_eq(s.disc.p.n, 10);
  cr_assert_eq(region(&s, "clamp")->count, 1);  /* the element with nodes 1, 2 */
  cr_assert_eq(region(&s, "middle")->count, 2); /* nodes 11, 12 are shared by elements 5 and 6 */
  cr_assert_eq(region(&s, "bar")->count, 10);
  cr_assert_eq(region(&s, "inner")->count, 7);
  peri_sim_free(&s);
  char cmd[300];
  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  cr_assert_eq(system(cmd), 0);
}
