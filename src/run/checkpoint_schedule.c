/* When and where checkpoints are written during a run (docs/restart.md). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/checkpoint.h"
#include "peri/comm.h"
#include "peri/error.h"
#include "peri/output.h"

void peri_checkpoint_path(const peri_sim *s, char *out, size_t size) {
  const peri_output *o = &s->out;
  if (!o->checkpoint_file) {
    snprintf(out, size, "%s/%s.h5", o->directory, o->basename);
    return;
  }
  /* "{step}" becomes the step number, so that every checkpoint is kept */
  char name[4096];
  const char *mark = strstr(o->checkpoint_file, "{step}");
  if (mark)
    snprintf(name, sizeof name, "%.*s%06ld%s", (int)(mark - o->checkpoint_file), o->checkpoint_file, s->state.step,
             mark + strlen("{step}"));
  else
    snprintf(name, sizeof name, "%s", o->checkpoint_file);
  if (name[0] == '/') snprintf(out, size, "%s", name);
  else snprintf(out, size, "%s/%s", o->directory, name);
}

bool peri_checkpoint_due(const peri_sim *s, long step) {
  const long every = s->out.checkpoint_every;
  return every >= 1 && (step % every == 0 || step == s->solver.steps);
}

int peri_checkpoint_after_step(const peri_sim *s, const peri_checkpoint_progress *done) {
  if (!peri_checkpoint_due(s, s->state.step)) return PERI_OK;
  /* inside a dynamic phase the load step is not finished: its checkpoint comes at its end */
  if (s->solver.qs.phase == PERI_QS_PHASE_DYNAMIC) return PERI_OK;
  char path[8192];
  peri_checkpoint_path(s, path, sizeof path);
  char *slash = strrchr(path, '/');
  if (slash && slash != path) { /* checkpoint_file may name a sub-directory; rank 0 writes the file */
    *slash = '\0';
    int rc = peri_comm_rank() == 0 ? peri_mkdir_p(path) : PERI_OK;
    *slash = '/';
    if (s->par.dd) rc = peri_comm_max_int(rc); /* every rank goes on to the (collective) write, or none */
    if (rc != PERI_OK) return rc;
  }
  return peri_checkpoint_write(s, path, done);
}

void peri_checkpoint_print_summary(const peri_sim *s, FILE *out) {
  if (s->out.checkpoint_every < 1) return;
  char path[8192];
  if (s->out.checkpoint_file && strstr(s->out.checkpoint_file, "{step}")) {
    const char *name = s->out.checkpoint_file;
    snprintf(path, sizeof path, "%s%s%s", name[0] == '/' ? "" : s->out.directory, name[0] == '/' ? "" : "/", name);
  } else {
    peri_checkpoint_path(s, path, sizeof path);
  }
  fprintf(out, "  checkpoints  every %ld step%s and at the end: %s\n", s->out.checkpoint_every,
          s->out.checkpoint_every == 1 ? "" : "s", path);
}
