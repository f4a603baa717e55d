/* A library's reading of a file run in a child process first (guarded_read.h). Gmsh 4.8
 * dereferences what a damaged .msh file leaves out and crashes; netCDF 4.9 (under Exodus II)
 * allocates and fills tens of GB at sizes read from a damaged header. In the child, a crash is
 * the child's, and the memory bound turns the allocation into a failed read; the parent reports
 * either as bad input (exit status 2) before any work. The child's messages come back through a
 * pipe, so the refusal of a reader that checks the file itself reads the same as unguarded. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L /* strsignal */
#endif
#include "guarded_read.h"
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include "peri/error.h"

/* the child's memory: this much more than the process maps, plus this many times the file */
#define CHILD_MEMORY_BASE ((rlim_t)4 << 30)
#define CHILD_MEMORY_PER_FILE_BYTE 64
/* the child's processor time: this many seconds plus one a MB of the file (the examples' meshes
 * read in a fraction of a second, and Gmsh reads a .msh at tens of MB/s): a reading beyond it
 * is taken for a loop on a damaged file */
#define CHILD_SECONDS_BASE 120
#define CHILD_BYTES_A_SECOND ((off_t)1 << 20)

/* The child's message sink: each line as "KIND<tab>LINE<newline>" into the pipe (a line has no
 * newline of its own: error.c writes control characters escaped). */
static void to_pipe(const char *kind, const char *line, void *ctx) {
  const int fd = *(const int *)ctx;
  const char *parts[4] = {kind, "\t", line, "\n"};
  for (int p = 0; p < 4; ++p)
    for (size_t done = 0, n = strlen(parts[p]); done < n;) {
      const ssize_t w = write(fd, parts[p] + done, n - done);
      if (w <= 0) return;
      done += (size_t)w;
    }
}

/* The address space the process maps now (its first field of /proc/self/statm), 0 if unknown. */
static rlim_t mapped_bytes(void) {
  FILE *f = fopen("/proc/self/statm", "r");
  unsigned long pages = 0;
  if (f) {
    if (fscanf(f, "%lu", &pages) != 1) pages = 0;
    fclose(f);
  }
  const long page = sysconf(_SC_PAGESIZE);
  return (rlim_t)pages * (rlim_t)(page > 0 ? page : 4096);
}

/* The file's size in bytes, 0 if unknown (the child's bounds grow with it). */
static off_t file_bytes(const char *path) {
  struct stat st;
  return stat(path, &st) == 0 && st.st_size > 0 ? st.st_size : 0;
}

/* The memory the child may take beyond what the process maps. */
static rlim_t child_budget(const char *path) {
  return CHILD_MEMORY_BASE + CHILD_MEMORY_PER_FILE_BYTE * (rlim_t)file_bytes(path);
}

/* The processor time the child may take reading PATH, in seconds. */
static unsigned child_seconds(const char *path) {
  return CHILD_SECONDS_BASE + (unsigned)(file_bytes(path) / CHILD_BYTES_A_SECOND);
}

/* The child's bounds: its processor time (0: none) and its memory beyond what the process maps
 * (0: none). */
typedef struct child_bounds {
  unsigned seconds;
  rlim_t memory;
} child_bounds;

static _Noreturn void run_child(int (*job)(void *), void *context, int fd, child_bounds bounds) {
  const struct rlimit no_core = {0, 0}; /* a crash is expected of a damaged file: no core file */
  setrlimit(RLIMIT_CORE, &no_core);
  /* beyond `seconds` of processor time SIGXCPU ends the child, and a child that catches it is
   * killed a little later (the hard limit) */
  struct rlimit cpu;
  const unsigned seconds = bounds.seconds;
  if (seconds > 0 && getrlimit(RLIMIT_CPU, &cpu) == 0 && (cpu.rlim_cur == RLIM_INFINITY || cpu.rlim_cur > seconds)) {
    cpu.rlim_cur = seconds;
    if (cpu.rlim_max == RLIM_INFINITY || cpu.rlim_max > seconds + 5) cpu.rlim_max = seconds + 5;
    setrlimit(RLIMIT_CPU, &cpu);
  }
  struct rlimit memory;
  if (bounds.memory > 0) {
    const rlim_t bound = mapped_bytes() + bounds.memory;
    if (getrlimit(RLIMIT_AS, &memory) == 0 && (memory.rlim_cur == RLIM_INFINITY || memory.rlim_cur > bound)) {
      memory.rlim_cur = bound;
      setrlimit(RLIMIT_AS, &memory);
    }
  }
  /* the libraries' own output (the messages come through the sink) */
  const int null = open("/dev/null", O_WRONLY);
  if (null >= 0) dup2(null, STDOUT_FILENO), dup2(null, STDERR_FILENO);
  peri_set_message_sink(to_pipe, &fd);
  const int rc = job(context);
  _exit(rc == PERI_OK ? 0 : PERI_ERR_INPUT); /* (no exit handlers: they are the parent's) */
}

/* The child's messages reported here, line by line, under their kinds; whether there was one. */
static int forward(char *text) {
  int lines = 0;
  char *rest = NULL;
  for (char *line = strtok_r(text, "\n", &rest); line; line = strtok_r(NULL, "\n", &rest)) {
    char *tab = strchr(line, '\t');
    if (!tab) continue;
    *tab = '\0';
    peri_message_forward(line, tab + 1);
    ++lines;
  }
  return lines;
}

/* Runs job(context) in a child within `bounds`; PERI_OK when it succeeded there, else the
 * child's messages or what ended it reported here (`doing`: "reading", "meshing") and
 * PERI_ERR_INPUT. 1 when no child could be started (the caller runs the job here). */
static int run_guarded(const char *path, const char *library, const char *doing, int (*job)(void *context),
                       void *context, child_bounds bounds) {
  int fds[2];
  if (pipe(fds) != 0) return 1;
  fflush(stdout), fflush(stderr); /* (nothing buffered here is written twice) */
  const pid_t child = fork();
  if (child == 0) {
    close(fds[0]);
    run_child(job, context, fds[1], bounds);
  }
  close(fds[1]);
  if (child < 0) {
    close(fds[0]);
    return 1;
  }
  /* the messages first (a child that fills the pipe waits for it to be read) */
  size_t size = 0, cap = 4096;
  char *text = peri_malloc(cap);
  for (;;) {
    if (size + 1 >= cap) text = peri_realloc(text, cap *= 2);
    const ssize_t r = read(fds[0], text + size, cap - size - 1);
    if (r > 0) size += (size_t)r;
    else if (r == 0 || errno != EINTR) break;
  }
  text[size] = '\0';
  close(fds[0]);
  int status = 0;
  while (waitpid(child, &status, 0) < 0)
    if (errno != EINTR) break;
  int rc = PERI_ERR_INPUT;
  if (WIFSIGNALED(status) && WTERMSIG(status) == SIGXCPU) {
    peri_error("%s: the %s library did not finish %s it within %u s of processor time: the file is damaged, "
               "or not one %s reads",
               path, library, doing, bounds.seconds, library);
  } else if (WIFSIGNALED(status)) {
    peri_error("%s: the %s library crashed %s it (%s): the file is damaged, or not one %s reads", path, library,
               doing, strsignal(WTERMSIG(status)), library);
  } else if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    rc = PERI_OK;
  } else {
    const int said = forward(text);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != PERI_ERR_INPUT || said == 0) {
      if (bounds.memory > 0)
        peri_error("%s: the %s library stopped %s it (exit status %d) within %.0f GiB of memory: the file is "
                   "damaged, or not one %s reads",
                   path, library, doing, WIFEXITED(status) ? WEXITSTATUS(status) : -1,
                   (double)bounds.memory / (double)((rlim_t)1 << 30), library);
      else
        peri_error("%s: the %s library stopped %s it (exit status %d): the file is damaged, or not one %s reads",
                   path, library, doing, WIFEXITED(status) ? WEXITSTATUS(status) : -1, library);
    }
  }
  free(text);
  return rc;
}

int peri_guarded_read(const char *path, const char *library, int (*reader)(void *context), void *context) {
  return peri_guarded_read_within(path, library, reader, context, child_seconds(path));
}

int peri_guarded_read_within(const char *path, const char *library, int (*reader)(void *context), void *context,
                             unsigned seconds) {
  const child_bounds bounds = {seconds, child_budget(path)};
  const int rc = run_guarded(path, library, "reading", reader, context, bounds);
  return rc == PERI_OK || rc == 1 ? reader(context) : rc; /* (read here too: the child's reading is gone) */
}

int peri_guarded_run(const char *path, const char *library, const char *doing, int (*job)(void *context),
                     void *context) {
  const child_bounds none = {0, 0};
  const int rc = run_guarded(path, library, doing, job, context, none);
  return rc == 1 ? job(context) : rc;
}
