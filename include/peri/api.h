/* The C API of libperi: build a simulation from a deck (a file or a string), run it or step
 * it, and read its node fields and history back, with every error returned as a status and a
 * message instead of printed. The Python module (python/peri, docs/python.md) is built on it
 * through ctypes; a C program links it with `pkg-config --cflags --libs peri`.
 *
 * Statuses are the program's exit statuses: PERI_API_OK (0), PERI_API_ERR_RUN (1, a failure
 * during the run: divergence, a file that cannot be written) and PERI_API_ERR_INPUT (2, bad
 * input: the deck, an override, a field name, a call out of order). After a status other than
 * PERI_API_OK, peri_api_last_error() holds the messages the library gave, one per line, in
 * the form the program prints them ("deck.yaml:12:5: error: unknown key 'densty' ..." or
 * "peri: error: ..."). Warnings still go to stderr.
 *
 * A run behaves as `peri run DECK --quiet` does: it writes its frames, history.csv and
 * pictures into output.directory (or the directory given to peri_api_set_output). Steps are
 * explicit time steps, or load steps for the quasi-static solvers; stepping n steps and then
 * m steps gives the state of n + m steps bit for bit.
 *
 * One thread at a time may call the API (the messages of a call are collected process-wide);
 * several simulations may be open at once. Under MPI (mpirun -np N) every rank calls the same
 * functions in the same order, and a field holds the nodes this rank owns. */
#ifndef PERI_API_H
#define PERI_API_H
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

enum { PERI_API_OK = 0, PERI_API_ERR_RUN = 1, PERI_API_ERR_INPUT = 2 };

typedef struct peri_api peri_api;

/* The library's version, e.g. "0.1.0". */
const char *peri_api_version(void);
/* The messages of the last call that failed (one per line, no final newline); "" when it
 * succeeded. Valid until the next call. */
const char *peri_api_last_error(void);

/* Builds the simulation of the deck file `path` with `n_sets` overrides "key.path=value"
 * (the program's --set) applied first; *out receives the handle (NULL on failure). Every
 * input error comes here, before any work: PERI_API_ERR_INPUT with file:line:column. */
int peri_api_open_deck(const char *path, int n_sets, const char *const *sets, peri_api **out);
/* The same from the YAML text of a deck; messages name it `name` (e.g. "deck.yaml"), and
 * relative paths in it (a node file) are taken from name's folder. */
int peri_api_open_string(const char *yaml, const char *name, int n_sets, const char *const *sets,
                         peri_api **out);

/* Settings, before the run starts (PERI_API_ERR_INPUT once it has): the output directory
 * (the program's --output), the summary and the progress line (quiet, the default, prints
 * neither), and a checkpoint to continue from (--restart, docs/restart.md). */
int peri_api_set_output(peri_api *a, const char *directory);
int peri_api_set_quiet(peri_api *a, int quiet);
int peri_api_set_restart(peri_api *a, const char *checkpoint);
/* OpenMP threads of the calling thread's later runs (the program's --threads); 0 or less
 * leaves them as they are (OMP_NUM_THREADS, or all cores). */
void peri_api_set_threads(int threads);

/* Starts the run: the checkpoint, the summary (unless quiet), the output directory, the first
 * frame and history row. Stepping, running and reading a field or the history start it when
 * it has not started. */
int peri_api_start(peri_api *a);
/* Runs n more steps (load steps for a quasi-static solver), or to the end of the run if fewer
 * are left. At the end the run finishes as the program's does (picture, plot; the end of the
 * summary unless quiet). Not for heat-only decks (solver type heat): run them with
 * peri_api_run. */
int peri_api_step(peri_api *a, long n);
/* Runs to the end and finishes. */
int peri_api_run(peri_api *a);

/* The state: step (or load step) done, steps of the whole run, time, dimension, nodes (this
 * rank's owned nodes), whether the solver is quasi-static, whether the run has finished
 * (reached its end, or stopped at an error). */
long peri_api_step_index(const peri_api *a);
long peri_api_steps(const peri_api *a);
double peri_api_time(const peri_api *a);
int peri_api_dimension(const peri_api *a);
long peri_api_nodes(const peri_api *a);
int peri_api_is_quasi_static(const peri_api *a);
int peri_api_finished(const peri_api *a);

/* The names peri_api_field accepts, k = 0, 1, ...; NULL after the last: "position" (x + u),
 * "reference_position" (x), then the frame fields of output.fields (docs/deck.md). */
const char *peri_api_field_name(int k);
/* The field `name` at the current state: ncomp values per node (1, 3 or 9; vectors have 3
 * components in every dimension), doubles in *data or int32 in *idata (material, block), the
 * other set to NULL. The arrays belong to the simulation and hold this state until it steps,
 * runs or closes (reading a field again recomputes the same values in place). PERI_API_ERR_INPUT for an unknown name or a field this simulation has not
 * (dilatation without LPS, temperature without heat). */
int peri_api_field(peri_api *a, const char *name, const double **data, const int32_t **idata, int *ncomp);

/* The rows of history.csv recorded so far, row after row (n_rows x n_columns doubles, valid
 * until the next call with `a`), and the name of column k. Not for heat-only decks. */
int peri_api_history(peri_api *a, const double **rows, long *n_rows, int *n_columns);
const char *peri_api_history_column(peri_api *a, int k);

/* Finishes a run stopped midway (picture, plot, as the program does when a run stops) and
 * frees everything. Returns PERI_API_OK, or the error of that finishing (a picture that
 * cannot be written); an error that an earlier call returned is not returned again. NULL is
 * a no-op. */
int peri_api_close(peri_api *a);

#ifdef __cplusplus
}
#endif
#endif
