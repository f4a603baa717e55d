/* Error messages and checked allocation. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"

static void vreport(const char *kind, const char *fmt, va_list ap) {
  fprintf(stderr, "peri: %s: ", kind);
  vfprintf(stderr, fmt, ap);
  fputc('\n', stderr);
}

void peri_error(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vreport("error", fmt, ap);
  va_end(ap);
}

void peri_warning(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vreport("warning", fmt, ap);
  va_end(ap);
}

void peri_error_at(const char *file, int line, int col, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  fprintf(stderr, "%s:%d:%d: error: ", file, line, col);
  vfprintf(stderr, fmt, ap);
  fputc('\n', stderr);
  va_end(ap);
}

static void *checked(void *p, size_t bytes) {
  if (!p && bytes) {
    peri_error("out of memory allocating %zu bytes", bytes);
    exit(PERI_ERR_RUN);
  }
  return p;
}

void *peri_malloc(size_t bytes) { return checked(malloc(bytes ? bytes : 1), bytes); }
void *peri_calloc(size_t count, size_t size) {
  return checked(calloc(count ? count : 1, size ? size : 1), count * size);
}
void *peri_realloc(void *ptr, size_t bytes) { return checked(realloc(ptr, bytes ? bytes : 1), bytes); }
char *peri_strdup(const char *s) {
  size_t n = strlen(s) + 1;
  return memcpy(peri_malloc(n), s, n);
}
