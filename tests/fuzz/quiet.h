/* Silences the library's messages (every rejected input prints one, and printing would
 * take most of the fuzzer's time) while libFuzzer's own lines and the sanitizer reports
 * still reach the terminal: the library prints through the `stderr` stream, libFuzzer
 * through the stream it saved at start-up and the sanitizers to file descriptor 2, so
 * pointing `stderr` at /dev/null silences the library alone. PERI_FUZZ_VERBOSE=1 keeps
 * the messages (to see why an input is rejected). */
#ifndef PERI_FUZZ_QUIET_H
#define PERI_FUZZ_QUIET_H
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static inline void silence_library(void) {
  if (getenv("PERI_FUZZ_VERBOSE")) return;
  FILE *null = fopen("/dev/null", "w");
  if (null) stderr = null; /* glibc: stderr is an assignable FILE * */
}

/* A path under TMPDIR (else /tmp) from `pattern` ("peri-fuzz-deck-XXXXXX.yaml"), for mkstemps or
 * mkdtemp to fill in. */
static inline void fuzz_temp_path(char *out, size_t size, const char *pattern) {
  const char *dir = getenv("TMPDIR");
  snprintf(out, size, "%s/%s", dir && strlen(dir) < 200 ? dir : "/tmp", pattern);
}

#endif
