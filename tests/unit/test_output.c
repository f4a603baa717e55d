/* Writers: files are written into a fresh directory under /tmp and read back. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <cairo.h>
#include <criterion/criterion.h>
#include <criterion/redirect.h>
#include <dirent.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include "peri/output.h"

/* ---- scratch directory ---- */

static char scratch_dir[64];

static void remove_tree(const char *path) {
  DIR *dir = opendir(path);
  if (!dir) {
    unlink(path);
    return;
  }
  struct dirent *entry;
  while ((entry = readdir(dir))) {
    if (!strcmp(entry->d_name, ".") || !strcmp(entry->d_name, "..")) continue;
    char child[512];
    snprintf(child, sizeof child, "%s/%s", path, entry->d_name);
    remove_tree(child);
  }
  closedir(dir);
  rmdir(path);
}

static void make_scratch(void) {
  strcpy(scratch_dir, "/tmp/peri_test_output_XXXXXX");
  cr_assert_not_null(mkdtemp(scratch_dir));
}

static void drop_scratch(void) { remove_tree(scratch_dir); }

/* Path of `name` inside the scratch directory (one static buffer per slot). */
static const char *scratch_path(int slot, const char *name) {
  static char paths[4][512];
  snprintf(paths[slot], sizeof paths[slot], "%s/%s", scratch_dir, name);
  return paths[slot];
}

static bool file_exists(const char *path) {
  struct stat info;
  return stat(path, &info) == 0;
}

static char *read_whole(const char *path, size_t *len_out) {
  FILE *in = fopen(path, "rb");
  cr_assert_not_null(in, "cannot open %s", path);
  fseek(in, 0, SEEK_END);
  long len = ftell(in);
  fseek(in, 0, SEEK_SET);
  char *text = malloc((size_t)len + 1);
  cr_assert_eq(fread(text, 1, (size_t)len, in), (size_t)len);
  text[len] = '\0';
  fclose(in);
  if (len_out) *len_out = (size_t)len;
  return text;
}

static int count_occurrences(const char *text, const char *needle) {
  int count = 0;
  for (const char *p = strstr(text, needle); p; p = strstr(p + 1, needle)) count++;
  return count;
}

/* The first line the code under test wrote on the (redirected) stderr. */
static void expect_error_mentions(const char *fragment) {
  fflush(stderr);
  char line[1024] = "";
  cr_assert_not_null(fgets(line, sizeof line, cr_get_redirected_stderr()));
  cr_expect(strstr(line, "peri: error: ") == line, "got: %s", line);
  cr_expect_not_null(strstr(line, fragment), "'%s' not in: %s", fragment, line);
}

/* ---- VTU reading: an independent base64 decoder and the VTK block layout ---- */

static int base64_value(char c) {
  static const char alphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const char *hit = c ? strchr(alphabet, c) : NULL;
  return hit ? (int)(hit - alphabet) : -1;
}

/* Decodes `len` characters of padded base64 (no whitespace inside). */
static unsigned char *base64_decode(const char *text, size_t len, size_t *out_len) {
  cr_assert_eq(len % 4, 0, "base64 length %zu is not a multiple of 4", len);
  unsigned char *out = malloc(len / 4 * 3 + 1);
  size_t used = 0;
  for (size_t i = 0; i < len; i += 4) {
    int v[4];
    int pad = 0;
    for (int k = 0; k < 4; k++) {
      if (text[i + k] == '=') {
        v[k] = 0;
        pad++;
      } else {
        v[k] = base64_value(text[i + k]);
        cr_assert_geq(v[k], 0, "bad base64 character '%c'", text[i + k]);
      }
    }
    uint32_t triple = (uint32_t)v[0] << 18 | (uint32_t)v[1] << 12 | (uint32_t)v[2] << 6 |
                      (uint32_t)v[3];
    out[used++] = (unsigned char)(triple >> 16);
    if (pad < 2) out[used++] = (unsigned char)(triple >> 8);
    if (pad < 1) out[used++] = (unsigned char)triple;
  }
  *out_len = used;
  return out;
}

/* The base64 text of the DataArray called `name` (whitespace trimmed). */
static const char *array_text(const char *xml, const char *name, size_t *len) {
  char key[128];
  snprintf(key, sizeof key, "Name=\"%s\"", name);
  const char *attr = strstr(xml, key);
  cr_assert_not_null(attr, "no DataArray %s", name);
  const char *start = strchr(attr, '>') + 1;
  while (*start == ' ' || *start == '\n') start++;
  const char *end = strchr(start, '<');
  while (end > start && (end[-1] == ' ' || end[-1] == '\n')) end--;
  *len = (size_t)(end - start);
  return start;
}

static size_t base64_chars(size_t bytes) { return (bytes + 2) / 3 * 4; }

/* The raw bytes of DataArray `name`, undoing base64 and, if `compressed`, zlib blocks. */
static unsigned char *array_bytes(const char *xml, const char *name, bool compressed,
                                  size_t *nbytes) {
  size_t len;
  const char *text = array_text(xml, name, &len);
  if (!compressed) {
    size_t decoded_len;
    unsigned char *decoded = base64_decode(text, len, &decoded_len);
    uint64_t declared;
    memcpy(&declared, decoded, sizeof declared);
    cr_assert_eq(decoded_len, sizeof declared + declared, "%s: header says %llu bytes", name,
                 (unsigned long long)declared);
    *nbytes = declared;
    memmove(decoded, decoded + sizeof declared, declared);
    return decoded;
  }
  /* Header and blocks are separate base64 streams; the block count sizes the header. */
  size_t first_len;
  unsigned char *first = base64_decode(text, base64_chars(8), &first_len);
  uint64_t nblocks;
  memcpy(&nblocks, first, 8);
  free(first);
  size_t header_bytes = 8 * (3 + nblocks);
  size_t header_len;
  unsigned char *header_raw = base64_decode(text, base64_chars(header_bytes), &header_len);
  cr_assert_eq(header_len, header_bytes);
  uint64_t *header = (uint64_t *)header_raw;
  cr_assert_eq(header[1], 32768);

  size_t packed_len;
  unsigned char *packed = base64_decode(text + base64_chars(header_bytes),
                                        len - base64_chars(header_bytes), &packed_len);
  size_t total = nblocks ? (nblocks - 1) * header[1] + header[2] : 0;
  unsigned char *out = malloc(total + 1);
  size_t in_pos = 0, out_pos = 0;
  for (uint64_t b = 0; b < nblocks; b++) {
    uLongf block_len = b + 1 < nblocks ? header[1] : header[2];
    uLongf got = block_len;
    cr_assert_eq(uncompress(out + out_pos, &got, packed + in_pos, header[3 + b]), Z_OK);
    cr_assert_eq(got, block_len);
    in_pos += header[3 + b];
    out_pos += block_len;
  }
  cr_assert_eq(in_pos, packed_len, "compressed sizes do not add up");
  free(packed);
  free(header_raw);
  *nbytes = total;
  return out;
}

/* Writes a frame with a vector, a scalar and an int field, and checks every array. */
static void check_vtu_round_trip(int32_t n, bool compress) {
  make_scratch();
  double *points = malloc(3 * (size_t)n * sizeof *points + 1);
  double *scalar = malloc((size_t)n * sizeof *scalar + 1);
  double *vector = malloc(3 * (size_t)n * sizeof *vector + 1);
  int32_t *flags = malloc((size_t)n * sizeof *flags + 1);
  for (int32_t i = 0; i < n; i++) {
    /* values whose decimal forms would not round-trip exactly */
    points[3 * i] = i / 3.0;
    points[3 * i + 1] = -1e-300 * (i + 1);
    points[3 * i + 2] = 1e300 / (i + 7);
    scalar[i] = sqrt(i + 0.1);
    for (int k = 0; k < 3; k++) vector[3 * i + k] = (k - 1) * acos(-1.0) * i;
    flags[i] = i % 2 ? -i : INT32_MAX - i;
  }
  peri_field fields[] = {
      {.name = "displacement", .ncomp = 3, .data = vector},
      {.name = "damage", .ncomp = 1, .data = scalar},
      {.name = "flags & <tags>", .ncomp = 1, .idata = flags},
  };
  const char *path = scratch_path(0, "frame.vtu");
  cr_assert_eq(peri_vtu_write(path, n, points, fields, 3, compress), 0);
  cr_assert(!file_exists(scratch_path(1, "frame.vtu.tmp")), "temporary file left behind");

  char *xml = read_whole(path, NULL);
  char expected[128];
  snprintf(expected, sizeof expected, "NumberOfPoints=\"%d\" NumberOfCells=\"%d\"", n, n);
  cr_expect_not_null(strstr(xml, expected));
  cr_expect_not_null(strstr(xml, "type=\"UnstructuredGrid\""));
  cr_expect_not_null(strstr(xml, "byte_order=\"LittleEndian\""));
  cr_expect_not_null(strstr(xml, "header_type=\"UInt64\""));
  cr_expect_eq(strstr(xml, "compressor=\"vtkZLibDataCompressor\"") != NULL, compress);
  cr_expect_not_null(strstr(xml, "Name=\"flags &amp; &lt;tags&gt;\""));
  cr_expect_eq(strncmp(xml + strlen(xml) - 11, "</VTKFile>\n", 11), 0);

  size_t nbytes;
  unsigned char *raw = array_bytes(xml, "Points", compress, &nbytes);
  cr_assert_eq(nbytes, 3 * (size_t)n * sizeof(double));
  cr_expect_eq(memcmp(raw, points, nbytes), 0, "points differ");
  free(raw);

  raw = array_bytes(xml, "displacement", compress, &nbytes);
  cr_assert_eq(nbytes, 3 * (size_t)n * sizeof(double));
  cr_expect_eq(memcmp(raw, vector, nbytes), 0, "vector field differs");
  free(raw);

  raw = array_bytes(xml, "damage", compress, &nbytes);
  cr_assert_eq(nbytes, (size_t)n * sizeof(double));
  cr_expect_eq(memcmp(raw, scalar, nbytes), 0, "scalar field differs");
  free(raw);

  raw = array_bytes(xml, "flags &amp; &lt;tags&gt;", compress, &nbytes);
  cr_assert_eq(nbytes, (size_t)n * sizeof(int32_t));
  cr_expect_eq(memcmp(raw, flags, nbytes), 0, "int field differs");
  free(raw);

  raw = array_bytes(xml, "connectivity", compress, &nbytes);
  cr_assert_eq(nbytes, (size_t)n * sizeof(int64_t));
  for (int32_t i = 0; i < n; i++) cr_assert_eq(((int64_t *)raw)[i], i);
  free(raw);

  raw = array_bytes(xml, "offsets", compress, &nbytes);
  cr_assert_eq(nbytes, (size_t)n * sizeof(int64_t));
  for (int32_t i = 0; i < n; i++) cr_assert_eq(((int64_t *)raw)[i], i + 1);
  free(raw);

  raw = array_bytes(xml, "types", compress, &nbytes);
  cr_assert_eq(nbytes, (size_t)n);
  for (int32_t i = 0; i < n; i++) cr_assert_eq(raw[i], 1);
  free(raw);

  free(xml);
  free(flags);
  free(vector);
  free(scalar);
  free(points);
  drop_scratch();
}

Test(vtu, small_uncompressed) { check_vtu_round_trip(3, false); }
Test(vtu, small_compressed) { check_vtu_round_trip(3, true); }
/* 2000 points: 48000 bytes of coordinates, so two zlib blocks with a short last one. */
Test(vtu, several_blocks_uncompressed) { check_vtu_round_trip(2000, false); }
Test(vtu, several_blocks_compressed) { check_vtu_round_trip(2000, true); }
/* 4096 doubles: exactly one full block, so the last block size equals the block size. */
Test(vtu, exact_block_compressed) { check_vtu_round_trip(4096, true); }
Test(vtu, empty_uncompressed) { check_vtu_round_trip(0, false); }
Test(vtu, empty_compressed) { check_vtu_round_trip(0, true); }

Test(vtu, replaces_existing_file) {
  make_scratch();
  const char *path = scratch_path(0, "frame.vtu");
  double p[3] = {1, 2, 3};
  cr_assert_eq(peri_vtu_write(path, 1, p, NULL, 0, false), 0);
  double q[6] = {4, 5, 6, 7, 8, 9};
  cr_assert_eq(peri_vtu_write(path, 2, q, NULL, 0, true), 0);
  char *xml = read_whole(path, NULL);
  cr_expect_not_null(strstr(xml, "NumberOfPoints=\"2\""));
  size_t nbytes;
  unsigned char *raw = array_bytes(xml, "Points", true, &nbytes);
  cr_expect_eq(nbytes, sizeof q);
  cr_expect_eq(memcmp(raw, q, sizeof q), 0);
  free(raw);
  free(xml);
  drop_scratch();
}

Test(vtu, missing_directory_is_reported, .init = cr_redirect_stderr) {
  make_scratch();
  const char *path = scratch_path(0, "no/such/dir/frame.vtu");
  double p[3] = {0, 0, 0};
  cr_assert_eq(peri_vtu_write(path, 1, p, NULL, 0, false), 1);
  char fragment[600];
  snprintf(fragment, sizeof fragment, "cannot write '%s': No such file or directory", path);
  expect_error_mentions(fragment);
  drop_scratch();
}

/* ---- PVD ---- */

static void expect_valid_pvd(const char *path, int n_frames) {
  char *xml = read_whole(path, NULL);
  cr_expect_eq(strncmp(xml, "<?xml version=\"1.0\"?>\n", 22), 0);
  cr_expect_not_null(strstr(xml, "<VTKFile type=\"Collection\""));
  cr_expect_eq(count_occurrences(xml, "<Collection>"), 1);
  cr_expect_eq(count_occurrences(xml, "</Collection>"), 1);
  cr_expect_eq(count_occurrences(xml, "<DataSet "), n_frames);
  cr_expect_eq(count_occurrences(xml, "/>"), n_frames);
  cr_expect_lt(strstr(xml, "<Collection>"), strstr(xml, "</Collection>"));
  cr_expect_eq(strcmp(xml + strlen(xml) - 11, "</VTKFile>\n"), 0);
  free(xml);
}

Test(pvd, rewritten_after_each_add) {
  make_scratch();
  const char *path = scratch_path(0, "run.pvd");
  peri_pvd *pvd = peri_pvd_open(path);
  cr_assert_not_null(pvd);
  expect_valid_pvd(path, 0);

  const double times[] = {0.0, 0.5, 1.0 / 3.0};
  const char *files[] = {"frames/f_0000.vtu", "frames/f_0001.vtu", "frames/f_0002.vtu"};
  const char *expected_lines[] = {
      "<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"frames/f_0000.vtu\"/>",
      "<DataSet timestep=\"0.5\" group=\"\" part=\"0\" file=\"frames/f_0001.vtu\"/>",
      "<DataSet timestep=\"0.333333333\" group=\"\" part=\"0\" file=\"frames/f_0002.vtu\"/>",
  };
  for (int k = 0; k < 3; k++) {
    cr_assert_eq(peri_pvd_add(pvd, times[k], files[k]), 0);
    expect_valid_pvd(path, k + 1);
    char *xml = read_whole(path, NULL);
    for (int j = 0; j <= k; j++)
      cr_expect_not_null(strstr(xml, expected_lines[j]), "frame %d missing after add %d", j, k);
    /* frames stay in the order they were added */
    if (k > 0) cr_expect_lt(strstr(xml, expected_lines[k - 1]), strstr(xml, expected_lines[k]));
    free(xml);
    cr_expect(!file_exists(scratch_path(1, "run.pvd.tmp")));
  }
  peri_pvd_close(pvd);
  expect_valid_pvd(path, 3);
  drop_scratch();
}

Test(pvd, escapes_file_names) {
  make_scratch();
  const char *path = scratch_path(0, "run.pvd");
  peri_pvd *pvd = peri_pvd_open(path);
  cr_assert_not_null(pvd);
  cr_assert_eq(peri_pvd_add(pvd, 1e-7, "a&b\"c.vtu"), 0);
  char *xml = read_whole(path, NULL);
  cr_expect_not_null(strstr(xml, "timestep=\"1e-07\""));
  cr_expect_not_null(strstr(xml, "file=\"a&amp;b&quot;c.vtu\""));
  free(xml);
  peri_pvd_close(pvd);
  drop_scratch();
}

Test(pvd, unwritable_path_gives_null, .init = cr_redirect_stderr) {
  make_scratch();
  const char *path = scratch_path(0, "missing/run.pvd");
  cr_expect_null(peri_pvd_open(path));
  expect_error_mentions("cannot write '");
  peri_pvd_close(NULL); /* harmless */
  drop_scratch();
}

/* ---- history.csv ---- */

Test(history, header_and_rows_flushed) {
  make_scratch();
  const char *path = scratch_path(0, "history.csv");
  const char *names[] = {"step", "time", "energy"};
  peri_history *h = peri_history_open(path, 3, names);
  cr_assert_not_null(h);
  char *text = read_whole(path, NULL);
  cr_expect_str_eq(text, "step,time,energy\n");
  free(text);

  const double row1[] = {1, 0.5, 1.2345678912345};
  const double row2[] = {2, 1e-12, -3};
  cr_assert_eq(peri_history_write(h, row1), 0);
  /* read back before close: each line must already be on disk */
  text = read_whole(path, NULL);
  cr_expect_str_eq(text, "step,time,energy\n1,0.5,1.234567891\n");
  free(text);
  cr_assert_eq(peri_history_write(h, row2), 0);
  text = read_whole(path, NULL);
  cr_expect_str_eq(text, "step,time,energy\n1,0.5,1.234567891\n2,1e-12,-3\n");
  free(text);
  peri_history_close(h);
  drop_scratch();
}

Test(history, quotes_awkward_names) {
  make_scratch();
  const char *path = scratch_path(0, "history.csv");
  const char *names[] = {"force,x", "say \"hi\""};
  peri_history *h = peri_history_open(path, 2, names);
  cr_assert_not_null(h);
  peri_history_close(h);
  char *text = read_whole(path, NULL);
  cr_expect_str_eq(text, "\"force,x\",\"say \"\"hi\"\"\"\n");
  free(text);
  drop_scratch();
}

Test(history, unwritable_path_gives_null, .init = cr_redirect_stderr) {
  make_scratch();
  const char *names[] = {"t"};
  const char *path = scratch_path(0, "missing/history.csv");
  cr_expect_null(peri_history_open(path, 1, names));
  expect_error_mentions("No such file or directory");
  drop_scratch();
}

/* ---- PNG ---- */

typedef struct png_info {
  uint32_t width, height;
} png_info;

/* Checks the signature and reads width/height from the IHDR chunk. */
static png_info read_png_header(const char *path) {
  size_t len;
  unsigned char *bytes = (unsigned char *)read_whole(path, &len);
  static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  cr_assert_geq(len, 24);
  cr_assert_eq(memcmp(bytes, signature, 8), 0, "not a PNG signature");
  cr_assert_eq(memcmp(bytes + 12, "IHDR", 4), 0);
  png_info info = {
      .width = (uint32_t)bytes[16] << 24 | (uint32_t)bytes[17] << 16 |
               (uint32_t)bytes[18] << 8 | bytes[19],
      .height = (uint32_t)bytes[20] << 24 | (uint32_t)bytes[21] << 16 |
                (uint32_t)bytes[22] << 8 | bytes[23],
  };
  free(bytes);
  return info;
}

typedef struct rgb8 {
  int r, g, b;
} rgb8;

static rgb8 pixel_at(cairo_surface_t *image, int x, int y) {
  const unsigned char *row =
      cairo_image_surface_get_data(image) + (size_t)y * cairo_image_surface_get_stride(image);
  uint32_t argb;
  memcpy(&argb, row + 4 * x, sizeof argb);
  return (rgb8){(argb >> 16) & 255, (argb >> 8) & 255, argb & 255};
}

static bool near_colour(rgb8 p, int r, int g, int b) {
  return abs(p.r - r) <= 3 && abs(p.g - g) <= 3 && abs(p.b - b) <= 3;
}

/* Pixels of one image column that are within a few levels of (r, g, b). */
static int count_in_column(cairo_surface_t *image, int x, int r, int g, int b) {
  int count = 0;
  for (int y = 0; y < cairo_image_surface_get_height(image); y++)
    if (near_colour(pixel_at(image, x, y), r, g, b)) count++;
  return count;
}

/* An odd-by-odd grid of unit spacing centred on x = 0, so its middle node lands in the
 * middle column of the image; that node gets `centre`, the others `rest`. */
static int32_t centred_grid(int nx, int ny, double centre, double rest, double **points,
                            double **values) {
  int32_t n = nx * ny;
  *points = malloc(3 * (size_t)n * sizeof **points);
  *values = malloc((size_t)n * sizeof **values);
  for (int j = 0; j < ny; j++)
    for (int i = 0; i < nx; i++) {
      int k = j * nx + i;
      (*points)[3 * k] = i - (nx - 1) / 2;
      (*points)[3 * k + 1] = j - (ny - 1) / 2;
      (*points)[3 * k + 2] = 0;
      (*values)[k] = (i == (nx - 1) / 2 && j == (ny - 1) / 2) ? centre : rest;
    }
  return n;
}

/* viridis ends, from matplotlib: #440154 and #fde725 */
enum { LOW_R = 0x44, LOW_G = 0x01, LOW_B = 0x54, TOP_R = 0xfd, TOP_G = 0xe7, TOP_B = 0x25 };

Test(png, size_signature_and_top_colour) {
  make_scratch();
  double *points, *values;
  int32_t n = centred_grid(11, 5, 1.0, 0.0, &points, &values);
  const char *path = scratch_path(0, "damage.png");
  cr_assert_eq(peri_png_write_field(path, n, points, values, 0.0, 1.0, 1.0, 400, "damage"), 0);
  cr_expect(!file_exists(scratch_path(1, "damage.png.tmp")));

  png_info info = read_png_header(path);
  cr_expect_eq(info.width, 400);
  /* wider than tall: 11 x 5 cloud */
  cr_expect_lt(info.height, info.width);

  cairo_surface_t *image = cairo_image_surface_create_from_png(path);
  cr_assert_eq(cairo_surface_status(image), CAIRO_STATUS_SUCCESS);
  cr_expect_eq(cairo_image_surface_get_width(image), 400);
  cr_expect_eq((uint32_t)cairo_image_surface_get_height(image), info.height);
  /* The middle column crosses the centre node (value vmax) and its vmin neighbours; each
   * square is about 400 / 11 px wide, so both runs are long. */
  int yellow = count_in_column(image, 200, TOP_R, TOP_G, TOP_B);
  int purple = count_in_column(image, 200, LOW_R, LOW_G, LOW_B);
  cr_expect_geq(yellow, 20, "only %d yellow pixels at the centre node", yellow);
  cr_expect_geq(purple, 80, "only %d purple pixels above and below it", purple);
  /* white background in the corner */
  cr_expect(near_colour(pixel_at(image, 1, 1), 255, 255, 255));
  cairo_surface_destroy(image);
  free(points);
  free(values);
  drop_scratch();
}

Test(png, nan_is_grey_and_range_from_data) {
  make_scratch();
  double *points, *values;
  int32_t n = centred_grid(7, 7, NAN, 2.0, &points, &values);
  values[0] = 5.0; /* a corner node holds the data maximum */
  const char *path = scratch_path(0, "nan.png");
  /* vmin >= vmax: the range comes from the finite data, [2, 5] */
  cr_assert_eq(peri_png_write_field(path, n, points, values, 0.0, 0.0, 1.0, 300, "t = 1"), 0);
  cairo_surface_t *image = cairo_image_surface_create_from_png(path);
  cr_assert_eq(cairo_surface_status(image), CAIRO_STATUS_SUCCESS);
  cr_expect_geq(count_in_column(image, 150, 153, 153, 153), 10, "no grey NaN node");
  cr_expect_geq(count_in_column(image, 150, LOW_R, LOW_G, LOW_B), 10, "2 is not vmin");
  /* the corner node (first column of nodes) is the data maximum, so yellow */
  int found_top = 0;
  for (int x = 0; x < 150; x++) found_top += count_in_column(image, x, TOP_R, TOP_G, TOP_B);
  cr_expect_geq(found_top, 100, "5 is not drawn as vmax");
  cairo_surface_destroy(image);
  free(points);
  free(values);
  drop_scratch();
}

Test(png, height_follows_aspect_ratio) {
  make_scratch();
  double *points, *values;
  int32_t n = centred_grid(3, 31, 0.0, 0.0, &points, &values);
  const char *tall = scratch_path(0, "tall.png");
  cr_assert_eq(peri_png_write_field(tall, n, points, values, 0, 1, 1.0, 200, "tall"), 0);
  free(points);
  free(values);
  n = centred_grid(31, 3, 0.0, 0.0, &points, &values);
  const char *wide = scratch_path(1, "wide.png");
  cr_assert_eq(peri_png_write_field(wide, n, points, values, 0, 1, 1.0, 200, "wide"), 0);
  png_info tall_info = read_png_header(tall), wide_info = read_png_header(wide);
  cr_expect_eq(tall_info.width, 200);
  cr_expect_eq(wide_info.width, 200);
  cr_expect_gt(tall_info.height, 2 * tall_info.width);
  cr_expect_lt(wide_info.height, wide_info.width);
  free(points);
  free(values);
  drop_scratch();
}

Test(png, empty_cloud_still_writes) {
  make_scratch();
  const char *path = scratch_path(0, "empty.png");
  cr_assert_eq(peri_png_write_field(path, 0, NULL, NULL, 0, 0, 0.1, 120, "nothing"), 0);
  png_info info = read_png_header(path);
  cr_expect_eq(info.width, 120);
  cr_expect_gt(info.height, 0);
  drop_scratch();
}

Test(png, tiny_dots_are_one_pixel) {
  make_scratch();
  double *points, *values;
  int32_t n = centred_grid(5, 5, 1.0, 0.0, &points, &values);
  for (int32_t i = 0; i < n; i++) points[3 * i] *= 1000, points[3 * i + 1] *= 1000;
  const char *path = scratch_path(0, "sparse.png");
  /* dot of 1e-6 model units is far below a pixel, but each node still shows */
  cr_assert_eq(peri_png_write_field(path, n, points, values, 0, 1, 1e-6, 101, NULL), 0);
  cairo_surface_t *image = cairo_image_surface_create_from_png(path);
  cr_assert_eq(cairo_surface_status(image), CAIRO_STATUS_SUCCESS);
  /* only the columns around the centre node: the colour bar's right end is yellow too */
  int yellow = 0;
  for (int x = 48; x <= 53; x++) yellow += count_in_column(image, x, TOP_R, TOP_G, TOP_B);
  cr_expect_geq(yellow, 1, "the vmax node vanished");
  cairo_surface_destroy(image);
  free(points);
  free(values);
  drop_scratch();
}

Test(png, unwritable_path_is_reported, .init = cr_redirect_stderr) {
  make_scratch();
  const char *path = scratch_path(0, "missing/x.png");
  double p[3] = {0, 0, 0}, v[1] = {1};
  cr_assert_eq(peri_png_write_field(path, 1, p, v, 0, 1, 1, 50, "x"), 1);
  expect_error_mentions("cannot write '");
  drop_scratch();
}

/* ---- mkdir -p ---- */

static bool is_dir(const char *path) {
  struct stat info;
  return stat(path, &info) == 0 && S_ISDIR(info.st_mode);
}

Test(mkdir_p, creates_nested_and_accepts_existing) {
  make_scratch();
  const char *nested = scratch_path(0, "a/b//c/");
  cr_assert_eq(peri_mkdir_p(nested), 0);
  cr_expect(is_dir(scratch_path(1, "a")));
  cr_expect(is_dir(scratch_path(1, "a/b")));
  cr_expect(is_dir(scratch_path(1, "a/b/c")));
  cr_expect_eq(peri_mkdir_p(nested), 0, "an existing directory is fine");
  cr_expect_eq(peri_mkdir_p(scratch_path(1, "a/b")), 0);
  cr_expect_eq(peri_mkdir_p("/"), 0);
  drop_scratch();
}

Test(mkdir_p, relative_path) {
  make_scratch();
  char cwd[512];
  cr_assert_not_null(getcwd(cwd, sizeof cwd));
  cr_assert_eq(chdir(scratch_dir), 0);
  cr_expect_eq(peri_mkdir_p("x/y"), 0);
  cr_expect(is_dir("x/y"));
  cr_assert_eq(chdir(cwd), 0);
  drop_scratch();
}

Test(mkdir_p, file_in_the_way, .init = cr_redirect_stderr) {
  make_scratch();
  const char *file = scratch_path(0, "plain");
  FILE *f = fopen(file, "w");
  cr_assert_not_null(f);
  fclose(f);
  cr_expect_eq(peri_mkdir_p(scratch_path(1, "plain/sub")), 1);
  char fragment[600];
  snprintf(fragment, sizeof fragment, "'%s' exists and is not a directory", file);
  expect_error_mentions(fragment);
  cr_expect_eq(peri_mkdir_p(file), 1);
  expect_error_mentions(fragment);
  drop_scratch();
}

/* ---- the picture with axes (docs/output.md section 4) ---- */

/* Dark pixels (text, ticks, frame) in a block of the image. */
static int dark_pixels(cairo_surface_t *image, int x0, int x1, int y0, int y1) {
  int count = 0;
  for (int y = y0; y < y1; y++)
    for (int x = x0; x < x1; x++) {
      rgb8 p = pixel_at(image, x, y);
      if (p.r < 80 && p.g < 80 && p.b < 80) count++;
    }
  return count;
}

Test(png, axes_add_ticks_labels_and_keep_the_width) {
  make_scratch();
  double *points, *values;
  int32_t n = centred_grid(11, 11, 1.0, 0.0, &points, &values);
  const char *plain = scratch_path(0, "plain.png"), *framed = scratch_path(1, "axes.png");
  cr_assert_eq(peri_png_write_field(plain, n, points, values, 0.0, 1.0, 1.0, 400, "damage"), 0);
  const peri_png_axes axes = {.x_label = "x [m]", .y_label = "y [m]", .value_label = "damage [1]"};
  cr_assert_eq(peri_png_write_field_axes(framed, n, points, values, 0.0, 1.0, 1.0, 400, "damage", &axes), 0);
  png_info a = read_png_header(plain), b = read_png_header(framed);
  cr_expect_eq(a.width, 400);
  cr_expect_eq(b.width, 400);
  /* the axes take room on the left: the square cloud is drawn narrower, hence less tall */
  cr_expect_gt(b.height, 0u);
  cairo_surface_t *pa = cairo_image_surface_create_from_png(plain), *pb = cairo_image_surface_create_from_png(framed);
  cr_assert_eq(cairo_surface_status(pb), CAIRO_STATUS_SUCCESS);
  /* the left margin is white without axes and holds the tick values and y label with them */
  const int margin = 16; /* 4% of 400 px */
  cr_expect_eq(dark_pixels(pa, 0, margin, 0, (int)a.height), 0);
  cr_expect_gt(dark_pixels(pb, 0, 80, 40, (int)b.height / 2), 50, "no tick values or y label left of the plot");
  /* the top node is still drawn in the highest colour (the cloud kept its colours) */
  int yellow = 0; /* in the upper half: the plot, not the colour bar at the bottom */
  for (int y = 0; y < (int)b.height / 2; y++)
    for (int x = 0; x < 400; x++) yellow += near_colour(pixel_at(pb, x, y), TOP_R, TOP_G, TOP_B);
  cr_expect_gt(yellow, 100, "the centre node (value 1) is not drawn yellow");
  cairo_surface_destroy(pa);
  cairo_surface_destroy(pb);
  free(points);
  free(values);
  drop_scratch();
}

/* The frame's time as FieldData TimeValue, all 17 digits (docs/output.md section 1). */
Test(vtu, time_value_field_data) {
  make_scratch();
  const char *timed = scratch_path(0, "timed.vtu"), *untimed = scratch_path(1, "untimed.vtu");
  double p[3] = {1, 2, 3};
  const double t = 1.0 / 3.0 * 1e-5;
  cr_assert_eq(peri_vtu_write_at(timed, t, 1, p, NULL, 0, true), 0);
  cr_assert_eq(peri_vtu_write(untimed, 1, p, NULL, 0, true), 0);
  FILE *in = fopen(timed, "r");
  cr_assert_not_null(in);
  char text[4096];
  size_t len = fread(text, 1, sizeof text - 1, in);
  fclose(in);
  text[len] = '\0';
  const char *at = strstr(text, "Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">");
  cr_assert_not_null(at, "no TimeValue in\n%s", text);
  cr_expect_eq(strtod(strchr(at, '>') + 1, NULL), t, "TimeValue is not the time to all digits");
  cr_expect(strstr(text, "<FieldData>") < strstr(text, "<Piece"), "FieldData must precede the Piece");
  in = fopen(untimed, "r");
  len = fread(text, 1, sizeof text - 1, in);
  fclose(in);
  text[len] = '\0';
  cr_expect_null(strstr(text, "TimeValue"), "peri_vtu_write writes no time");
  drop_scratch();
}
