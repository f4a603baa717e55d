/* Images of phases (docs/microstructures.md): PNG files read with libpng into RGBA (any
 * colour type, the file's own 8-bit values), the phase of a point of an image placed in the
 * plane (pixel edges belong to the pixel above and to the right, points just outside to the
 * edge pixels), and grids filled from an image: one node per pixel centre at a spacing of one
 * pixel, the pixel's material, no node on a void pixel; later fill shapes override it. */
#include <criterion/criterion.h>
#include "scratch_dir.h"
#include <png.h>
#include <string.h>
#include "peri/discretize.h"
#include "peri/error.h"
#include "peri/image_reader.h"

TestSuite(phase_map, .init = make_tmpdir, .fini = remove_tmpdir);

static void write_png(const char *path, int w, int h, png_uint_32 format, const uint8_t *pixels) {
  png_image image;
  memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  image.width = (png_uint_32)w, image.height = (png_uint_32)h, image.format = format;
  cr_assert(png_image_write_to_file(&image, path, 0, pixels, 0, NULL), "%s", image.message);
}

Test(phase_map, reads_rgb_and_grey_pngs) {
  char path[128];
  snprintf(path, sizeof path, "%s/rgb.png", tmpdir);
  const uint8_t rgb[3 * 3 * 2] = {255, 255, 255, 0, 0, 0, 255, 0, 0, 1, 2, 3, 200, 100, 50, 0, 255, 0};
  write_png(path, 3, 2, PNG_FORMAT_RGB, rgb);
  int w = 0, h = 0;
  uint8_t *px = NULL;
  cr_assert_eq(peri_image_read_rgba(path, &w, &h, &px), PERI_OK);
  cr_assert(w == 3 && h == 2);
  for (int k = 0; k < 6; ++k)
    for (int c = 0; c < 3; ++c) cr_expect_eq(px[4 * k + c], rgb[3 * k + c], "pixel %d channel %d", k, c);
  free(px);
  snprintf(path, sizeof path, "%s/grey.png", tmpdir);
  const uint8_t grey[2] = {17, 240};
  write_png(path, 2, 1, PNG_FORMAT_GRAY, grey);
  cr_assert_eq(peri_image_read_rgba(path, &w, &h, &px), PERI_OK);
  for (int k = 0; k < 2; ++k)
    cr_expect(px[4 * k] == grey[k] && px[4 * k + 1] == grey[k] && px[4 * k + 2] == grey[k], "grey pixel %d", k);
  free(px);
}

Test(phase_map, unreadable_files_are_input_errors) {
  char path[128];
  int w, h;
  uint8_t *px = NULL;
  snprintf(path, sizeof path, "%s/missing.png", tmpdir);
  cr_expect_eq(peri_image_read_rgba(path, &w, &h, &px), PERI_ERR_INPUT);
  snprintf(path, sizeof path, "%s/text.png", tmpdir);
  write_file(path, "not an image\n");
  cr_expect_eq(peri_image_read_rgba(path, &w, &h, &px), PERI_ERR_INPUT);
  cr_expect_null(px);
}

/* 3 x 2 pixels of 0.5, lower-left corner (1, 2): top row 0 1 2, bottom row 3 4 5 */
static int32_t phases[6] = {0, 1, 2, 3, 4, 5};
static const peri_phase_map map = {3, 2, 0.5, {1.0, 2.0}, phases};

Test(phase_map, pixel_of_a_point) {
  const double centre_top_right[3] = {2.25, 2.75, 0}, centre_bottom_left[3] = {1.25, 2.25, 0};
  cr_expect_eq(peri_phase_map_at(&map, centre_top_right), 2);
  cr_expect_eq(peri_phase_map_at(&map, centre_bottom_left), 3);
  const double edge[3] = {1.5, 2.5, 0}; /* the corner of four pixels: the one above and to the right */
  cr_expect_eq(peri_phase_map_at(&map, edge), 1);
  const double outside[3] = {1.0 - 1e-12, 3.0 + 1e-12, 0}; /* the top-left corner, just outside */
  cr_expect_eq(peri_phase_map_at(&map, outside), 0);
}

Test(phase_map, grid_from_an_image) {
  int32_t ph[6] = {0, PERI_PHASE_VOID, 1, 1, 0, 0};
  peri_phase_map m = {3, 2, 0.5, {1.0, 2.0}, ph};
  peri_fill fill[2] = {{.material = PERI_PHASE_VOID, .phases = &m}, {.material = 2}};
  fill[0].shape.kind = PERI_SHAPE_BOX;
  fill[0].shape.min[0] = 1.0, fill[0].shape.min[1] = 2.0, fill[0].shape.max[0] = 2.5, fill[0].shape.max[1] = 3.0;
  peri_grid_params g = {.dim = 2, .spacing = 0.5, .thickness = 1.0, .n_fill = 1, .fill = fill};
  peri_particles p;
  cr_assert_eq(peri_grid_generate(&p, &g), 5, "one node per pixel but the void one");
  int count[2] = {0, 0};
  for (int32_t i = 0; i < p.n; ++i) {
    const int32_t expect = peri_phase_map_at(&m, &p.x[3 * i]);
    cr_expect_eq(p.material[i], expect);
    cr_expect(!(p.x[3 * i] == 1.75 && p.x[3 * i + 1] == 2.75), "a node on the void pixel");
    count[p.material[i]]++;
  }
  cr_expect(count[0] == 3 && count[1] == 2, "materials %d, %d", count[0], count[1]);
  peri_particles_free(&p);
  /* a later shape over the void pixel fills it with its material */
  fill[1].shape.kind = PERI_SHAPE_BOX;
  fill[1].shape.min[0] = 1.5, fill[1].shape.min[1] = 2.5, fill[1].shape.max[0] = 2.0, fill[1].shape.max[1] = 3.0;
  g.n_fill = 2;
  cr_assert_eq(peri_grid_generate(&p, &g), 6);
  int inclusion = 0;
  for (int32_t i = 0; i < p.n; ++i) inclusion += p.material[i] == 2;
  cr_expect_eq(inclusion, 1);
  peri_particles_free(&p);
}
