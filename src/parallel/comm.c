/* The message-passing layer (include/peri/comm.h): MPI when PERI_HAVE_MPI is defined, else
 * a single process. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "peri/comm.h"
#include "peri/error.h"
#ifdef PERI_HAVE_MPI
#include <mpi.h>
#endif

#ifdef PERI_HAVE_MPI
struct peri_comm_request {
  MPI_Request request;
};

static int comm_rank = 0, comm_size = 1;
static bool started_here = false;
static pid_t started_pid; /* the process that started MPI (its exit handler finalizes it) */
static bool check_collectives = false; /* PERI_CHECK_COLLECTIVES (docs/parallel.md) */
static long checked_calls = 0;

enum { SITE_TEXT = 160 };

/* FNV-1a of the operation and its call site: the tag the ranks compare. */
static unsigned long tag_of(const char *call, const char *site) {
  unsigned long h = 1469598103934665603UL;
  for (const char *t = call; *t; ++t) h = (h ^ (unsigned char)*t) * 1099511628211UL;
  h = (h ^ '@') * 1099511628211UL;
  for (const char *t = site; *t; ++t) h = (h ^ (unsigned char)*t) * 1099511628211UL;
  return h;
}

/* The site from the source tree on: src/..., app/... or tests/... (__FILE__ may be an
 * absolute path). */
static const char *short_site(const char *site) {
  static const char *const tops[] = {"src/", "app/", "tests/"};
  const char *best = site;
  for (const char *t = site; *t; ++t)
    for (int k = 0; k < 3; ++k)
      if (!strncmp(t, tops[k], strlen(tops[k])) && (t == site || t[-1] == '/')) best = t;
  return best;
}

/* Before a collective call in the check mode: every rank sends its tag (operation and call
 * site) to every other. A run whose ranks took different branches would otherwise hang
 * (ranks waiting in different collectives) or combine unrelated values (the same kind of
 * collective from different places). On a mismatch rank 0, whose messages are the ones
 * shown, names where each rank is and stops the run; the other ranks wait for that. */
static void agree(const char *call, const char *site) {
  if (!check_collectives || comm_size == 1) return;
  ++checked_calls;
  unsigned long mine = tag_of(call, site);
  unsigned long *all = peri_malloc(sizeof(unsigned long) * (size_t)comm_size);
  MPI_Allgather(&mine, 1, MPI_UNSIGNED_LONG, all, 1, MPI_UNSIGNED_LONG, MPI_COMM_WORLD);
  bool same = true;
  for (int r = 1; r < comm_size; ++r) same = same && all[r] == all[0];
  free(all);
  if (same) return;
  char text[SITE_TEXT];
  snprintf(text, sizeof text, "%s at %s", call, short_site(site));
  char *texts = comm_rank == 0 ? peri_malloc((size_t)SITE_TEXT * (size_t)comm_size) : NULL;
  MPI_Gather(text, SITE_TEXT, MPI_CHAR, texts, SITE_TEXT, MPI_CHAR, 0, MPI_COMM_WORLD);
  if (comm_rank == 0) {
    peri_error("MPI ranks disagree on the sequence of collective calls (PERI_CHECK_COLLECTIVES) at checked "
               "call %ld; a decision before it was taken from data that differ between ranks:", checked_calls);
    /* the ranks' calls in one write, as peri_error writes its line (error.c) */
    char *lines = NULL;
    size_t size = 0;
    FILE *memory = open_memstream(&lines, &size);
    for (int r = 0; r < comm_size; ++r) fprintf(memory ? memory : stderr, "  rank %d: %s\n", r, texts + (size_t)SITE_TEXT * r);
    if (memory) {
      fclose(memory);
      fwrite(lines, 1, size, stderr);
      free(lines);
    }
    peri_comm_abort(PERI_ERR_RUN);
  }
  MPI_Barrier(MPI_COMM_WORLD); /* rank 0 never enters it: its abort ends this rank */
  peri_comm_abort(PERI_ERR_RUN);
}

void peri_comm_check_at(const char *call, const char *site) {
  if (comm_size > 1) agree(call, site);
}

/* Started by an MPI launcher (mpirun, mpiexec, srun)? A plain `peri run` then skips MPI_Init,
 * which would otherwise start a singleton MPI job (about a second). */
static bool launched_by_mpi(void) {
  static const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS", NULL};
  for (int k = 0; vars[k]; ++k)
    if (getenv(vars[k])) return true;
  return false;
}

void peri_comm_init(int *argc, char ***argv) {
  int ready = 0;
  MPI_Initialized(&ready);
  if (!ready && !launched_by_mpi()) return; /* one process */
  if (!ready) {
    MPI_Init(argc, argv);
    started_here = true;
    started_pid = getpid();
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &comm_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &comm_size);
  const char *check = getenv("PERI_CHECK_COLLECTIVES");
  check_collectives = check && check[0] && strcmp(check, "0") != 0;
  if (comm_rank > 0) { /* one copy of every message: rank 0 prints */
    if (!freopen("/dev/null", "w", stdout)) { /* keep the stream as it is */ }
    if (!freopen("/dev/null", "w", stderr)) { /* keep the stream as it is */ }
  }
}

void peri_comm_finalize(void) {
  int done = 0;
  MPI_Finalized(&done);
  /* (not in a process forked from this one, whose exit handlers are these: src/io/guarded_read.c) */
  if (started_here && !done && getpid() == started_pid) {
    agree("the end of the run (MPI_Finalize)", PERI_COMM_SITE); /* a rank that left early */
    MPI_Finalize();
  }
}

void peri_comm_abort(int status) {
  fflush(stdout);
  fflush(stderr);
  if (comm_size == 1) exit(status);
  MPI_Abort(MPI_COMM_WORLD, status);
}

int peri_comm_rank(void) { return comm_rank; }
int peri_comm_size(void) { return comm_size; }
void peri_comm_barrier_at(const char *site) {
  agree("peri_comm_barrier", site);
  if (comm_size > 1) MPI_Barrier(MPI_COMM_WORLD);
}

long peri_comm_sum_long_at(long value, const char *site) {
  long out = value;
  agree("peri_comm_sum_long", site);
  if (comm_size > 1) MPI_Allreduce(&value, &out, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  return out;
}

int peri_comm_max_int_at(int value, const char *site) {
  int out = value;
  agree("peri_comm_max_int", site);
  if (comm_size > 1) MPI_Allreduce(&value, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return out;
}

double peri_comm_min_at(double value, const char *site) {
  double out = value;
  agree("peri_comm_min", site);
  if (comm_size > 1) MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  return out;
}

double peri_comm_max_at(double value, const char *site) {
  double out = value;
  agree("peri_comm_max", site);
  if (comm_size > 1) MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return out;
}

bool peri_comm_all_at(bool value, const char *site) {
  int v = value ? 1 : 0, out = v;
  agree("peri_comm_all", site);
  if (comm_size > 1) MPI_Allreduce(&v, &out, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return out != 0;
}

void peri_comm_gather_doubles_at(const double *local, int64_t count, const int64_t *counts, double *out,
                                 const char *site) {
  agree("peri_comm_gather_doubles", site);
  if (comm_size == 1) {
    if (count > 0) memcpy(out, local, sizeof(double) * (size_t)count);
    return;
  }
  int *rc = NULL, *displ = NULL;
  if (comm_rank == 0) {
    rc = peri_malloc(sizeof(int) * (size_t)comm_size);
    displ = peri_malloc(sizeof(int) * (size_t)comm_size);
    int64_t at = 0;
    for (int r = 0; r < comm_size; ++r) {
      rc[r] = (int)counts[r];
      displ[r] = (int)at;
      at += counts[r];
    }
  }
  MPI_Gatherv(local, (int)count, MPI_DOUBLE, out, rc, displ, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  free(rc);
  free(displ);
}

/* Point-to-point messages of at most 2^30 bytes, received by rank 0 in rank order: the
 * counts and offsets of MPI_Gatherv are ints, and the bond arrays of a large problem hold
 * more than 2^31 bytes. */
void peri_comm_gather_bytes_at(const uint8_t *local, int64_t count, const int64_t *counts, uint8_t *out,
                               const char *site) {
  enum { CHUNK = 1 << 30, TAG = 18 }; /* a tag of its own, apart from the halo's */
  agree("peri_comm_gather_bytes", site);
  if (comm_rank > 0) {
    for (int64_t at = 0; at < count; at += CHUNK) {
      const int64_t part = count - at < CHUNK ? count - at : CHUNK;
      MPI_Send(local + at, (int)part, MPI_UNSIGNED_CHAR, 0, TAG, MPI_COMM_WORLD);
    }
    return;
  }
  if (count > 0) memcpy(out, local, (size_t)count);
  int64_t offset = counts[0];
  for (int r = 1; r < comm_size; ++r) {
    for (int64_t at = 0; at < counts[r]; at += CHUNK) {
      const int64_t part = counts[r] - at < CHUNK ? counts[r] - at : CHUNK;
      MPI_Recv(out + offset + at, (int)part, MPI_UNSIGNED_CHAR, r, TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    }
    offset += counts[r];
  }
}

void peri_comm_allgather_doubles_at(const double *local, int64_t count, const int64_t *counts, double *out,
                                    const char *site) {
  agree("peri_comm_allgather_doubles", site);
  if (comm_size == 1) {
    if (count > 0) memcpy(out, local, sizeof(double) * (size_t)count);
    return;
  }
  int *rc = peri_malloc(sizeof(int) * (size_t)comm_size), *displ = peri_malloc(sizeof(int) * (size_t)comm_size);
  int64_t at = 0;
  for (int r = 0; r < comm_size; ++r) {
    rc[r] = (int)counts[r];
    displ[r] = (int)at;
    at += counts[r];
  }
  MPI_Allgatherv(local, (int)count, MPI_DOUBLE, out, rc, displ, MPI_DOUBLE, MPI_COMM_WORLD);
  free(rc);
  free(displ);
}

void peri_comm_broadcast_doubles_at(double *values, int count, const char *site) {
  agree("peri_comm_broadcast_doubles", site);
  if (comm_size > 1) MPI_Bcast(values, count, MPI_DOUBLE, 0, MPI_COMM_WORLD);
}

peri_comm_request *peri_comm_requests(int n) { return peri_calloc((size_t)(n > 0 ? n : 1), sizeof(peri_comm_request)); }

void peri_comm_isend(const double *data, int64_t count, int to, peri_comm_request *r, int k) {
  MPI_Isend(data, (int)count, MPI_DOUBLE, to, 17, MPI_COMM_WORLD, &r[k].request);
}

void peri_comm_irecv(double *data, int64_t count, int from, peri_comm_request *r, int k) {
  MPI_Irecv(data, (int)count, MPI_DOUBLE, from, 17, MPI_COMM_WORLD, &r[k].request);
}

void peri_comm_waitall(peri_comm_request *r, int n) {
  for (int k = 0; k < n; ++k) MPI_Wait(&r[k].request, MPI_STATUS_IGNORE);
}

#else /* one process */

struct peri_comm_request {
  int unused;
};

void peri_comm_init(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
}
void peri_comm_finalize(void) {}
void peri_comm_abort(int status) { exit(status); }
int peri_comm_rank(void) { return 0; }
int peri_comm_size(void) { return 1; }
void peri_comm_check_at(const char *call, const char *site) { (void)call, (void)site; }
void peri_comm_barrier_at(const char *site) { (void)site; }
long peri_comm_sum_long_at(long value, const char *site) { return (void)site, value; }
int peri_comm_max_int_at(int value, const char *site) { return (void)site, value; }
double peri_comm_min_at(double value, const char *site) { return (void)site, value; }
double peri_comm_max_at(double value, const char *site) { return (void)site, value; }
bool peri_comm_all_at(bool value, const char *site) { return (void)site, value; }
void peri_comm_gather_doubles_at(const double *local, int64_t count, const int64_t *counts, double *out,
                                 const char *site) {
  (void)counts, (void)site;
  if (count > 0) memcpy(out, local, sizeof(double) * (size_t)count);
}
void peri_comm_gather_bytes_at(const uint8_t *local, int64_t count, const int64_t *counts, uint8_t *out,
                               const char *site) {
  (void)counts, (void)site;
  if (count > 0) memcpy(out, local, (size_t)count);
}
void peri_comm_allgather_doubles_at(const double *local, int64_t count, const int64_t *counts, double *out,
                                    const char *site) {
  (void)counts, (void)site;
  if (count > 0) memcpy(out, local, sizeof(double) * (size_t)count);
}
void peri_comm_broadcast_doubles_at(double *values, int count, const char *site) {
  (void)values, (void)count, (void)site;
}
peri_comm_request *peri_comm_requests(int n) { return peri_calloc((size_t)(n > 0 ? n : 1), sizeof(peri_comm_request)); }
/* A single process has no neighbours: the halo is empty and these are never called. */
void peri_comm_isend(const double *data, int64_t count, int to, peri_comm_request *r, int k) {
  (void)data, (void)count, (void)to, (void)r, (void)k;
}
void peri_comm_irecv(double *data, int64_t count, int from, peri_comm_request *r, int k) {
  (void)data, (void)count, (void)from, (void)r, (void)k;
}
void peri_comm_waitall(peri_comm_request *r, int n) {
  (void)r;
  (void)n;
}
#endif
