/* VTK XML UnstructuredGrid (.vtu) writer: points as VTK_VERTEX cells, fields as PointData,
 * inline base64 binary data, optionally zlib-compressed. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>
#include "peri/error.h"
#include "peri/output.h"
#include "xml_escape.h"

/* Uncompressed size of one zlib block; 32 KiB is what VTK itself uses. */
enum { VTU_BLOCK_BYTES = 32768 };
enum { VTK_VERTEX = 1 };

typedef uint64_t vtu_header_t; /* matches header_type="UInt64" */

static const char BASE64_ALPHABET[] =
    "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/* Writes `len` bytes as one padded base64 stream. */
static void base64_write(FILE *out, const unsigned char *bytes, size_t len) {
  char chunk[4096]; /* multiple of 4 so whole quads fit */
  size_t used = 0;
  for (size_t i = 0; i < len; i += 3) {
    size_t left = len - i;
    uint32_t triple = (uint32_t)bytes[i] << 16;
    if (left > 1) triple |= (uint32_t)bytes[i + 1] << 8;
    if (left > 2) triple |= bytes[i + 2];
    chunk[used++] = BASE64_ALPHABET[(triple >> 18) & 63];
    chunk[used++] = BASE64_ALPHABET[(triple >> 12) & 63];
    chunk[used++] = left > 1 ? BASE64_ALPHABET[(triple >> 6) & 63] : '=';
    chunk[used++] = left > 2 ? BASE64_ALPHABET[triple & 63] : '=';
    if (used == sizeof chunk) {
      fwrite(chunk, 1, used, out);
      used = 0;
    }
  }
  fwrite(chunk, 1, used, out);
}

static bool host_is_little_endian(void) {
  const uint16_t probe = 1;
  return *(const unsigned char *)&probe == 1;
}

/* Uncompressed binary: one base64 stream of (byte count, data), as VTK reads it. */
static void write_raw_payload(FILE *out, const void *data, size_t nbytes) {
  unsigned char *joined = peri_malloc(sizeof(vtu_header_t) + nbytes);
  vtu_header_t header = nbytes;
  memcpy(joined, &header, sizeof header);
  if (nbytes) memcpy(joined + sizeof header, data, nbytes);
  base64_write(out, joined, sizeof header + nbytes);
  free(joined);
}

/* zlib binary: header [nblocks, block size, last block size, compressed sizes...] and the
 * concatenated compressed blocks, each encoded as its own base64 stream (VTK's layout). */
static int write_zlib_payload(FILE *out, const void *data, size_t nbytes) {
  size_t nblocks = (nbytes + VTU_BLOCK_BYTES - 1) / VTU_BLOCK_BYTES;
  vtu_header_t *header = peri_malloc((3 + nblocks) * sizeof *header);
  header[0] = nblocks;
  header[1] = VTU_BLOCK_BYTES;
  header[2] = nblocks ? nbytes - (nblocks - 1) * (size_t)VTU_BLOCK_BYTES : 0;

  /* the blocks are independent: compressed in parallel, each into its own slot, then packed
   * in order (the same bytes on any number of threads) */
  const size_t slot = compressBound(VTU_BLOCK_BYTES);
  unsigned char *packed = peri_malloc(nblocks * slot + 1);
  int status = 0;
#pragma omp parallel for schedule(dynamic, 4) reduction(| : status)
  for (size_t b = 0; b < nblocks; b++) {
    size_t offset = b * (size_t)VTU_BLOCK_BYTES;
    size_t block_len = nbytes - offset < VTU_BLOCK_BYTES ? nbytes - offset : VTU_BLOCK_BYTES;
    uLongf dest_len = slot;
    /* Level 1: output is written every few steps, so speed matters more than a few %. */
    if (compress2(packed + b * slot, &dest_len, (const Bytef *)data + offset, block_len, Z_BEST_SPEED) != Z_OK)
      status |= 1;
    header[3 + b] = dest_len;
  }
  status = status ? -1 : 0;
  size_t packed_len = 0;
  for (size_t b = 0; status == 0 && b < nblocks; b++) {
    memmove(packed + packed_len, packed + b * slot, header[3 + b]);
    packed_len += header[3 + b];
  }
  if (status == 0) {
    base64_write(out, (const unsigned char *)header, (3 + nblocks) * sizeof *header);
    base64_write(out, packed, packed_len);
  }
  free(packed);
  free(header);
  return status;
}

/* One <DataArray>. `ncomp` = 0 omits NumberOfComponents. */
static int write_data_array(FILE *out, const char *type, const char *name, int ncomp,
                            const void *data, size_t nbytes, bool compress) {
  fprintf(out, "        <DataArray type=\"%s\" Name=\"", type);
  peri_xml_attr_write(out, name);
  fputc('"', out);
  if (ncomp > 0) fprintf(out, " NumberOfComponents=\"%d\"", ncomp);
  fputs(" format=\"binary\">\n          ", out);
  int status = 0;
  if (compress)
    status = write_zlib_payload(out, data, nbytes);
  else
    write_raw_payload(out, data, nbytes);
  fputs("\n        </DataArray>\n", out);
  return status;
}

static int write_cells(FILE *out, int32_t n, bool compress) {
  size_t count = (size_t)n;
  int64_t *ids = peri_malloc(count * sizeof *ids);
  for (size_t i = 0; i < count; i++) ids[i] = (int64_t)i;
  int status = write_data_array(out, "Int64", "connectivity", 0, ids, count * sizeof *ids,
                                compress);
  /* offsets are one past each cell's last entry: 1..n for single-point cells */
  for (size_t i = 0; i < count; i++) ids[i] = (int64_t)i + 1;
  if (status == 0)
    status = write_data_array(out, "Int64", "offsets", 0, ids, count * sizeof *ids, compress);
  free(ids);
  if (status != 0) return status;

  unsigned char *types = peri_malloc(count);
  memset(types, VTK_VERTEX, count);
  status = write_data_array(out, "UInt8", "types", 0, types, count, compress);
  free(types);
  return status;
}

static int write_document(FILE *out, double time, int32_t n, const double *points, const peri_field *fields,
                          int n_fields, bool compress) {
  size_t count = (size_t)n;
  fputs("<?xml version=\"1.0\"?>\n", out);
  fprintf(out,
          "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"%s\""
          " header_type=\"UInt64\"%s>\n",
          host_is_little_endian() ? "LittleEndian" : "BigEndian",
          compress ? " compressor=\"vtkZLibDataCompressor\"" : "");
  fputs("  <UnstructuredGrid>\n", out);
  if (isfinite(time)) /* the frame's time, which ParaView shows when the file is opened alone */
    fprintf(out, "    <FieldData>\n      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
                 "format=\"ascii\">%.17g</DataArray>\n    </FieldData>\n", time);
  fprintf(out, "    <Piece NumberOfPoints=\"%d\" NumberOfCells=\"%d\">\n", (int)n, (int)n);

  int status = 0;
  fputs("      <PointData>\n", out);
  for (int f = 0; f < n_fields && status == 0; f++) {
    const peri_field *field = &fields[f];
    size_t values = count * (size_t)field->ncomp;
    if (field->idata)
      status = write_data_array(out, "Int32", field->name, field->ncomp, field->idata,
                                values * sizeof(int32_t), compress);
    else
      status = write_data_array(out, "Float64", field->name, field->ncomp, field->data,
                                values * sizeof(double), compress);
  }
  fputs("      </PointData>\n", out);
  if (status != 0) return status;

  fputs("      <Points>\n", out);
  status = write_data_array(out, "Float64", "Points", 3, points, 3 * count * sizeof(double),
                            compress);
  fputs("      </Points>\n", out);
  if (status != 0) return status;

  fputs("      <Cells>\n", out);
  status = write_cells(out, n, compress);
  fputs("      </Cells>\n", out);
  fputs("    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n", out);
  return status;
}

/* Checks the arguments the file format cannot represent; a bad frame is a caller bug, but a
 * message beats a crash. */
static bool frame_is_valid(const char *path, int32_t n, const double *points,
                           const peri_field *fields, int n_fields) {
  if (n < 0 || n_fields < 0 || (n > 0 && !points) || (n_fields > 0 && !fields)) {
    peri_error("cannot write '%s': invalid frame (n = %d, %d fields)", path, (int)n, n_fields);
    return false;
  }
  for (int f = 0; f < n_fields; f++) {
    const peri_field *field = &fields[f];
    const char *name = field->name ? field->name : "(unnamed)";
    if (!field->name || field->ncomp < 1 || (field->data && field->idata) ||
        (n > 0 && !field->data && !field->idata)) {
      peri_error("cannot write '%s': field '%s' needs a name, ncomp >= 1 and one data array",
                 path, name);
      return false;
    }
  }
  return true;
}

int peri_vtu_write(const char *path, int32_t n, const double *points,
                   const peri_field *fields, int n_fields, bool compress) {
  return peri_vtu_write_at(path, NAN, n, points, fields, n_fields, compress);
}

int peri_vtu_write_at(const char *path, double time, int32_t n, const double *points,
                      const peri_field *fields, int n_fields, bool compress) {
  if (!frame_is_valid(path, n, points, fields, n_fields)) return PERI_ERR_RUN;

  /* Written beside the target and renamed, so a reader never sees a half file. */
  size_t path_len = strlen(path);
  char *tmp_path = peri_malloc(path_len + sizeof ".tmp");
  memcpy(tmp_path, path, path_len);
  memcpy(tmp_path + path_len, ".tmp", sizeof ".tmp");

  FILE *out = fopen(tmp_path, "wb");
  if (!out) {
    peri_error("cannot write '%s': %s", path, strerror(errno));
    free(tmp_path);
    return PERI_ERR_RUN;
  }
  errno = 0;
  int status = write_document(out, time, n, points, fields, n_fields, compress);
  if (status != 0) {
    fclose(out);
    remove(tmp_path);
    peri_error("cannot write '%s': zlib compression failed", path);
    free(tmp_path);
    return PERI_ERR_RUN;
  }
  bool write_failed = ferror(out) != 0;
  int saved_errno = errno;
  if (fclose(out) != 0 && !write_failed) {
    write_failed = true;
    saved_errno = errno;
  }
  if (!write_failed && rename(tmp_path, path) != 0) {
    write_failed = true;
    saved_errno = errno;
  }
  if (write_failed) {
    remove(tmp_path);
    peri_error("cannot write '%s': %s", path, strerror(saved_errno ? saved_errno : EIO));
    free(tmp_path);
    return PERI_ERR_RUN;
  }
  free(tmp_path);
  return 0;
}
