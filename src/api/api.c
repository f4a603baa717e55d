/* The C API (include/peri/api.h): a simulation built from a deck and its run in parts, with
 * the library's messages collected for the caller instead of printed. It adds no behaviour of
 * its own: building is src/deck/setup.c, the run is src/run/ (peri_run_prepare, then
 * peri_run_open / advance / finish, as `peri run` does), the fields are those of a frame
 * (src/post/frames.c). */
#include <limits.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/api.h"
#include "peri/comm.h"
#include "peri/error.h"
#include "peri/frames.h"
#include "peri/history.h"
#include "peri/output.h"
#include "peri/run.h"
#include "peri/setup.h"
#include "peri/sim.h"

struct peri_api {
  peri_sim sim;
  char *restart;             /* checkpoint to continue from, or NULL */
  bool started, finished;
  int status;                /* the run's status so far */
  peri_run_session *run;     /* mechanical runs, once started */
  peri_frames *buffers;      /* the derived fields read by peri_api_field */
  double *positions;         /* [3n] x + u, for "position" */
  char **columns;            /* history.csv's column names */
  int n_columns;
};

/* ---- messages ----------------------------------------------------------------------- */

/* The errors of the call in progress, one per line. Warnings go to stderr as always. */
static char *messages;
static size_t messages_length;

static void collect(const char *kind, const char *line, void *ctx) {
  (void)ctx;
  if (strcmp(kind, "error") != 0) {
    fprintf(stderr, "%s\n", line);
    return;
  }
  const size_t add = strlen(line) + (messages_length ? 1 : 0);
  messages = peri_realloc(messages, messages_length + add + 1);
  if (messages_length) messages[messages_length++] = '\n';
  memcpy(messages + messages_length, line, strlen(line) + 1);
  messages_length += strlen(line);
}

/* Every entry point: forget the last call's messages and take the library's. */
static void enter(void) {
  static bool comm_ready = false;
  if (!comm_ready) { /* MPI when launched by mpirun, else one process (docs/parallel.md) */
    peri_comm_init(NULL, NULL);
    atexit(peri_comm_finalize); /* after PETSc's own (registered later, so run first) */
    comm_ready = true;
  }
  messages_length = 0;
  if (messages) messages[0] = '\0';
  peri_set_message_sink(collect, NULL);
}

/* Gives the messages back to stderr and returns the status, with a message of its own when
 * a failing status came without one. */
static int leave(int status) {
  peri_set_message_sink(NULL, NULL);
  if (status != PERI_OK && messages_length == 0) {
    static const char fallback[] = "peri: error: the call failed without a message";
    messages = peri_realloc(messages, sizeof fallback);
    memcpy(messages, fallback, sizeof fallback);
    messages_length = sizeof fallback - 1;
  }
  return status;
}

/* A message of the API itself (a call out of order, an unknown field). */
#define API_ERROR(status, ...) (peri_error(__VA_ARGS__), (status))

const char *peri_api_version(void) { return PERI_VERSION; }
const char *peri_api_last_error(void) { return messages ? messages : ""; }

/* ---- building ----------------------------------------------------------------------- */

static int opened(peri_api *a, int rc, peri_api **out) {
  if (rc != PERI_OK) {
    peri_sim_free(&a->sim);
    free(a);
    a = NULL;
  } else {
    a->sim.out.quiet = true; /* a library prints nothing unless asked */
  }
  *out = a;
  return leave(rc);
}

int peri_api_open_deck(const char *path, int n_sets, const char *const *sets, peri_api **out) {
  enter();
  *out = NULL;
  if (!path) return leave(API_ERROR(PERI_ERR_INPUT, "open: no deck path given"));
  peri_api *a = peri_calloc(1, sizeof *a);
  return opened(a, peri_sim_from_deck_with(&a->sim, path, n_sets, sets), out);
}

int peri_api_open_string(const char *yaml, const char *name, int n_sets, const char *const *sets, peri_api **out) {
  enter();
  *out = NULL;
  if (!yaml) return leave(API_ERROR(PERI_ERR_INPUT, "open: no deck text given"));
  peri_api *a = peri_calloc(1, sizeof *a);
  return opened(a, peri_sim_from_string_with(&a->sim, yaml, name && *name ? name : "deck", n_sets, sets), out);
}

/* ---- settings ----------------------------------------------------------------------- */

static int before_start(const peri_api *a, const char *what) {
  if (!a) return API_ERROR(PERI_ERR_INPUT, "%s: no simulation (NULL handle)", what);
  if (a->started) return API_ERROR(PERI_ERR_INPUT, "%s: the run has started; set it before the first step", what);
  return PERI_OK;
}

int peri_api_set_output(peri_api *a, const char *directory) {
  enter();
  int rc = before_start(a, "set_output");
  if (rc == PERI_OK && (!directory || !*directory))
    rc = API_ERROR(PERI_ERR_INPUT, "set_output: expected a directory, got an empty path");
  if (rc == PERI_OK) {
    free(a->sim.out.directory);
    a->sim.out.directory = peri_strdup(directory);
  }
  return leave(rc);
}

int peri_api_set_quiet(peri_api *a, int quiet) {
  enter();
  int rc = before_start(a, "set_quiet");
  if (rc == PERI_OK) a->sim.out.quiet = quiet != 0;
  return leave(rc);
}

int peri_api_set_restart(peri_api *a, const char *checkpoint) {
  enter();
  int rc = before_start(a, "set_restart");
  if (rc == PERI_OK) {
    free(a->restart);
    a->restart = checkpoint && *checkpoint ? peri_strdup(checkpoint) : NULL;
  }
  return leave(rc);
}

void peri_api_set_threads(int threads) {
  if (threads > 0) omp_set_num_threads(threads);
}

/* ---- running ------------------------------------------------------------------------ */

static bool heat_only(const peri_api *a) { return a->sim.solver.kind == PERI_SOLVER_HEAT; }

/* Starts the run once; the status of the start (or of the run so far). */
static int start(peri_api *a) {
  if (a->started) return a->status;
  a->started = true;
  a->status = peri_run_prepare(&a->sim, a->restart);
  if (a->status == PERI_OK && !heat_only(a)) {
    a->run = peri_run_open(&a->sim, true);
    a->status = a->run ? peri_run_status(a->run) : PERI_ERR_RUN;
  }
  if (a->status != PERI_OK) a->finished = true;
  return a->status;
}

/* After an error the run has stopped: say so on every later call. */
static int stopped(const peri_api *a, const char *what) {
  return API_ERROR(a->status, "%s: the run stopped at step %ld after an error", what, a->sim.state.step);
}

int peri_api_start(peri_api *a) {
  enter();
  if (!a) return leave(API_ERROR(PERI_ERR_INPUT, "start: no simulation (NULL handle)"));
  return leave(start(a));
}

/* Runs to step `until` (at most the last); finishes the run at its end or at an error. */
static int advance(peri_api *a, long until) {
  if (a->finished) return a->status;
  if (a->sim.state.step < a->sim.solver.steps) a->status = peri_run_advance(a->run, until);
  if (a->status != PERI_OK || a->sim.state.step >= a->sim.solver.steps) {
    const int finished = peri_run_finish(a->run);
    if (a->status == PERI_OK) a->status = finished;
    a->finished = true;
  }
  return a->status;
}

int peri_api_step(peri_api *a, long n) {
  enter();
  if (!a) return leave(API_ERROR(PERI_ERR_INPUT, "step: no simulation (NULL handle)"));
  if (n < 0) return leave(API_ERROR(PERI_ERR_INPUT, "step: expected a number of steps >= 0, got %ld", n));
  if (heat_only(a))
    return leave(API_ERROR(PERI_ERR_INPUT, "step: a heat-only deck (solver type heat) runs whole: use run"));
  const bool had_failed = a->started && a->status != PERI_OK;
  int rc = start(a);
  if (rc != PERI_OK) return leave(had_failed ? stopped(a, "step") : rc);
  const long step = a->sim.state.step;
  return leave(advance(a, n > LONG_MAX - step ? LONG_MAX : step + n));
}

int peri_api_run(peri_api *a) {
  enter();
  if (!a) return leave(API_ERROR(PERI_ERR_INPUT, "run: no simulation (NULL handle)"));
  const bool had_failed = a->started && a->status != PERI_OK;
  int rc = start(a);
  if (rc != PERI_OK) return leave(had_failed ? stopped(a, "run") : rc);
  if (heat_only(a)) {
    if (!a->finished) { /* conduction runs whole (src/run/heat_run.c) */
      a->status = peri_run(&a->sim);
      a->finished = true;
    }
    return leave(a->status);
  }
  return leave(advance(a, LONG_MAX));
}

/* ---- state -------------------------------------------------------------------------- */

long peri_api_step_index(const peri_api *a) { return a ? a->sim.state.step : 0; }
long peri_api_steps(const peri_api *a) { return a ? a->sim.solver.steps : 0; }
double peri_api_time(const peri_api *a) { return a ? a->sim.state.time : 0.0; }
int peri_api_dimension(const peri_api *a) { return a ? a->sim.disc.geom.dim : 0; }
long peri_api_nodes(const peri_api *a) { return a ? a->sim.disc.p.n_owned : 0; }
int peri_api_is_quasi_static(const peri_api *a) { return a && peri_is_quasi_static(&a->sim); }
int peri_api_finished(const peri_api *a) { return a && a->finished; }

/* ---- fields ------------------------------------------------------------------------- */

static const char *const own_fields[] = {"position", "reference_position"};
enum { N_OWN_FIELDS = sizeof own_fields / sizeof own_fields[0] };

const char *peri_api_field_name(int k) {
  if (k < 0) return NULL;
  if (k < N_OWN_FIELDS) return own_fields[k];
  for (int j = 0; peri_frame_fields[j]; ++j)
    if (j == k - N_OWN_FIELDS) return peri_frame_fields[j];
  return NULL;
}

int peri_api_field(peri_api *a, const char *name, const double **data, const int32_t **idata, int *ncomp) {
  enter();
  *data = NULL, *idata = NULL, *ncomp = 0;
  if (!a) return leave(API_ERROR(PERI_ERR_INPUT, "field: no simulation (NULL handle)"));
  if (!name) return leave(API_ERROR(PERI_ERR_INPUT, "field: no name given"));
  int known = -1;
  for (int k = 0; peri_api_field_name(k); ++k)
    if (!strcmp(name, peri_api_field_name(k))) known = k;
  if (known < 0) {
    char list[1024] = "";
    for (int k = 0; peri_api_field_name(k); ++k)
      snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", k ? ", " : "", peri_api_field_name(k));
    return leave(API_ERROR(PERI_ERR_INPUT, "field: unknown field '%s' (fields: %s)", name, list));
  }
  /* the state the fields describe is the run's: its initial conditions once started */
  if (!a->started && start(a) != PERI_OK) return leave(a->status);
  const peri_particles *p = &a->sim.disc.p;
  if (!strcmp(name, "reference_position")) {
    *data = p->x, *ncomp = 3;
    return leave(PERI_OK);
  }
  if (!strcmp(name, "position")) {
    a->positions = peri_realloc(a->positions, sizeof(double) * 3 * (size_t)(p->n > 0 ? p->n : 1));
    for (size_t c = 0; c < 3 * (size_t)p->n_owned; ++c) a->positions[c] = p->x[c] + p->u[c];
    *data = a->positions, *ncomp = 3;
    return leave(PERI_OK);
  }
  if (!a->buffers) a->buffers = peri_frames_buffers(&a->sim);
  peri_field fl;
  const int got = peri_frames_field(a->buffers, &a->sim, name, &fl);
  if (got < 0) return leave(PERI_ERR_RUN);
  if (got == 0)
    return leave(API_ERROR(PERI_ERR_INPUT, "field: this simulation has no field '%s' (%s)", name,
                           !strcmp(name, "dilatation") ? "the model has no dilatation" : "no heat conduction"));
  *data = fl.data, *idata = fl.idata, *ncomp = fl.ncomp;
  return leave(PERI_OK);
}

/* ---- history ------------------------------------------------------------------------ */

int peri_api_history(peri_api *a, const double **rows, long *n_rows, int *n_columns) {
  enter();
  *rows = NULL, *n_rows = 0, *n_columns = 0;
  if (!a) return leave(API_ERROR(PERI_ERR_INPUT, "history: no simulation (NULL handle)"));
  if (heat_only(a))
    return leave(API_ERROR(PERI_ERR_INPUT, "history: a heat-only deck (solver type heat) keeps its history in "
                                           "history.csv only"));
  if (!a->started && start(a) != PERI_OK) return leave(a->status);
  if (!a->run) return leave(API_ERROR(PERI_ERR_RUN, "history: the run could not open its output"));
  *rows = peri_run_history(a->run, n_rows, n_columns);
  return leave(PERI_OK);
}

const char *peri_api_history_column(peri_api *a, int k) {
  if (!a) return NULL;
  if (!a->columns) a->columns = peri_history_columns(&a->sim, &a->n_columns);
  return k >= 0 && k < a->n_columns ? a->columns[k] : NULL;
}

/* ---- the end ------------------------------------------------------------------------ */

int peri_api_close(peri_api *a) {
  if (!a) return PERI_OK;
  enter();
  int rc = PERI_OK;
  if (a->run) {
    /* finishes a run stopped midway; a finished run's status was returned already */
    const bool was_finished = a->finished;
    const int closed = peri_run_close(a->run);
    if (!was_finished) rc = closed;
  }
  peri_frames_close(a->buffers);
  if (a->columns) peri_history_columns_free(a->columns, a->n_columns);
  free(a->positions);
  free(a->restart);
  peri_sim_free(&a->sim);
  free(a);
  return leave(rc);
}
