/* ParaView .pvd collection: the list of frames (time, file) is kept in memory and the whole
 * file is rewritten, through a temporary and a rename, after every frame. */
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

typedef struct pvd_frame {
  double time;
  char *file;
} pvd_frame;

struct peri_pvd {
  char *path;
  char *tmp_path;
  pvd_frame *frames;
  size_t n_frames, capacity;
};

static const char *host_byte_order(void) {
  const uint16_t probe = 1;
  return *(const unsigned char *)&probe == 1 ? "LittleEndian" : "BigEndian";
}

/* Writes the whole collection; returns 0 or PERI_ERR_RUN with a message. */
static int pvd_rewrite(const peri_pvd *pvd) {
  FILE *out = fopen(pvd->tmp_path, "w");
  if (!out) {
    peri_error("cannot write '%s': %s", pvd->path, strerror(errno));
    return PERI_ERR_RUN;
  }
  errno = 0;
  fputs("<?xml version=\"1.0\"?>\n", out);
  fprintf(out, "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"%s\">\n",
          host_byte_order());
  fputs("  <Collection>\n", out);
  for (size_t i = 0; i < pvd->n_frames; i++) {
    fprintf(out, "    <DataSet timestep=\"%.9g\" group=\"\" part=\"0\" file=\"",
            pvd->frames[i].time);
    peri_xml_attr_write(out, pvd->frames[i].file);
    fputs("\"/>\n", out);
  }
  fputs("  </Collection>\n</VTKFile>\n", out);

  bool failed = ferror(out) != 0;
  int saved_errno = errno;
  if (fclose(out) != 0 && !failed) {
    failed = true;
    saved_errno = errno;
  }
  if (!failed && rename(pvd->tmp_path, pvd->path) != 0) {
    failed = true;
    saved_errno = errno;
  }
  if (failed) {
    remove(pvd->tmp_path);
    peri_error("cannot write '%s': %s", pvd->path, strerror(saved_errno ? saved_errno : EIO));
    return PERI_ERR_RUN;
  }
  return 0;
}

peri_pvd *peri_pvd_open(const char *path) {
  peri_pvd *pvd = peri_calloc(1, sizeof *pvd);
  pvd->path = peri_strdup(path);
  size_t path_len = strlen(path);
  pvd->tmp_path = peri_malloc(path_len + sizeof ".tmp");
  memcpy(pvd->tmp_path, path, path_len);
  memcpy(pvd->tmp_path + path_len, ".tmp", sizeof ".tmp");
  /* An empty collection right away: the path is checked now and a run that stops before its
   * first frame still leaves a valid file. */
  if (pvd_rewrite(pvd) != 0) {
    peri_pvd_close(pvd);
    return NULL;
  }
  return pvd;
}

int peri_pvd_add(peri_pvd *pvd, double time, const char *file) {
  if (pvd->n_frames == pvd->capacity) {
    pvd->capacity = pvd->capacity ? 2 * pvd->capacity : 16;
    pvd->frames = peri_realloc(pvd->frames, pvd->capacity * sizeof *pvd->frames);
  }
  /* Kept even if the rewrite fails, so the next successful rewrite lists it. */
  pvd->frames[pvd->n_frames].time = time;
  pvd->frames[pvd->n_frames].file = peri_strdup(file);
  pvd->n_frames++;
  return pvd_rewrite(pvd);
}

void peri_pvd_close(peri_pvd *pvd) {
  if (!pvd) return;
  for (size_t i = 0; i < pvd->n_frames; i++) free(pvd->frames[i].file);
  free(pvd->frames);
  free(pvd->tmp_path);
  free(pvd->path);
  free(pvd);
}
