/* The HDF5 file of a graph dataset (include/peri/dataset_file.h, docs/datasets.md). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/dataset_file.h"
#include "peri/error.h"

#ifdef PERI_HAVE_HDF5
#include <hdf5.h>

/* Rows of a chunk: a fixed number, so that a file's layout depends on its arrays' shapes
 * alone (2^16 rows of 3 doubles are 1.5 MiB, within HDF5's chunk cache). */
enum { CHUNK_ROWS = 1 << 16 };
/* deflate level: 4 compresses the smooth fields nearly as well as 9 at a fraction of the time */
enum { DEFLATE_LEVEL = 4 };

struct peri_dataset_file {
  hid_t file, dcpl, gcpl;
  char *path;
  char failed_at[512]; /* the first object that could not be written ("" while none) */
};

bool peri_dataset_file_supported(void) { return true; }

peri_dataset_file *peri_dataset_file_open(const char *path, bool append) {
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* our messages, not the library's error stack */
  peri_dataset_file *f = peri_calloc(1, sizeof *f);
  f->path = peri_strdup(path);
  /* no modification times anywhere: identical runs give identical files */
  f->dcpl = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_obj_track_times(f->dcpl, 0);
  f->gcpl = H5Pcreate(H5P_GROUP_CREATE);
  H5Pset_obj_track_times(f->gcpl, 0);
  if (append) {
    f->file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
  } else {
    hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
    H5Pset_obj_track_times(fcpl, 0);
    /* the HDF5 1.10 format (any h5py of the last years reads it): checksummed headers, and
     * small chunk indexes (a v1 B-tree node per dataset would add ~40 KB to every frame) */
    hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    H5Pset_libver_bounds(fapl, H5F_LIBVER_V110, H5F_LIBVER_V110);
    f->file = H5Fcreate(path, H5F_ACC_TRUNC, fcpl, fapl);
    H5Pclose(fapl);
    H5Pclose(fcpl);
  }
  if (f->file < 0) {
    peri_error("cannot %s the graph dataset '%s' (HDF5)", append ? "open" : "create", path);
    H5Pclose(f->dcpl);
    H5Pclose(f->gcpl);
    free(f->path);
    free(f);
    return NULL;
  }
  return f;
}

static void failed(peri_dataset_file *f, const char *path) {
  if (!f->failed_at[0]) snprintf(f->failed_at, sizeof f->failed_at, "%s", path[0] ? path : "/");
}

int peri_dataset_file_close(peri_dataset_file *f) {
  if (!f) return PERI_OK;
  if (H5Fclose(f->file) < 0) failed(f, "/");
  H5Pclose(f->dcpl);
  H5Pclose(f->gcpl);
  const int rc = f->failed_at[0] ? PERI_ERR_RUN : PERI_OK;
  if (rc != PERI_OK) peri_error("cannot write the graph dataset '%s': HDF5 failed at '%s' (disk full?)", f->path, f->failed_at);
  free(f->path);
  free(f);
  return rc;
}

void peri_dataset_file_group(peri_dataset_file *f, const char *path) {
  if (f->failed_at[0]) return;
  hid_t g = H5Gcreate2(f->file, path, H5P_DEFAULT, f->gcpl, H5P_DEFAULT);
  if (g < 0) failed(f, path);
  else H5Gclose(g);
}

static void array_put(peri_dataset_file *f, const char *path, hid_t file_type, hid_t mem_type, int64_t rows, int cols,
                      const void *data) {
  if (f->failed_at[0]) return;
  const hsize_t dims[2] = {(hsize_t)rows, (hsize_t)cols};
  const int rank = cols > 1 ? 2 : 1;
  hid_t space = H5Screate_simple(rank, dims, NULL);
  hid_t dcpl = H5Pcopy(f->dcpl);
  if (rows > 0) {
    const hsize_t chunk[2] = {rows < CHUNK_ROWS ? (hsize_t)rows : CHUNK_ROWS, (hsize_t)cols};
    if (H5Pset_chunk(dcpl, rank, chunk) < 0 || H5Pset_shuffle(dcpl) < 0 || H5Pset_deflate(dcpl, DEFLATE_LEVEL) < 0)
      failed(f, path);
  }
  hid_t d = H5Dcreate2(f->file, path, file_type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  if (d < 0 || (rows > 0 && H5Dwrite(d, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)) failed(f, path);
  if (d >= 0) H5Dclose(d);
  H5Pclose(dcpl);
  H5Sclose(space);
}

void peri_dataset_file_doubles(peri_dataset_file *f, const char *path, int64_t rows, int cols, const double *data) {
  array_put(f, path, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, rows, cols, data);
}

void peri_dataset_file_ints(peri_dataset_file *f, const char *path, int64_t rows, int cols, const int32_t *data) {
  array_put(f, path, H5T_STD_I32LE, H5T_NATIVE_INT32, rows, cols, data);
}

void peri_dataset_file_bytes(peri_dataset_file *f, const char *path, int64_t rows, const uint8_t *data) {
  array_put(f, path, H5T_STD_U8LE, H5T_NATIVE_UINT8, rows, 1, data);
}

static hid_t string_type(size_t length) {
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, length > 0 ? length : 1);
  H5Tset_strpad(t, H5T_STR_NULLPAD);
  return t;
}

void peri_dataset_file_strings(peri_dataset_file *f, const char *path, int count, const char *const *text) {
  if (f->failed_at[0]) return;
  size_t width = 1;
  for (int k = 0; k < count; ++k) width = strlen(text[k]) > width ? strlen(text[k]) : width;
  char *packed = peri_calloc((size_t)(count > 0 ? count : 1), width);
  for (int k = 0; k < count; ++k) memcpy(packed + (size_t)k * width, text[k], strlen(text[k]));
  hid_t t = string_type(width);
  const hsize_t dims[1] = {(hsize_t)count};
  hid_t space = H5Screate_simple(1, dims, NULL);
  hid_t d = H5Dcreate2(f->file, path, t, space, H5P_DEFAULT, f->dcpl, H5P_DEFAULT);
  if (d < 0 || (count > 0 && H5Dwrite(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, packed) < 0)) failed(f, path);
  if (d >= 0) H5Dclose(d);
  H5Sclose(space);
  H5Tclose(t);
  free(packed);
}

static void attr_put(peri_dataset_file *f, const char *path, const char *name, hid_t file_type, hid_t mem_type,
                     const void *value) {
  if (f->failed_at[0]) return;
  hid_t o = H5Oopen(f->file, path[0] ? path : "/", H5P_DEFAULT);
  hid_t space = H5Screate(H5S_SCALAR);
  /* an attribute written again (the frame count) is overwritten in place */
  const htri_t exists = o >= 0 ? H5Aexists(o, name) : 0;
  hid_t a = o < 0 ? -1 : exists > 0 ? H5Aopen(o, name, H5P_DEFAULT) : H5Acreate2(o, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT);
  if (a < 0 || H5Awrite(a, mem_type, value) < 0) failed(f, path);
  if (a >= 0) H5Aclose(a);
  H5Sclose(space);
  if (o >= 0) H5Oclose(o);
}

void peri_dataset_file_attr_double(peri_dataset_file *f, const char *path, const char *name, double value) {
  attr_put(f, path, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
}

void peri_dataset_file_attr_long(peri_dataset_file *f, const char *path, const char *name, long value) {
  const long long v = value;
  attr_put(f, path, name, H5T_STD_I64LE, H5T_NATIVE_LLONG, &v);
}

void peri_dataset_file_attr_string(peri_dataset_file *f, const char *path, const char *name, const char *value) {
  hid_t t = string_type(strlen(value));
  attr_put(f, path, name, t, t, value[0] ? value : "");
  H5Tclose(t);
}

#else /* without HDF5: the deck refuses output.dataset (src/deck/dataset_keys.c) */

bool peri_dataset_file_supported(void) { return false; }
peri_dataset_file *peri_dataset_file_open(const char *path, bool append) {
  (void)append;
  peri_error("cannot write the graph dataset '%s': this peri was built without HDF5", path);
  return NULL;
}
int peri_dataset_file_close(peri_dataset_file *f) { (void)f; return PERI_OK; }
void peri_dataset_file_group(peri_dataset_file *f, const char *path) { (void)f, (void)path; }
void peri_dataset_file_doubles(peri_dataset_file *f, const char *path, int64_t rows, int cols, const double *data) {
  (void)f, (void)path, (void)rows, (void)cols, (void)data;
}
void peri_dataset_file_ints(peri_dataset_file *f, const char *path, int64_t rows, int cols, const int32_t *data) {
  (void)f, (void)path, (void)rows, (void)cols, (void)data;
}
void peri_dataset_file_bytes(peri_dataset_file *f, const char *path, int64_t rows, const uint8_t *data) {
  (void)f, (void)path, (void)rows, (void)data;
}
void peri_dataset_file_strings(peri_dataset_file *f, const char *path, int count, const char *const *text) {
  (void)f, (void)path, (void)count, (void)text;
}
void peri_dataset_file_attr_double(peri_dataset_file *f, const char *path, const char *name, double value) {
  (void)f, (void)path, (void)name, (void)value;
}
void peri_dataset_file_attr_long(peri_dataset_file *f, const char *path, const char *name, long value) {
  (void)f, (void)path, (void)name, (void)value;
}
void peri_dataset_file_attr_string(peri_dataset_file *f, const char *path, const char *name, const char *value) {
  (void)f, (void)path, (void)name, (void)value;
}
#endif
