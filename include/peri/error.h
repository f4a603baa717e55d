/* Error reporting and exit statuses shared by the library and the program. */
#ifndef PERI_ERROR_H
#define PERI_ERROR_H
#include <stdarg.h>
#include <stddef.h>

/* Status codes returned by library functions; they are also the program's exit codes. */
enum peri_status {
  PERI_OK = 0,
  PERI_ERR_RUN = 1,   /* a failure during the run (I/O, divergence, ...) */
  PERI_ERR_INPUT = 2, /* bad input: deck, mesh file, image; detected before work starts */
};

/* Prints "peri: error: <message>" on stderr. */
void peri_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Prints "peri: warning: <message>" on stderr. */
void peri_warning(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Prints "<file>:<line>:<col>: error: <message>" on stderr (line/col 1-based). */
void peri_error_at(const char *file, int line, int col, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* Messages go to stderr unless a program that embeds the library takes them (the C API,
 * include/peri/api.h): the sink receives the kind ("error" or "warning") and the whole line
 * as it would be printed, without the newline. NULL restores stderr. One sink per process. */
typedef void (*peri_message_sink)(const char *kind, const char *line, void *ctx);
void peri_set_message_sink(peri_message_sink sink, void *ctx);
/* A whole line as a sink receives it (kind and line), reported here: to this process's sink,
 * or printed on stderr (how a child process's messages are passed on). */
void peri_message_forward(const char *kind, const char *line);

/* The text of a printf-style format and its arguments, allocated (free it). */
char *peri_vformat(const char *fmt, va_list ap);

/* Allocation that aborts the run with a message instead of returning NULL. */
void *peri_malloc(size_t bytes);
void *peri_calloc(size_t count, size_t size);
void *peri_realloc(void *ptr, size_t bytes);
/* The same at a cache-line (64-byte) boundary, for per-bond arrays whose rows of layers the
 * vector loops load and store whole: rows of 32 bytes from malloc's 16-byte boundary would
 * straddle two lines every other bond. Released with free(). */
#define PERI_CACHE_LINE 64
void *peri_malloc_aligned(size_t bytes);
void *peri_calloc_aligned(size_t count, size_t size);
char *peri_strdup(const char *s);

#endif
