/* Error messages and checked allocation. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"

/* Messages quote deck text, file names and values a user typed; a control character
 * among them (ESC, BEL, CR) written raw would act on the terminal instead of being
 * seen, so each is written as an escape such as \x1b or \r. UTF-8 is kept. */
static void write_escaped(FILE *stream, const char *text) {
  for (const unsigned char *c = (const unsigned char *)text; *c; c++) {
    switch (*c) {
    case '\n': fputs("\\n", stream); break;
    case '\r': fputs("\\r", stream); break;
    case '\t': fputs("\\t", stream); break;
    default:
      if (*c < 0x20 || *c == 0x7f)
        fprintf(stream, "\\x%02x", *c);
      else
        fputc(*c, stream);
    }
  }
}

char *peri_vformat(const char *fmt, va_list ap) {
  va_list copy;
  va_copy(copy, ap);
  int length = vsnprintf(NULL, 0, fmt, copy);
  va_end(copy);
  if (length < 0) length = 0;
  char *text = peri_malloc((size_t)length + 1);
  vsnprintf(text, (size_t)length + 1, fmt, ap);
  return text;
}

/* Where messages go: stderr, or a sink a program installed (peri_set_message_sink). */
static peri_message_sink message_sink;
static void *message_sink_ctx;

void peri_set_message_sink(peri_message_sink sink, void *ctx) {
  message_sink = sink;
  message_sink_ctx = ctx;
}

void peri_message_forward(const char *kind, const char *line) {
  if (message_sink) {
    message_sink(kind, line, message_sink_ctx);
    return;
  }
  const size_t n = strlen(line);
  char *whole = peri_malloc(n + 2); /* (one write, as emit's) */
  memcpy(whole, line, n);
  whole[n] = '\n', whole[n + 1] = '\0';
  fputs(whole, stderr);
  free(whole);
}

/* One message line: "peri: KIND: text", or "file:line:col: KIND: text" when file is given,
 * escaped, to the sink (without the newline) or to stderr. */
static void emit(const char *kind, const char *file, int line, int col, const char *fmt, va_list ap) {
  /* composed in memory and written to stderr in one call: stderr is unbuffered, and a line
   * written a character at a time reaches a terminal or mpirun's output forwarding in
   * pieces that other ranks' or mpirun's own lines can split */
  char *captured = NULL;
  size_t size = 0;
  FILE *memory = open_memstream(&captured, &size);
  FILE *stream = memory ? memory : stderr;
  if (file) {
    write_escaped(stream, file);
    fprintf(stream, ":%d:%d: %s: ", line, col, kind);
  } else {
    fprintf(stream, "peri: %s: ", kind);
  }
  char *text = peri_vformat(fmt, ap);
  write_escaped(stream, text);
  free(text);
  if (!memory) {
    fputc('\n', stderr);
    return;
  }
  if (!message_sink) fputc('\n', memory);
  fclose(memory);
  if (message_sink) message_sink(kind, captured, message_sink_ctx);
  else fwrite(captured, 1, size, stderr);
  free(captured);
}

void peri_error(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  emit("error", NULL, 0, 0, fmt, ap);
  va_end(ap);
}

void peri_warning(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  emit("warning", NULL, 0, 0, fmt, ap);
  va_end(ap);
}

void peri_error_at(const char *file, int line, int col, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  emit("error", file, line, col, fmt, ap);
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
void *peri_malloc_aligned(size_t bytes) {
  /* (aligned_alloc takes a multiple of the alignment) */
  const size_t whole = ((bytes ? bytes : 1) + PERI_CACHE_LINE - 1) / PERI_CACHE_LINE * PERI_CACHE_LINE;
  return checked(aligned_alloc(PERI_CACHE_LINE, whole), whole);
}
void *peri_calloc_aligned(size_t count, size_t size) {
  void *p = peri_malloc_aligned(count * size);
  memset(p, 0, count * size);
  return p;
}
void *peri_realloc(void *ptr, size_t bytes) { return checked(realloc(ptr, bytes ? bytes : 1), bytes); }
char *peri_strdup(const char *s) {
  size_t n = strlen(s) + 1;
  return memcpy(peri_malloc(n), s, n);
}
