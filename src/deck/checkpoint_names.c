/* output.checkpoint_file must not name a file the run writes or reads (docs/restart.md):
 * writing a checkpoint would replace it. Names are compared as absolute paths, with "." and
 * ".." resolved and the symbolic links of the existing directories followed; "{step}" and
 * the frame numbers stand for any run of digits. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <ctype.h>
#include <limits.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "peri/deck.h"
#include "peri/error.h"
#include "peri/setup.h"
#include "setup_parts.h"

enum { NAME_MAX_LEN = 8192 };

/* `path` (relative to `base`, unless absolute) as an absolute path without ".", ".." or
 * repeated slashes; the longest existing directory at its start has its links resolved. */
static void resolve(const char *base, const char *path, char *out) {
  char joined[NAME_MAX_LEN];
  char cwd[PATH_MAX] = "/";
  if (!getcwd(cwd, sizeof cwd)) strcpy(cwd, "/");
  if (path[0] == '/') snprintf(joined, sizeof joined, "%s", path);
  else if (base[0] == '/') snprintf(joined, sizeof joined, "%s/%s", base, path);
  else snprintf(joined, sizeof joined, "%s/%s/%s", cwd, base, path);
  /* lexical clean-up */
  char clean[NAME_MAX_LEN] = "";
  size_t len = 0;
  for (char *part = strtok(joined, "/"); part; part = strtok(NULL, "/")) {
    if (!strcmp(part, ".")) continue;
    if (!strcmp(part, "..")) {
      char *slash = strrchr(clean, '/');
      len = slash ? (size_t)(slash - clean) : 0;
      clean[len] = '\0';
      continue;
    }
    len += (size_t)snprintf(clean + len, sizeof clean - len, "/%s", part);
    if (len >= sizeof clean) len = sizeof clean - 1;
  }
  if (!clean[0]) strcpy(clean, "/");
  /* links: the longest existing directory prefix through realpath */
  char head[NAME_MAX_LEN];
  snprintf(head, sizeof head, "%s", clean);
  for (char *slash = strrchr(head, '/'); slash; slash = strrchr(head, '/')) {
    *slash = '\0';
    char real[PATH_MAX];
    if (realpath(head[0] ? head : "/", real)) {
      const char *rest = clean + (slash - head);
      snprintf(out, NAME_MAX_LEN, "%s%s", strcmp(real, "/") ? real : "", rest);
      return;
    }
  }
  snprintf(out, NAME_MAX_LEN, "%s", clean);
}

/* Whether `name` matches `pattern`, in which '#' stands for one or more digits. */
static bool matches(const char *pattern, const char *name) {
  if (!*pattern) return !*name;
  if (*pattern == '#') {
    if (!isdigit((unsigned char)*name)) return false;
    while (isdigit((unsigned char)*name)) {
      ++name;
      if (matches(pattern + 1, name)) return true;
    }
    return false;
  }
  return *pattern == *name && matches(pattern + 1, name + 1);
}

/* `pattern` with each '#' replaced by a step number. */
static void instance(const char *pattern, char *out) {
  size_t k = 0;
  for (const char *c = pattern; *c && k + 8 < NAME_MAX_LEN; ++c) {
    if (*c == '#') k += (size_t)snprintf(out + k, NAME_MAX_LEN - k, "000001");
    else out[k++] = *c;
  }
  out[k] = '\0';
}

/* Whether two patterns can name the same file. */
static bool collide(const char *a, const char *b) {
  char ia[NAME_MAX_LEN], ib[NAME_MAX_LEN];
  instance(a, ia);
  instance(b, ib);
  return matches(a, ib) || matches(b, ia);
}

int peri_checkpoint_check_names(const peri_sim *s, const peri_node *root) {
  const peri_output *o = &s->out;
  if (o->checkpoint_every < 1) return PERI_OK;
  const peri_node *output = peri_deck_get(root, "output");
  const peri_node *key = output ? peri_deck_key_node(output, "checkpoint_file") : NULL;
  /* the checkpoint: "{step}" is six or more digits ('#'), "#" in the name itself a digit */
  char name[NAME_MAX_LEN];
  if (o->checkpoint_file) {
    const char *mark = strstr(o->checkpoint_file, "{step}");
    if (mark) snprintf(name, sizeof name, "%.*s#%s", (int)(mark - o->checkpoint_file), o->checkpoint_file,
                       mark + strlen("{step}"));
    else snprintf(name, sizeof name, "%s", o->checkpoint_file);
  } else {
    snprintf(name, sizeof name, "%s.h5", o->basename);
  }
  char checkpoint[NAME_MAX_LEN];
  resolve(o->directory, name, checkpoint);

  /* what the run writes (relative to the output directory) and reads */
  struct { char pattern[NAME_MAX_LEN]; const char *what; } files[16];
  int n = 0;
  const char *dir = o->directory;
#define ADD(WHAT, ...)                                                                                                 \
  do {                                                                                                                 \
    char rel[NAME_MAX_LEN];                                                                                            \
    snprintf(rel, sizeof rel, __VA_ARGS__);                                                                            \
    resolve(dir, rel, files[n].pattern);                                                                               \
    files[n++].what = WHAT;                                                                                            \
  } while (0)
  ADD("the run's history.csv", "history.csv");
  ADD("the run's .pvd", "%s.pvd", o->basename);
  ADD("the run's history_units.csv", "history_units.csv");
  if (o->exodus) ADD("the run's Exodus file", "%s.e", o->basename);
  ADD("a frame of the run", "%s_#.vtu", o->basename);
  ADD("a frame of the run", "%s_#.pvtu", o->basename);
  ADD("a frame piece of the run", "%s_#_#.vtu", o->basename);
  if (o->picture && o->picture_field) ADD("the run's picture", "%s.png", o->picture_field);
  if (o->plot_x && o->plot_y) ADD("the run's plot", "%s_vs_%s.png", o->plot_y, o->plot_x);
  dir = ".";
  ADD("the deck", "%s", s->deck_path);
  const peri_node *disc = peri_deck_get(root, "discretization");
  const peri_node *node_file = disc ? peri_deck_get(disc, "node_file") : NULL;
  if (node_file && node_file->scalar) { /* relative to the deck's directory */
    const char *slash = strrchr(s->deck_path, '/');
    if (node_file->scalar[0] != '/' && slash)
      ADD("the deck's node file", "%.*s/%s", (int)(slash - s->deck_path), s->deck_path, node_file->scalar);
    else
      ADD("the deck's node file", "%s", node_file->scalar);
  }
  const peri_node *mesh = disc ? peri_deck_get(disc, "mesh") : NULL;
  if (mesh && mesh->scalar) { /* relative to the deck's directory */
    const char *slash = strrchr(s->deck_path, '/');
    if (mesh->scalar[0] != '/' && slash)
      ADD("the deck's mesh file", "%.*s/%s", (int)(slash - s->deck_path), s->deck_path, mesh->scalar);
    else
      ADD("the deck's mesh file", "%s", mesh->scalar);
  }
  const peri_node *fill = disc ? peri_deck_get(disc, "fill") : NULL;
  for (int k = 0; fill && fill->kind == PERI_NODE_SEQUENCE && k < fill->count && n < 16; ++k) {
    const peri_node *file = peri_setup_is_image_fill(fill->items[k]) ? peri_deck_get(fill->items[k], "file") : NULL;
    if (!file || !file->scalar) continue;
    const char *slash = strrchr(s->deck_path, '/'); /* an image: relative to the deck's directory */
    if (file->scalar[0] != '/' && slash)
      ADD("the deck's image", "%.*s/%s", (int)(slash - s->deck_path), s->deck_path, file->scalar);
    else
      ADD("the deck's image", "%s", file->scalar);
  }
#undef ADD
  for (int k = 0; k < n; ++k) {
    bool same = collide(checkpoint, files[k].pattern);
    if (!same && !strchr(checkpoint, '#') && !strchr(files[k].pattern, '#')) {
      /* the same file under another name (a symbolic link to it) */
      char real_a[PATH_MAX], real_b[PATH_MAX];
      same = realpath(checkpoint, real_a) && realpath(files[k].pattern, real_b) && !strcmp(real_a, real_b);
    }
    if (same)
      return peri_deck_error(key ? key : output, "key 'checkpoint_file': '%s' would overwrite %s (%s); give the "
                             "checkpoints a name of their own, e.g. 'checkpoint_{step}.h5'",
                             o->checkpoint_file ? o->checkpoint_file : name, files[k].what, files[k].pattern);
  }
  return PERI_OK;
}
