/* The deck: a YAML document read with libyaml into a tree whose every node knows its
 * file, line and column, plus typed accessors that report errors at that position.
 *
 * Every mapping records which of its keys were read. A section parser declares the
 * keys it accepts with peri_deck_allow(); an unknown key is an error that names the
 * nearest accepted key ("did you mean ...?"). Nothing the user wrote is ignored. */
#ifndef PERI_DECK_H
#define PERI_DECK_H
#include <stdbool.h>
#include "peri/expr.h"

typedef enum { PERI_NODE_SCALAR, PERI_NODE_SEQUENCE, PERI_NODE_MAPPING } peri_node_kind;

typedef struct peri_node peri_node;
struct peri_node {
  peri_node_kind kind;
  const char *file; /* shared by all nodes of a document */
  int line, col;    /* 1-based position of the node's first character */
  char *scalar;     /* SCALAR: the text; NULL otherwise */
  int count;        /* SEQUENCE: items; MAPPING: entries */
  peri_node **items;/* SEQUENCE: the items; MAPPING: the values, parallel to keys */
  peri_node **keys; /* MAPPING: the key nodes (scalars) */
};

/* Reads a YAML file. On error prints "file:line:col: error: ..." and returns NULL. A deck
 * whose root is not a mapping, or a mapping with a repeated key, is an error. */
peri_node *peri_deck_load(const char *path);
/* Same from a string, reported under the name `name` (for tests). */
peri_node *peri_deck_parse_string(const char *text, const char *name);
void peri_deck_free(peri_node *root);

/* Prints "file:line:col: error: <message>" with the position of `at`. Returns PERI_ERR_INPUT. */
int peri_deck_error(const peri_node *at, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Checks that `map` is a mapping whose keys are all in the NULL-terminated list
 * `allowed`. `section` names the section in messages (e.g. "materials.glass").
 * On an unknown key prints e.g.
 *   deck.yaml:12:5: error: unknown key 'densty' in materials.glass; did you mean 'density'?
 * (the suggestion is the allowed key of least edit distance, offered when that distance
 * is at most max(2, len/3)) and returns PERI_ERR_INPUT; otherwise PERI_OK. */
int peri_deck_allow(const peri_node *map, const char *section, const char *const *allowed);
/* Edit (Levenshtein) distance, case-insensitive; exposed for tests. */
int peri_edit_distance(const char *a, const char *b);

/* The value under `key` in a mapping, or NULL if absent (or map is NULL). */
peri_node *peri_deck_get(const peri_node *map, const char *key);
/* The node of the key itself (for error positions), or NULL. */
const peri_node *peri_deck_key_node(const peri_node *map, const char *key);
/* The position of `key` among the mapping's keys, or -1; a binary search. */
int peri_deck_key_index(const peri_node *map, const char *key);

/* Typed accessors. Each returns PERI_OK, or PERI_ERR_INPUT after printing a message that
 * names file:line:col, the key, what was expected and what was found. When the key is
 * absent: if `required`, the message is "missing key 'k' in <section>" at the mapping's
 * position; otherwise *out is left untouched (holding the caller's default) and PERI_OK. */
int peri_deck_double(const peri_node *map, const char *key, bool required, double *out);
int peri_deck_int(const peri_node *map, const char *key, bool required, long *out);
int peri_deck_bool(const peri_node *map, const char *key, bool required, bool *out);
/* *out points into the tree (valid until peri_deck_free). */
int peri_deck_string(const peri_node *map, const char *key, bool required, const char **out);
/* A string that must be one of the NULL-terminated `choices`; *out is its index. An
 * unknown value gets a "did you mean" suggestion and the list of choices. */
int peri_deck_choice(const peri_node *map, const char *key, bool required,
                     const char *const *choices, int *out);
/* A sequence of exactly n numbers, e.g. [0, 1.5e-3, 0]. */
int peri_deck_vector(const peri_node *map, const char *key, bool required, int n, double *out);
/* A sequence of between min_n and max_n numbers; *count receives how many. */
int peri_deck_vector_range(const peri_node *map, const char *key, bool required, int min_n,
                           int max_n, double *out, int *count);
/* A number or an expression string in x y z t. */
int peri_deck_expr(const peri_node *map, const char *key, bool required, peri_expr **out);
/* Parse a scalar node itself (for sequence items). */
int peri_deck_node_double(const peri_node *node, const char *what, double *out);
int peri_deck_node_expr(const peri_node *node, const char *what, peri_expr **out);

/* The name of a node's kind for messages: "a number", "a mapping", ... */
const char *peri_deck_kind_name(const peri_node *node);

#endif
