/* Parallel VTK unstructured grid (.pvtu): the index of the pieces that the ranks of a
 * distributed run write, one .vtu each (docs/parallel.md). */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/output.h"
#include "xml_escape.h"

int peri_pvtu_write(const char *path, const char *const *pieces, int n_pieces, const peri_field *fields,
                    int n_fields) {
  size_t len = strlen(path);
  char *tmp = peri_malloc(len + sizeof ".tmp");
  memcpy(tmp, path, len);
  memcpy(tmp + len, ".tmp", sizeof ".tmp");
  FILE *out = fopen(tmp, "w");
  if (!out) {
    peri_error("cannot write '%s': %s", path, strerror(errno));
    free(tmp);
    return PERI_ERR_RUN;
  }
  const uint16_t probe = 1;
  fputs("<?xml version=\"1.0\"?>\n", out);
  fprintf(out, "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"%s\" header_type=\"UInt64\">\n",
          *(const unsigned char *)&probe == 1 ? "LittleEndian" : "BigEndian");
  fputs("  <PUnstructuredGrid GhostLevel=\"0\">\n    <PPointData>\n", out);
  for (int f = 0; f < n_fields; ++f) {
    fprintf(out, "      <PDataArray type=\"%s\" Name=\"", fields[f].idata ? "Int32" : "Float64");
    peri_xml_attr_write(out, fields[f].name);
    fprintf(out, "\" NumberOfComponents=\"%d\"/>\n", fields[f].ncomp);
  }
  fputs("    </PPointData>\n    <PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" "
        "NumberOfComponents=\"3\"/>\n    </PPoints>\n", out);
  for (int k = 0; k < n_pieces; ++k) {
    fputs("    <Piece Source=\"", out);
    peri_xml_attr_write(out, pieces[k]);
    fputs("\"/>\n", out);
  }
  fputs("  </PUnstructuredGrid>\n</VTKFile>\n", out);
  bool failed = ferror(out) != 0;
  int saved = errno;
  if (fclose(out) != 0 && !failed) failed = true, saved = errno;
  if (!failed && rename(tmp, path) != 0) failed = true, saved = errno;
  if (failed) {
    remove(tmp);
    peri_error("cannot write '%s': %s", path, strerror(saved ? saved : EIO));
  }
  free(tmp);
  return failed ? PERI_ERR_RUN : PERI_OK;
}
