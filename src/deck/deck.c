/* The deck: libyaml events turned into a tree of positioned nodes, and the typed
 * accessors that section parsers use to read it. Every error names file:line:col, the
 * key, what was expected and what was found, so a user can fix a deck without reading
 * the source. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>
#include "peri/deck.h"
#include "peri/error.h"

/* Bounds the recursion of the loader: a hostile or broken deck must not overflow the
 * stack. Real decks nest four or five levels. */
enum { MAX_NESTING = 128 };

/* Longest scalar quoted back in a message before it is shortened with "...". */
enum { QUOTE_LIMIT = 60 };

/* Every node is allocated as a deck_node with the public part first, so a peri_node
 * pointer handed out by this file converts back. The extra fields hold what messages
 * need but the public struct does not carry. Only nodes built here may be passed in. */
typedef struct {
  peri_node pub;
  bool is_null;  /* a plain scalar spelled as YAML null: empty, ~, null */
  char *section; /* MAPPING: its path for messages, "" for the root, "materials.glass" */
  int *order;    /* MAPPING: indices of the first `ordered` keys, sorted by text, so that a
                  * lookup in a mapping of 100,000 regions is a binary search */
  int ordered;   /* keys appended later (--set) are searched one by one */
} deck_node;

static const deck_node *hidden(const peri_node *node) { return (const deck_node *)node; }

/* ---- messages ---------------------------------------------------------------------- */

int peri_deck_error(const peri_node *at, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  char *message = peri_vformat(fmt, ap);
  va_end(ap);
  if (at)
    peri_error_at(at->file, at->line, at->col, "%s", message);
  else
    peri_error("%s", message);
  free(message);
  return PERI_ERR_INPUT;
}

static bool equal_ignoring_case(const char *a, const char *b) {
  for (; *a && *b; a++, b++)
    if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return false;
  return *a == *b;
}

typedef enum { NUMBER_OK, NUMBER_NOT_FINITE, NUMBER_INVALID } number_status;

/* The whole scalar must be one number; "1.5 m" or "" are not numbers. */
static number_status parse_number(const char *text, double *out) {
  char *end;
  errno = 0;
  double value = strtod(text, &end);
  if (end == text) return NUMBER_INVALID;
  while (isspace((unsigned char)*end)) end++;
  if (*end) return NUMBER_INVALID;
  if (!isfinite(value)) return NUMBER_NOT_FINITE;
  *out = value;
  return NUMBER_OK;
}

static bool is_value_scalar(const peri_node *node) {
  return node && node->kind == PERI_NODE_SCALAR && !hidden(node)->is_null;
}

const char *peri_deck_kind_name(const peri_node *node) {
  if (!node) return "nothing";
  switch (node->kind) {
  case PERI_NODE_MAPPING: return "a mapping";
  case PERI_NODE_SEQUENCE: return "a list";
  case PERI_NODE_SCALAR: break;
  }
  if (hidden(node)->is_null) return "null";
  double ignored;
  return parse_number(node->scalar, &ignored) == NUMBER_OK ? "a number" : "a string";
}

/* What was found, for "expected X, got Y": a scalar is quoted back (shortened, first
 * line only), anything else is named by its kind. */
static const char *describe(const peri_node *node, char *buffer, size_t size) {
  if (!is_value_scalar(node)) return peri_deck_kind_name(node);
  const char *text = node->scalar;
  size_t length = strcspn(text, "\n");
  bool shortened = length > QUOTE_LIMIT || text[length] != '\0';
  if (length > QUOTE_LIMIT) length = QUOTE_LIMIT;
  snprintf(buffer, size, "'%.*s%s'", (int)length, text, shortened ? "..." : "");
  return buffer;
}

/* Reports "<what>: expected <expectation>, got <found>" at the node. */
static int report_expected(const peri_node *node, const char *what, const char *expectation) {
  char found[QUOTE_LIMIT + 16];
  return peri_deck_error(node, "%s: expected %s, got %s", what, expectation,
                         describe(node, found, sizeof found));
}

/* "a, b, c" from a NULL-terminated list; the caller frees it. */
static char *join_names(const char *const *names) {
  size_t length = 1;
  for (int i = 0; names[i]; i++) length += strlen(names[i]) + 2;
  char *joined = peri_malloc(length);
  joined[0] = '\0';
  for (int i = 0; names[i]; i++) {
    if (i) strcat(joined, ", ");
    strcat(joined, names[i]);
  }
  return joined;
}

int peri_edit_distance(const char *a, const char *b) {
  size_t length_a = strlen(a), length_b = strlen(b);
  int *row = peri_malloc((length_b + 1) * sizeof *row);
  for (size_t j = 0; j <= length_b; j++) row[j] = (int)j;
  for (size_t i = 1; i <= length_a; i++) {
    int diagonal = row[0];
    row[0] = (int)i;
    for (size_t j = 1; j <= length_b; j++) {
      int above = row[j];
      int cost = tolower((unsigned char)a[i - 1]) != tolower((unsigned char)b[j - 1]);
      int best = diagonal + cost;
      if (above + 1 < best) best = above + 1;
      if (row[j - 1] + 1 < best) best = row[j - 1] + 1;
      row[j] = best;
      diagonal = above;
    }
  }
  int distance = row[length_b];
  free(row);
  return distance;
}

/* The candidate closest to `word`, or NULL when none is close enough to be a likely
 * typo: distance at most max(2, len/3), and not a rewrite of every letter (which would
 * make 'x' suggest 'q'). */
static const char *closest_name(const char *word, const char *const *candidates) {
  int limit = (int)(strlen(word) / 3);
  if (limit < 2) limit = 2;
  const char *best = NULL;
  int best_distance = limit + 1;
  for (int i = 0; candidates[i]; i++) {
    int distance = peri_edit_distance(word, candidates[i]);
    size_t longer = strlen(word) > strlen(candidates[i]) ? strlen(word) : strlen(candidates[i]);
    if ((size_t)distance >= longer) continue;
    if (distance < best_distance) {
      best_distance = distance;
      best = candidates[i];
    }
  }
  return best;
}

/* ---- loading ----------------------------------------------------------------------- */

typedef struct {
  yaml_parser_t parser;
  const char *text; /* the whole input, to locate reader errors and look at characters */
  size_t length;
  const char *file; /* shared by every node; owned by the root */
} loader;

static bool is_continuation_byte(char byte) { return ((unsigned char)byte & 0xC0) == 0x80; }

/* The input at a libyaml mark. Marks count characters, not bytes, so walk to the line and
 * then over UTF-8 characters. NULL when the mark lies beyond the text. */
static const char *character_at(const loader *ld, yaml_mark_t mark) {
  const char *p = ld->text, *end = ld->text + ld->length;
  if (ld->length >= 3 && memcmp(p, "\xEF\xBB\xBF", 3) == 0) p += 3; /* a BOM is not counted */
  for (size_t line = 0; line < mark.line; line++) {
    p = memchr(p, '\n', (size_t)(end - p));
    if (!p) return NULL;
    p++;
  }
  for (size_t column = 0; column < mark.column && p < end; column++) {
    p++;
    while (p < end && is_continuation_byte(*p)) p++;
  }
  return p < end ? p : NULL;
}

static void report_yaml_error(loader *ld) {
  const yaml_parser_t *p = &ld->parser;
  const char *problem = p->problem ? p->problem : "cannot parse the deck";
  if (p->error == YAML_MEMORY_ERROR) {
    peri_error_at(ld->file, 1, 1, "out of memory while reading the deck");
    return;
  }
  if (p->error == YAML_READER_ERROR) {
    /* Reader errors (bad encoding) carry a byte offset, not a mark. */
    int line = 1, col = 1;
    size_t start = ld->length >= 3 && memcmp(ld->text, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
    for (size_t i = start; i < p->problem_offset && i < ld->length; i++) {
      if (ld->text[i] == '\n') {
        line++;
        col = 1;
      } else if (!is_continuation_byte(ld->text[i])) {
        col++;
      }
    }
    if (p->problem_value >= 0)
      peri_error_at(ld->file, line, col, "%s (0x%X)", problem, (unsigned)p->problem_value);
    else
      peri_error_at(ld->file, line, col, "%s", problem);
    return;
  }
  yaml_mark_t at = p->problem_mark;
  int line = (int)at.line + 1, col = (int)at.column + 1;
  /* libyaml's wording for a tab in indentation does not say what is wrong. */
  const char *character = character_at(ld, at);
  if (character && *character == '\t') {
    peri_error_at(ld->file, line, col, "tab character; YAML indentation must use spaces");
    return;
  }
  bool context_elsewhere = p->context && (p->context_mark.line != at.line ||
                                          p->context_mark.column != at.column);
  if (context_elsewhere)
    peri_error_at(ld->file, line, col, "%s (%s started at line %d, column %d)", problem,
                  p->context, (int)p->context_mark.line + 1, (int)p->context_mark.column + 1);
  else
    peri_error_at(ld->file, line, col, "%s", problem);
}

static bool next_event(loader *ld, yaml_event_t *event) {
  if (yaml_parser_parse(&ld->parser, event)) return true;
  report_yaml_error(ld);
  return false;
}

static void error_at_mark(loader *ld, yaml_mark_t mark, const char *fmt, const char *arg) {
  char message[256];
  snprintf(message, sizeof message, fmt, arg);
  peri_error_at(ld->file, (int)mark.line + 1, (int)mark.column + 1, "%s", message);
}

static deck_node *new_node(loader *ld, peri_node_kind kind, yaml_mark_t mark) {
  deck_node *node = peri_calloc(1, sizeof *node);
  node->pub.kind = kind;
  node->pub.file = ld->file;
  node->pub.line = (int)mark.line + 1;
  node->pub.col = (int)mark.column + 1;
  return node;
}

/* Frees a subtree; the file name belongs to the root and is freed by peri_deck_free. */
static void free_node(peri_node *node) {
  if (!node) return;
  for (int i = 0; i < node->count; i++) {
    free_node(node->items[i]);
    if (node->keys) free_node(node->keys[i]);
  }
  free(node->items);
  free(node->keys);
  free(node->scalar);
  free(((deck_node *)node)->section);
  free(((deck_node *)node)->order);
  free(node);
}

/* Anchors and aliases would make one node reachable twice and positions ambiguous;
 * decks are short enough to repeat values. */
static const char *anchor_of(const yaml_event_t *event) {
  switch (event->type) {
  case YAML_SCALAR_EVENT: return (const char *)event->data.scalar.anchor;
  case YAML_SEQUENCE_START_EVENT: return (const char *)event->data.sequence_start.anchor;
  case YAML_MAPPING_START_EVENT: return (const char *)event->data.mapping_start.anchor;
  default: return NULL;
  }
}

static peri_node *build_node(loader *ld, yaml_event_t *event, const char *section, int depth);

static peri_node *build_scalar(loader *ld, yaml_event_t *event) {
  deck_node *node = new_node(ld, PERI_NODE_SCALAR, event->start_mark);
  size_t length = event->data.scalar.length;
  node->pub.scalar = peri_malloc(length + 1);
  memcpy(node->pub.scalar, event->data.scalar.value, length);
  node->pub.scalar[length] = '\0';
  const char *text = node->pub.scalar;
  bool plain = event->data.scalar.style == YAML_PLAIN_SCALAR_STYLE &&
               event->data.scalar.plain_implicit;
  node->is_null = plain && (text[0] == '\0' || strcmp(text, "~") == 0 ||
                            strcmp(text, "null") == 0 || strcmp(text, "Null") == 0 ||
                            strcmp(text, "NULL") == 0);
  return &node->pub;
}

static void append(peri_node *parent, int *capacity, peri_node *key, peri_node *value) {
  if (parent->count == *capacity) {
    *capacity = *capacity ? 2 * *capacity : 8;
    parent->items = peri_realloc(parent->items, (size_t)*capacity * sizeof *parent->items);
    if (parent->kind == PERI_NODE_MAPPING)
      parent->keys = peri_realloc(parent->keys, (size_t)*capacity * sizeof *parent->keys);
  }
  if (parent->kind == PERI_NODE_MAPPING) parent->keys[parent->count] = key;
  parent->items[parent->count] = value;
  parent->count++;
}

static char *child_path(const char *section, const char *key, int index) {
  size_t size = strlen(section) + (key ? strlen(key) : 0) + 24;
  char *path = peri_malloc(size);
  if (key)
    snprintf(path, size, "%s%s%s", section, section[0] ? "." : "", key);
  else
    snprintf(path, size, "%s[%d]", section, index);
  return path;
}

static peri_node *build_sequence(loader *ld, yaml_event_t *start, const char *section,
                                 int depth) {
  peri_node *node = &new_node(ld, PERI_NODE_SEQUENCE, start->start_mark)->pub;
  int capacity = 0;
  for (;;) {
    yaml_event_t event;
    if (!next_event(ld, &event)) break;
    if (event.type == YAML_SEQUENCE_END_EVENT) {
      yaml_event_delete(&event);
      return node;
    }
    char *path = child_path(section, NULL, node->count);
    peri_node *item = build_node(ld, &event, path, depth + 1);
    free(path);
    if (!item) break;
    append(node, &capacity, NULL, item);
  }
  free_node(node);
  return NULL;
}

typedef struct {
  const char *text;
  int index;
} key_entry;

static int compare_keys(const void *a, const void *b) {
  const key_entry *x = a, *y = b;
  int by_text = strcmp(x->text, y->text);
  if (by_text) return by_text;
  return (x->index > y->index) - (x->index < y->index);
}

/* Sorts the keys of a finished mapping (O(n log n), where comparing each new key with
 * every earlier one took minutes on 100,000 regions) and reports a duplicate: the one
 * that comes first in the deck, at its second occurrence, as a reader going down the
 * deck would meet it. False after reporting. */
static bool order_keys(deck_node *mapping) {
  const peri_node *node = &mapping->pub;
  int n = node->count;
  key_entry *entries = peri_malloc((size_t)(n ? n : 1) * sizeof *entries);
  for (int i = 0; i < n; i++) entries[i] = (key_entry){node->keys[i]->scalar, i};
  qsort(entries, (size_t)n, sizeof *entries, compare_keys);
  int duplicate = -1, first = -1;
  for (int i = 1; i < n; i++) {
    bool repeats = strcmp(entries[i].text, entries[i - 1].text) == 0;
    bool starts_run = i == 1 || strcmp(entries[i - 1].text, entries[i - 2].text) != 0;
    if (repeats && starts_run && (duplicate < 0 || entries[i].index < duplicate)) {
      duplicate = entries[i].index;
      first = entries[i - 1].index;
    }
  }
  if (duplicate >= 0) {
    const peri_node *key = node->keys[duplicate], *earlier = node->keys[first];
    peri_deck_error(key, "duplicate key '%s' (first given at line %d, column %d)",
                    key->scalar, earlier->line, earlier->col);
    free(entries);
    return false;
  }
  mapping->order = peri_malloc((size_t)(n ? n : 1) * sizeof *mapping->order);
  for (int i = 0; i < n; i++) mapping->order[i] = entries[i].index;
  mapping->ordered = n;
  free(entries);
  return true;
}

static peri_node *build_mapping(loader *ld, yaml_event_t *start, const char *section,
                                int depth) {
  deck_node *mapping = new_node(ld, PERI_NODE_MAPPING, start->start_mark);
  mapping->section = peri_strdup(section);
  peri_node *node = &mapping->pub;
  int capacity = 0;
  for (;;) {
    yaml_event_t event;
    if (!next_event(ld, &event)) break;
    if (event.type == YAML_MAPPING_END_EVENT) {
      yaml_event_delete(&event);
      if (order_keys(mapping)) return node;
      break;
    }
    if (event.type == YAML_SEQUENCE_START_EVENT || event.type == YAML_MAPPING_START_EVENT) {
      error_at_mark(ld, event.start_mark, "%s", "a mapping key must be a name, not a list or "
                    "a mapping");
      yaml_event_delete(&event);
      break;
    }
    peri_node *key = build_node(ld, &event, section, depth + 1);
    if (!key) break;
    yaml_event_t value_event;
    if (!next_event(ld, &value_event)) {
      free_node(key);
      break;
    }
    char *path = child_path(section, key->scalar, 0);
    peri_node *value = build_node(ld, &value_event, path, depth + 1);
    free(path);
    if (!value) {
      free_node(key);
      break;
    }
    append(node, &capacity, key, value);
  }
  free_node(node);
  return NULL;
}

/* Builds the node that starts with `event`, taking ownership of the event. Returns NULL
 * after reporting an error. */
static peri_node *build_node(loader *ld, yaml_event_t *event, const char *section, int depth) {
  peri_node *node = NULL;
  const char *anchor = anchor_of(event);
  if (event->type == YAML_ALIAS_EVENT) {
    error_at_mark(ld, event->start_mark,
                  "aliases are not supported ('*%s'); write the value out in full",
                  (const char *)event->data.alias.anchor);
  } else if (anchor) {
    error_at_mark(ld, event->start_mark,
                  "anchors are not supported ('&%s'); write the value out in full", anchor);
  } else if (depth > MAX_NESTING) {
    error_at_mark(ld, event->start_mark, "%s", "the deck is nested too deeply");
  } else if (event->type == YAML_SCALAR_EVENT) {
    node = build_scalar(ld, event);
  } else if (event->type == YAML_SEQUENCE_START_EVENT) {
    node = build_sequence(ld, event, section, depth);
  } else if (event->type == YAML_MAPPING_START_EVENT) {
    node = build_mapping(ld, event, section, depth);
  } else {
    error_at_mark(ld, event->start_mark, "%s", "unexpected YAML structure");
  }
  yaml_event_delete(event);
  return node;
}

/* Reads the single document of the stream; its root must be a mapping of sections. */
static peri_node *build_document(loader *ld) {
  yaml_event_t event;
  if (!next_event(ld, &event)) return NULL;
  yaml_event_delete(&event); /* stream start */
  if (!next_event(ld, &event)) return NULL;
  if (event.type == YAML_STREAM_END_EVENT) {
    yaml_event_delete(&event);
    peri_error_at(ld->file, 1, 1, "the deck is empty; expected a mapping of sections");
    return NULL;
  }
  yaml_event_delete(&event); /* document start */
  if (!next_event(ld, &event)) return NULL;
  peri_node *root = build_node(ld, &event, "", 0);
  if (!root) return NULL;
  if (root->kind != PERI_NODE_MAPPING) {
    if (hidden(root)->is_null)
      peri_deck_error(root, "the deck is empty; expected a mapping of sections");
    else
      peri_deck_error(root, "the deck must be a mapping of sections, got %s",
                      peri_deck_kind_name(root));
    free_node(root);
    return NULL;
  }
  if (!next_event(ld, &event)) goto fail;
  yaml_event_delete(&event); /* document end */
  if (!next_event(ld, &event)) goto fail;
  if (event.type != YAML_STREAM_END_EVENT) {
    error_at_mark(ld, event.start_mark, "%s",
                  "a second YAML document; a deck holds exactly one");
    yaml_event_delete(&event);
    goto fail;
  }
  yaml_event_delete(&event);
  return root;
fail:
  free_node(root);
  return NULL;
}

static peri_node *parse_text(const char *text, size_t length, const char *name) {
  loader ld = {.text = text, .length = length};
  char *file = peri_strdup(name);
  ld.file = file;
  if (!yaml_parser_initialize(&ld.parser)) {
    peri_error("cannot initialise the YAML parser");
    free(file);
    return NULL;
  }
  yaml_parser_set_input_string(&ld.parser, (const unsigned char *)text, length);
  peri_node *root = build_document(&ld);
  yaml_parser_delete(&ld.parser);
  if (!root) free(file);
  return root;
}

peri_node *peri_deck_parse_string(const char *text, const char *name) {
  return parse_text(text, strlen(text), name);
}

peri_node *peri_deck_load(const char *path) {
  FILE *file = fopen(path, "rb");
  if (!file) {
    peri_error("cannot open deck '%s': %s", path, strerror(errno));
    return NULL;
  }
  size_t length = 0, capacity = 4096;
  char *text = peri_malloc(capacity);
  for (;;) {
    length += fread(text + length, 1, capacity - length, file);
    if (length < capacity) break;
    capacity *= 2;
    text = peri_realloc(text, capacity);
  }
  if (ferror(file)) {
    /* fopen succeeds on a directory; the read is what fails. */
    peri_error("cannot read deck '%s': %s", path, strerror(errno));
    fclose(file);
    free(text);
    return NULL;
  }
  fclose(file);
  peri_node *root = parse_text(text, length, path);
  free(text);
  return root;
}

void peri_deck_free(peri_node *root) {
  if (!root) return;
  char *file = (char *)root->file;
  free_node(root);
  free(file);
}

/* ---- lookup ------------------------------------------------------------------------ */

int peri_deck_key_index(const peri_node *map, const char *key) {
  if (!map || map->kind != PERI_NODE_MAPPING) return -1;
  const deck_node *mapping = hidden(map);
  /* a mapping whose keys were moved out (--set) is searched one by one */
  int ordered = mapping->order && mapping->ordered <= map->count ? mapping->ordered : 0;
  int low = 0, high = ordered;
  while (low < high) {
    int middle = low + (high - low) / 2;
    int index = mapping->order[middle];
    int by_text = strcmp(map->keys[index]->scalar, key);
    if (by_text == 0) return index;
    if (by_text < 0)
      low = middle + 1;
    else
      high = middle;
  }
  for (int i = ordered; i < map->count; i++)
    if (strcmp(map->keys[i]->scalar, key) == 0) return i;
  return -1;
}

peri_node *peri_deck_get(const peri_node *map, const char *key) {
  int index = peri_deck_key_index(map, key);
  return index < 0 ? NULL : map->items[index];
}

const peri_node *peri_deck_key_node(const peri_node *map, const char *key) {
  int index = peri_deck_key_index(map, key);
  return index < 0 ? NULL : map->keys[index];
}

static const char *section_name(const peri_node *map) {
  const char *section = hidden(map)->section;
  return section && section[0] ? section : "the deck";
}

int peri_deck_allow(const peri_node *map, const char *section, const char *const *allowed) {
  if (!map) return PERI_OK; /* an absent optional section has no keys to check */
  if (map->kind != PERI_NODE_MAPPING)
    return peri_deck_error(map, "section '%s': expected a mapping, got %s", section,
                           peri_deck_kind_name(map));
  int status = PERI_OK;
  for (int i = 0; i < map->count; i++) {
    const char *key = map->keys[i]->scalar;
    bool known = false;
    for (int j = 0; allowed[j] && !known; j++) known = strcmp(key, allowed[j]) == 0;
    if (known) continue;
    const char *suggestion = closest_name(key, allowed);
    if (suggestion) {
      peri_deck_error(map->keys[i], "unknown key '%s' in %s; did you mean '%s'?", key,
                      section, suggestion);
    } else {
      char *accepted = join_names(allowed);
      peri_deck_error(map->keys[i], "unknown key '%s' in %s; accepted keys: %s", key, section,
                      accepted[0] ? accepted : "(none)");
      free(accepted);
    }
    status = PERI_ERR_INPUT; /* keep going: report every unknown key at once */
  }
  return status;
}

/* Finds `key` for an accessor. PERI_OK with *value NULL means absent and optional. */
static int find_value(const peri_node *map, const char *key, bool required,
                      const peri_node **value) {
  *value = NULL;
  if (!map) {
    if (!required) return PERI_OK;
    peri_error("missing key '%s'", key);
    return PERI_ERR_INPUT;
  }
  if (map->kind != PERI_NODE_MAPPING) {
    char found[QUOTE_LIMIT + 16];
    return peri_deck_error(map, "expected a mapping with key '%s', got %s", key,
                           describe(map, found, sizeof found));
  }
  *value = peri_deck_get(map, key);
  if (!*value && required)
    return peri_deck_error(map, "missing key '%s' in %s", key, section_name(map));
  return PERI_OK;
}

/* The "key 'k'" that starts every message about a keyed value. */
static void key_label(const char *key, char *label, size_t size) {
  snprintf(label, size, "key '%s'", key);
}

enum { LABEL_SIZE = 160 };

/* ---- typed accessors --------------------------------------------------------------- */

static int missing_node(const char *what) {
  peri_error("%s: missing value", what);
  return PERI_ERR_INPUT;
}

int peri_deck_node_double(const peri_node *node, const char *what, double *out) {
  if (!node) return missing_node(what);
  if (is_value_scalar(node)) {
    double value;
    number_status status = parse_number(node->scalar, &value);
    if (status == NUMBER_OK) {
      *out = value;
      return PERI_OK;
    }
    if (status == NUMBER_NOT_FINITE) return report_expected(node, what, "a finite number");
  }
  return report_expected(node, what, "a number");
}

int peri_deck_double(const peri_node *map, const char *key, bool required, double *out) {
  const peri_node *value;
  int status = find_value(map, key, required, &value);
  if (status != PERI_OK || !value) return status;
  char label[LABEL_SIZE];
  key_label(key, label, sizeof label);
  return peri_deck_node_double(value, label, out);
}

/* Integers in decimal; an integral number such as 1e6 is accepted too, since step
 * counts are naturally written that way. */
static bool parse_integer(const char *text, long *out, bool *out_of_range) {
  *out_of_range = false;
  char *end;
  errno = 0;
  long value = strtol(text, &end, 10);
  if (end != text) {
    while (isspace((unsigned char)*end)) end++;
    if (!*end) {
      if (errno == ERANGE) {
        *out_of_range = true;
        return false;
      }
      *out = value;
      return true;
    }
  }
  double real;
  if (parse_number(text, &real) != NUMBER_OK || real != floor(real)) return false;
  /* Beyond 2^53 a double no longer holds every integer exactly. */
  if (fabs(real) > 9007199254740992.0) {
    *out_of_range = true;
    return false;
  }
  *out = (long)real;
  return true;
}

int peri_deck_int(const peri_node *map, const char *key, bool required, long *out) {
  const peri_node *value;
  int status = find_value(map, key, required, &value);
  if (status != PERI_OK || !value) return status;
  char label[LABEL_SIZE];
  key_label(key, label, sizeof label);
  if (is_value_scalar(value)) {
    bool out_of_range;
    if (parse_integer(value->scalar, out, &out_of_range)) return PERI_OK;
    if (out_of_range) return report_expected(value, label, "an integer in range");
  }
  return report_expected(value, label, "an integer");
}

int peri_deck_bool(const peri_node *map, const char *key, bool required, bool *out) {
  static const char *const true_words[] = {"true", "yes", "on"};
  static const char *const false_words[] = {"false", "no", "off"};
  const peri_node *value;
  int status = find_value(map, key, required, &value);
  if (status != PERI_OK || !value) return status;
  if (is_value_scalar(value)) {
    for (int i = 0; i < 3; i++) {
      if (equal_ignoring_case(value->scalar, true_words[i])) {
        *out = true;
        return PERI_OK;
      }
      if (equal_ignoring_case(value->scalar, false_words[i])) {
        *out = false;
        return PERI_OK;
      }
    }
  }
  char label[LABEL_SIZE];
  key_label(key, label, sizeof label);
  return report_expected(value, label, "true or false");
}

int peri_deck_string(const peri_node *map, const char *key, bool required, const char **out) {
  const peri_node *value;
  int status = find_value(map, key, required, &value);
  if (status != PERI_OK || !value) return status;
  if (is_value_scalar(value)) {
    *out = value->scalar;
    return PERI_OK;
  }
  char label[LABEL_SIZE];
  key_label(key, label, sizeof label);
  return report_expected(value, label, "a string");
}

int peri_deck_choice(const peri_node *map, const char *key, bool required,
                     const char *const *choices, int *out) {
  const peri_node *value;
  int status = find_value(map, key, required, &value);
  if (status != PERI_OK || !value) return status;
  char label[LABEL_SIZE];
  key_label(key, label, sizeof label);
  char *listed = join_names(choices);
  if (!is_value_scalar(value)) {
    size_t size = strlen(listed) + 16;
    char *expectation = peri_malloc(size);
    snprintf(expectation, size, "one of %s", listed);
    status = report_expected(value, label, expectation);
    free(expectation);
    free(listed);
    return status;
  }
  for (int i = 0; choices[i]; i++) {
    if (strcmp(value->scalar, choices[i]) == 0) {
      *out = i;
      free(listed);
      return PERI_OK;
    }
  }
  const char *suggestion = closest_name(value->scalar, choices);
  if (suggestion)
    peri_deck_error(value, "%s: unknown value '%s'; did you mean '%s'? (choices: %s)", label,
                    value->scalar, suggestion, listed);
  else
    peri_deck_error(value, "%s: unknown value '%s' (choices: %s)", label, value->scalar,
                    listed);
  free(listed);
  return PERI_ERR_INPUT;
}

int peri_deck_vector_range(const peri_node *map, const char *key, bool required, int min_n,
                           int max_n, double *out, int *count) {
  const peri_node *value;
  int status = find_value(map, key, required, &value);
  if (status != PERI_OK || !value) return status;
  char label[LABEL_SIZE];
  key_label(key, label, sizeof label);
  char expectation[96];
  if (min_n == max_n)
    snprintf(expectation, sizeof expectation, "a list of %d number%s", min_n,
             min_n == 1 ? "" : "s");
  else
    snprintf(expectation, sizeof expectation, "a list of %d to %d numbers", min_n, max_n);
  if (value->kind != PERI_NODE_SEQUENCE) return report_expected(value, label, expectation);
  if (value->count < min_n || value->count > max_n)
    return peri_deck_error(value, "%s: expected %s, got a list of %d", label, expectation,
                           value->count);
  /* Check every item before writing any, so a failure leaves *out as it was. */
  for (int i = 0; i < value->count; i++) {
    char item_label[LABEL_SIZE + 32];
    snprintf(item_label, sizeof item_label, "%s, item %d", label, i + 1);
    double ignored;
    status = peri_deck_node_double(value->items[i], item_label, &ignored);
    if (status != PERI_OK) return status;
  }
  for (int i = 0; i < value->count; i++) parse_number(value->items[i]->scalar, &out[i]);
  *count = value->count;
  return PERI_OK;
}

int peri_deck_vector(const peri_node *map, const char *key, bool required, int n, double *out) {
  int count;
  return peri_deck_vector_range(map, key, required, n, n, out, &count);
}

int peri_deck_node_expr(const peri_node *node, const char *what, peri_expr **out) {
  if (!node) return missing_node(what);
  if (!is_value_scalar(node)) return report_expected(node, what, "a number or an expression");
  double number;
  number_status status = parse_number(node->scalar, &number);
  if (status == NUMBER_OK) {
    *out = peri_expr_constant(number);
    return PERI_OK;
  }
  if (status == NUMBER_NOT_FINITE) return report_expected(node, what, "a finite number");
  char reason[256];
  peri_expr *expression = peri_expr_parse(node->scalar, reason, sizeof reason);
  if (!expression)
    return peri_deck_error(node, "%s: bad expression '%s': %s", what, node->scalar, reason);
  *out = expression;
  return PERI_OK;
}

int peri_deck_expr(const peri_node *map, const char *key, bool required, peri_expr **out) {
  const peri_node *value;
  int status = find_value(map, key, required, &value);
  if (status != PERI_OK || !value) return status;
  char label[LABEL_SIZE];
  key_label(key, label, sizeof label);
  return peri_deck_node_expr(value, label, out);
}
