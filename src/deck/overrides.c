/* "--set key.path=value" overrides of the deck tree (include/peri/overrides.h). New nodes
 * are made by the deck parser itself (a small YAML document per override), so they are
 * ordinary deck nodes; their positions are rewritten to point into the option. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/overrides.h"

enum { MAX_DEPTH = 32 };

typedef struct {
  int ordinal;            /* K of "--set:K:C" */
  int key_col[MAX_DEPTH]; /* 1-based column of each path component in the argument */
  int value_col;          /* column of the value */
  int gen_value_line, gen_value_col; /* where the value starts in the generated document */
} positions;

/* Rewrites the positions of a grafted subtree: keys and mappings of path level `level`
 * take that component's column; the value subtree maps its generated columns. */
static void place_value(peri_node *node, const positions *ps) {
  if (!node) return;
  node->col = node->line == ps->gen_value_line ? ps->value_col + (node->col - ps->gen_value_col) : ps->value_col;
  node->line = ps->ordinal;
  for (int i = 0; i < node->count; ++i) {
    place_value(node->items[i], ps);
    if (node->keys) place_value(node->keys[i], ps);
  }
}

static void place_chain(peri_node *key, peri_node *value, int level, int last, const positions *ps) {
  key->line = ps->ordinal;
  key->col = ps->key_col[level];
  if (level == last) {
    place_value(value, ps);
    return;
  }
  value->line = ps->ordinal;
  value->col = ps->key_col[level];
  place_chain(value->keys[0], value->items[0], level + 1, last, ps);
}

static int fail(int ordinal, int col, const char *fmt, const char *a, const char *b) {
  peri_error_at("--set", ordinal, col, fmt, a, b);
  return PERI_ERR_INPUT;
}

/* Suggests the nearest existing key of a name-keyed mapping (materials, regions). */
static int unknown_name(const peri_node *map, const char *what, const char *name, int ordinal, int col) {
  int best = -1, best_d = 1 << 30;
  for (int i = 0; i < map->count; ++i) {
    int d = peri_edit_distance(name, map->keys[i]->scalar);
    if (d < best_d) best_d = d, best = i;
  }
  char msg[512];
  if (best >= 0 && best_d <= 2)
    snprintf(msg, sizeof msg, "unknown %s '%s'; did you mean '%s'?", what, name, map->keys[best]->scalar);
  else
    snprintf(msg, sizeof msg, "unknown %s '%s' (an override cannot add one)", what, name);
  peri_error_at("--set", ordinal, col, "%s", msg);
  return PERI_ERR_INPUT;
}

static int apply_one(peri_node *root, const char *arg, int ordinal, peri_node **keep) {
  const char *eq = strchr(arg, '=');
  if (!eq || eq == arg)
    return fail(ordinal, 1, "expected KEY.PATH=VALUE (e.g. discretization.horizon=1e-3), got '%s'%s", arg, "");
  char path[1024];
  size_t plen = (size_t)(eq - arg);
  if (plen >= sizeof path) return fail(ordinal, 1, "key path too long: '%.40s...'%s", arg, "");
  memcpy(path, arg, plen);
  path[plen] = '\0';
  const char *value = eq + 1;
  positions ps = {.ordinal = ordinal, .value_col = (int)(value - arg) + 1};
  char *comp[MAX_DEPTH];
  int n = 0;
  for (char *p = path, *start = path;; ++p) {
    if (*p == '.' || *p == '\0') {
      bool end = *p == '\0';
      *p = '\0';
      if (!*start) return fail(ordinal, (int)(start - path) + 1, "empty component in key path '%s'%s", arg, "");
      if (n == MAX_DEPTH) return fail(ordinal, 1, "key path nested too deeply: '%s'%s", arg, "");
      ps.key_col[n] = (int)(start - path) + 1;
      comp[n++] = start;
      if (end) break;
      start = p + 1;
    }
  }
  /* walk the existing tree */
  peri_node *cur = root;
  const char *cur_name = "the deck";
  int level = 0;
  for (; level < n; ++level) {
    if (cur->kind == PERI_NODE_SEQUENCE) {
      char *endp = NULL;
      long idx = strtol(comp[level], &endp, 10);
      if (*endp || idx < 0 || idx >= cur->count) {
        char range[64];
        snprintf(range, sizeof range, "0 to %d", cur->count - 1);
        peri_error_at("--set", ordinal, ps.key_col[level], "'%s': %s is a list; expected an index from %s",
                      comp[level], cur_name, cur->count ? range : "(it is empty)");
        return PERI_ERR_INPUT;
      }
      if (level == n - 1) break;
      cur_name = comp[level];
      cur = cur->items[idx];
      continue;
    }
    if (cur->kind != PERI_NODE_MAPPING) {
      peri_error_at("--set", ordinal, ps.key_col[level], "'%s' is a value, not a section; cannot set '%s' in it",
                    cur_name, comp[level]);
      return PERI_ERR_INPUT;
    }
    peri_node *child = peri_deck_get(cur, comp[level]);
    if (!child) {
      if (level == 1 && (!strcmp(comp[0], "materials") || !strcmp(comp[0], "regions")))
        return unknown_name(cur, !strcmp(comp[0], "materials") ? "material" : "region", comp[level], ordinal,
                            ps.key_col[level]);
      break;
    }
    if (level == n - 1) break;
    cur_name = comp[level];
    cur = child;
  }
  /* the new part as a YAML document: comp[level]:\n  comp[level+1]: ... VALUE */
  size_t size = strlen(arg) * 2 + 64 + (size_t)n * (MAX_DEPTH + 4);
  char *text = peri_malloc(size);
  size_t used = 0;
  int first = level < n ? level : n - 1;
  bool in_list = cur->kind == PERI_NODE_SEQUENCE;
  if (in_list) first = n - 1;
  for (int k = first; k < n; ++k) {
    int indent = 2 * (k - first);
    if (k < n - 1)
      used += (size_t)snprintf(text + used, size - used, "%*s%s:\n", indent, "", in_list ? "v" : comp[k]);
    else {
      used += (size_t)snprintf(text + used, size - used, "%*s%s: ", indent, "", in_list ? "v" : comp[k]);
      ps.gen_value_line = k - first + 1;
      ps.gen_value_col = (int)(indent + strlen(in_list ? "v" : comp[k]) + 2) + 1;
      used += (size_t)snprintf(text + used, size - used, "%s\n", value);
    }
  }
  peri_node *doc = peri_deck_parse_string(text, "--set");
  free(text);
  if (!doc) { /* the parser said why, with positions in the generated text */
    peri_error("in --set number %d: '%s' (the value must be YAML, e.g. 1e-3, [0, 1], {x: 0})", ordinal, arg);
    return PERI_ERR_INPUT;
  }
  *keep = doc;
  peri_node *new_key = doc->keys[0], *new_value = doc->items[0];
  place_chain(new_key, new_value, first, n - 1, &ps);
  if (in_list) {
    long idx = strtol(comp[n - 1], NULL, 10);
    doc->items[0] = cur->items[idx]; /* the replaced node is freed with the document */
    cur->items[idx] = new_value;
    return PERI_OK;
  }
  if (level < n && !peri_deck_get(cur, comp[level])) {
    /* a new key: move the pair into the mapping */
    cur->items = peri_realloc(cur->items, sizeof(peri_node *) * (size_t)(cur->count + 1));
    cur->keys = peri_realloc(cur->keys, sizeof(peri_node *) * (size_t)(cur->count + 1));
    cur->keys[cur->count] = new_key;
    cur->items[cur->count] = new_value;
    cur->count++;
    doc->count = 0; /* the document no longer owns them */
    return PERI_OK;
  }
  /* replace the value of an existing key */
  for (int i = 0; i < cur->count; ++i)
    if (!strcmp(cur->keys[i]->scalar, comp[n - 1])) {
      doc->items[0] = cur->items[i];
      cur->items[i] = new_value;
      break;
    }
  return PERI_OK;
}

int peri_deck_apply_overrides(peri_node *root, int n, const char *const *sets, peri_node ***keep) {
  *keep = n > 0 ? peri_calloc((size_t)n, sizeof(peri_node *)) : NULL;
  for (int k = 0; k < n; ++k)
    if (apply_one(root, sets[k], k + 1, &(*keep)[k]) != PERI_OK) return PERI_ERR_INPUT;
  return PERI_OK;
}

void peri_overrides_free(peri_node **keep, int n) {
  if (!keep) return;
  for (int k = 0; k < n; ++k) peri_deck_free(keep[k]);
  free(keep);
}
