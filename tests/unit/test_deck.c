/* The deck layer: node positions, typed accessors and the exact messages users see. */
#include <criterion/criterion.h>
#include <criterion/redirect.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "peri/deck.h"
#include "peri/error.h"

static peri_node *parse(const char *text) {
  peri_node *root = peri_deck_parse_string(text, "deck.yaml");
  cr_assert_not_null(root, "deck should parse:\n%s", text);
  return root;
}

/* Everything written to stderr so far, for comparing whole messages. */
static void expect_stderr(const char *expected) {
  fflush(stderr);
  cr_assert_stderr_eq_str(expected);
}

static void expect_position(const peri_node *node, int line, int col) {
  cr_assert_not_null(node);
  cr_assert_eq(node->line, line, "line %d, expected %d", node->line, line);
  cr_assert_eq(node->col, col, "col %d, expected %d", node->col, col);
}

/* ---- tree and positions ------------------------------------------------------------ */

static const char *positions_deck =
    "# a comment\n"
    "discretization:\n"
    "  spacing: 1.0e-3\n"
    "  origin: [0, 1.5, -2]\n"
    "materials:\n"
    "  - name: glass\n"
    "    density: 2440\n"
    "  - {name: steel}\n"
    "title: 'quoted'\n";

Test(deck_tree, positions_are_one_based) {
  peri_node *root = parse(positions_deck);
  cr_assert_eq(root->kind, PERI_NODE_MAPPING);
  cr_assert_eq(root->count, 3);
  cr_assert_str_eq(root->file, "deck.yaml");
  expect_position(root, 2, 1);

  const peri_node *disc = peri_deck_get(root, "discretization");
  cr_assert_eq(disc->kind, PERI_NODE_MAPPING);
  expect_position(disc, 3, 3);
  expect_position(peri_deck_key_node(root, "discretization"), 2, 1);
  expect_position(peri_deck_get(disc, "spacing"), 3, 12);
  expect_position(peri_deck_key_node(disc, "spacing"), 3, 3);

  const peri_node *origin = peri_deck_get(disc, "origin");
  cr_assert_eq(origin->kind, PERI_NODE_SEQUENCE);
  cr_assert_eq(origin->count, 3);
  expect_position(origin, 4, 11);
  expect_position(origin->items[2], 4, 20);
  cr_assert_str_eq(origin->items[2]->scalar, "-2");

  const peri_node *materials = peri_deck_get(root, "materials");
  cr_assert_eq(materials->kind, PERI_NODE_SEQUENCE);
  cr_assert_eq(materials->count, 2);
  expect_position(materials, 6, 3);
  expect_position(materials->items[0], 6, 5);
  expect_position(peri_deck_get(materials->items[0], "density"), 7, 14);
  expect_position(materials->items[1], 8, 5);
  cr_assert_str_eq(peri_deck_get(materials->items[1], "name")->scalar, "steel");

  const peri_node *title = peri_deck_get(root, "title");
  cr_assert_str_eq(title->scalar, "quoted");
  expect_position(title, 9, 8);
  cr_assert_eq(title->file, root->file, "nodes share the file name");
  peri_deck_free(root);
}

Test(deck_tree, get_absent_key_and_null_map) {
  peri_node *root = parse("a: 1\n");
  cr_assert_null(peri_deck_get(root, "b"));
  cr_assert_null(peri_deck_get(root, "A"), "keys are case-sensitive");
  cr_assert_null(peri_deck_key_node(root, "b"));
  cr_assert_null(peri_deck_get(NULL, "a"));
  cr_assert_null(peri_deck_get(peri_deck_get(root, "a"), "x"), "a scalar has no keys");
  peri_deck_free(root);
  peri_deck_free(NULL);
}

Test(deck_tree, kind_names) {
  peri_node *root = parse("m: {a: 1}\nl: [1]\nn: 2.5\ns: abc\nempty:\ntilde: ~\nq: ''\n");
  cr_assert_str_eq(peri_deck_kind_name(peri_deck_get(root, "m")), "a mapping");
  cr_assert_str_eq(peri_deck_kind_name(peri_deck_get(root, "l")), "a list");
  cr_assert_str_eq(peri_deck_kind_name(peri_deck_get(root, "n")), "a number");
  cr_assert_str_eq(peri_deck_kind_name(peri_deck_get(root, "s")), "a string");
  cr_assert_str_eq(peri_deck_kind_name(peri_deck_get(root, "empty")), "null");
  cr_assert_str_eq(peri_deck_kind_name(peri_deck_get(root, "tilde")), "null");
  cr_assert_str_eq(peri_deck_kind_name(peri_deck_get(root, "q")), "a string",
                   "a quoted empty string is not null");
  peri_deck_free(root);
}

Test(deck_tree, load_from_file) {
  char path[] = "/tmp/peri_test_deck_XXXXXX";
  int fd = mkstemp(path);
  cr_assert_geq(fd, 0);
  const char *text = "\n\nsolver:\n  steps: 10\n";
  cr_assert_eq(write(fd, text, strlen(text)), (ssize_t)strlen(text));
  close(fd);
  peri_node *root = peri_deck_load(path);
  unlink(path);
  cr_assert_not_null(root);
  cr_assert_str_eq(root->file, path);
  expect_position(peri_deck_get(peri_deck_get(root, "solver"), "steps"), 4, 10);
  peri_deck_free(root);
}

Test(deck_tree, load_missing_file, .init = cr_redirect_stderr) {
  cr_assert_null(peri_deck_load("/nonexistent/deck.yaml"));
  expect_stderr("peri: error: cannot open deck '/nonexistent/deck.yaml': "
                "No such file or directory\n");
}

/* ---- load errors ------------------------------------------------------------------- */

Test(deck_load, syntax_error, .init = cr_redirect_stderr) {
  cr_assert_null(peri_deck_parse_string("a: 1\n b: 2\n", "deck.yaml"));
  expect_stderr("deck.yaml:2:3: error: mapping values are not allowed in this context\n");
}

Test(deck_load, syntax_error_with_context, .init = cr_redirect_stderr) {
  cr_assert_null(peri_deck_parse_string("a: [1, 2\nb: 3\n", "deck.yaml"));
  expect_stderr("deck.yaml:2:2: error: did not find expected ',' or ']' "
                "(while parsing a flow sequence started at line 1, column 4)\n");
}

Test(deck_load, tab_indentation, .init = cr_redirect_stderr) {
  cr_assert_null(peri_deck_parse_string("a:\n\tb: 1\n", "deck.yaml"));
  expect_stderr("deck.yaml:2:1: error: tab character; YAML indentation must use spaces\n");
}

Test(deck_load, tab_after_multibyte_text, .init = cr_redirect_stderr) {
  /* libyaml counts characters; the tab must still be found behind "éé". */
  cr_assert_null(peri_deck_parse_string("a: \"\xc3\xa9\xc3\xa9\"\nb:\n \tc: 1\n", "deck.yaml"));
  expect_stderr("deck.yaml:3:2: error: tab character; YAML indentation must use spaces\n");
}

Test(deck_load, bad_encoding_after_multibyte_text, .init = cr_redirect_stderr) {
  cr_assert_null(peri_deck_parse_string("\xef\xbb\xbf" "a: \xc3\xa9\xff\n", "deck.yaml"));
  expect_stderr("deck.yaml:1:5: error: invalid leading UTF-8 octet (0xFF)\n");
}

Test(deck_load, bad_encoding, .init = cr_redirect_stderr) {
  cr_assert_null(peri_deck_parse_string("a: 1\nb: \xff\n", "deck.yaml"));
  expect_stderr("deck.yaml:2:4: error: invalid leading UTF-8 octet (0xFF)\n");
}

Test(deck_load, duplicate_key, .init = cr_redirect_stderr) {
  cr_assert_null(peri_deck_parse_string("a: 1\nm:\n  b: 2\n  b: 3\n", "deck.yaml"));
  expect_stderr("deck.yaml:4:3: error: duplicate key 'b' (first given at line 3, column 3)\n");
}

/* With several repeated keys, the one met first going down the deck is reported, at its
 * second occurrence, whatever the order of the names. */
Test(deck_load, first_duplicate_in_deck_order, .init = cr_redirect_stderr) {
  cr_assert_null(peri_deck_parse_string("z: 1\nb: 2\nb: 3\nz: 4\nb: 5\n", "deck.yaml"));
  expect_stderr("deck.yaml:3:1: error: duplicate key 'b' (first given at line 2, column 1)\n");
}

Test(deck_lookup, key_index_in_a_large_mapping) {
  enum { KEYS = 5000 };
  char *text = malloc(KEYS * 24);
  size_t length = 0;
  for (int i = KEYS - 1; i >= 0; i--) length += (size_t)sprintf(text + length, "k%d: %d\n", i, i);
  peri_node *root = peri_deck_parse_string(text, "deck.yaml");
  free(text);
  cr_assert_not_null(root);
  for (int i = 0; i < KEYS; i += 7) {
    char key[16];
    sprintf(key, "k%d", i);
    int index = peri_deck_key_index(root, key);
    cr_assert_eq(index, KEYS - 1 - i, "%s at %d", key, index);
    cr_assert_str_eq(root->items[index]->scalar, key + 1);
  }
  cr_assert_eq(peri_deck_key_index(root, "k5000"), -1);
  cr_assert_null(peri_deck_get(root, "missing"));
  peri_deck_free(root);
}

Test(deck_load, anchor_rejected, .init = cr_redirect_stderr) {
  cr_assert_null(peri_deck_parse_string("a: &v 1\n", "deck.yaml"));
  expect_stderr("deck.yaml:1:4: error: anchors are not supported ('&v'); "
                "write the value out in full\n");
}

Test(deck_load, alias_rejected, .init = cr_redirect_stderr) {
  cr_assert_null(peri_deck_parse_string("a: [1]\nb: *v\n", "deck.yaml"));
  expect_stderr("deck.yaml:2:4: error: aliases are not supported ('*v'); "
                "write the value out in full\n");
}

Test(deck_load, empty_deck, .init = cr_redirect_stderr) {
  cr_assert_null(peri_deck_parse_string("# only a comment\n", "deck.yaml"));
  expect_stderr("deck.yaml:1:1: error: the deck is empty; expected a mapping of sections\n");
}

Test(deck_load, root_must_be_mapping, .init = cr_redirect_stderr) {
  cr_assert_null(peri_deck_parse_string("- 1\n- 2\n", "deck.yaml"));
  expect_stderr("deck.yaml:1:1: error: the deck must be a mapping of sections, got a list\n");
}

Test(deck_load, second_document, .init = cr_redirect_stderr) {
  cr_assert_null(peri_deck_parse_string("a: 1\n---\nb: 2\n", "deck.yaml"));
  expect_stderr("deck.yaml:2:1: error: a second YAML document; a deck holds exactly one\n");
}

Test(deck_load, complex_key, .init = cr_redirect_stderr) {
  cr_assert_null(peri_deck_parse_string("? [a]\n: 1\n", "deck.yaml"));
  expect_stderr("deck.yaml:1:3: error: a mapping key must be a name, not a list or a mapping\n");
}

Test(deck_load, deep_nesting, .init = cr_redirect_stderr) {
  char text[1024];
  memset(text, '[', 600);
  text[600] = '\0';
  char deck[1100];
  snprintf(deck, sizeof deck, "a: %s", text);
  cr_assert_null(peri_deck_parse_string(deck, "deck.yaml"));
  expect_stderr("deck.yaml:1:132: error: the deck is nested too deeply\n");
}

/* ---- peri_deck_error --------------------------------------------------------------- */

Test(deck_error, format_and_status, .init = cr_redirect_stderr) {
  peri_node *root = parse("a:\n  b: 7\n");
  int status = peri_deck_error(peri_deck_get(peri_deck_get(root, "a"), "b"), "bad %s %d", "x", 3);
  cr_assert_eq(status, PERI_ERR_INPUT);
  cr_assert_eq(status, 2);
  peri_deck_free(root);
  expect_stderr("deck.yaml:2:6: error: bad x 3\n");
}

/* ---- numbers ----------------------------------------------------------------------- */

Test(deck_double, accepted_forms) {
  peri_node *root = parse("a: 1e-3\nb: 2.5E+9\nc: -4\nd: .5\ne: ' 7.25 '\nf: 0\n");
  const char *keys[] = {"a", "b", "c", "d", "e", "f"};
  double expected[] = {1e-3, 2.5e9, -4, 0.5, 7.25, 0};
  for (int i = 0; i < 6; i++) {
    double value = -1;
    cr_assert_eq(peri_deck_double(root, keys[i], true, &value), PERI_OK);
    cr_assert_eq(value, expected[i], "key %s", keys[i]);
  }
  peri_deck_free(root);
}

Test(deck_double, optional_absent_keeps_default) {
  peri_node *root = parse("a: 1\n");
  double value = 42;
  cr_assert_eq(peri_deck_double(root, "b", false, &value), PERI_OK);
  cr_assert_eq(value, 42);
  cr_assert_eq(peri_deck_double(NULL, "b", false, &value), PERI_OK);
  cr_assert_eq(value, 42);
  peri_deck_free(root);
}

Test(deck_double, not_a_number, .init = cr_redirect_stderr) {
  peri_node *root = parse("materials:\n  glass:\n    density: abc\n");
  const peri_node *glass = peri_deck_get(peri_deck_get(root, "materials"), "glass");
  double value = 0;
  cr_assert_eq(peri_deck_double(glass, "density", true, &value), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:3:14: error: key 'density': expected a number, got 'abc'\n");
}

Test(deck_double, partial_parse_rejected, .init = cr_redirect_stderr) {
  peri_node *root = parse("a: 1.5 m\nb: ''\n");
  double value = 0;
  cr_assert_eq(peri_deck_double(root, "a", true, &value), PERI_ERR_INPUT);
  cr_assert_eq(peri_deck_double(root, "b", true, &value), PERI_ERR_INPUT);
  cr_assert_eq(value, 0);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:4: error: key 'a': expected a number, got '1.5 m'\n"
                "deck.yaml:2:4: error: key 'b': expected a number, got ''\n");
}

Test(deck_double, infinity_rejected, .init = cr_redirect_stderr) {
  peri_node *root = parse("a: inf\nb: nan\nc: 1e999\n");
  double value = 0;
  cr_assert_eq(peri_deck_double(root, "a", true, &value), PERI_ERR_INPUT);
  cr_assert_eq(peri_deck_double(root, "b", true, &value), PERI_ERR_INPUT);
  cr_assert_eq(peri_deck_double(root, "c", true, &value), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:4: error: key 'a': expected a finite number, got 'inf'\n"
                "deck.yaml:2:4: error: key 'b': expected a finite number, got 'nan'\n"
                "deck.yaml:3:4: error: key 'c': expected a finite number, got '1e999'\n");
}

Test(deck_double, null_rejected_even_when_optional, .init = cr_redirect_stderr) {
  peri_node *root = parse("a:\nb: ~\n");
  double value = 0;
  cr_assert_eq(peri_deck_double(root, "a", true, &value), PERI_ERR_INPUT);
  cr_assert_eq(peri_deck_double(root, "b", false, &value), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:3: error: key 'a': expected a number, got null\n"
                "deck.yaml:2:4: error: key 'b': expected a number, got null\n");
}

Test(deck_double, list_where_number_expected, .init = cr_redirect_stderr) {
  peri_node *root = parse("solver:\n  dt: [1, 2]\n");
  double value = 0;
  cr_assert_eq(peri_deck_double(peri_deck_get(root, "solver"), "dt", true, &value),
               PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:2:7: error: key 'dt': expected a number, got a list\n");
}

Test(deck_double, missing_required_key, .init = cr_redirect_stderr) {
  peri_node *root = parse("title: x\ndiscretization:\n  horizon: 3\n");
  double value = 0;
  cr_assert_eq(peri_deck_double(peri_deck_get(root, "discretization"), "spacing", true, &value),
               PERI_ERR_INPUT);
  cr_assert_eq(peri_deck_double(root, "time", true, &value), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:3:3: error: missing key 'spacing' in discretization\n"
                "deck.yaml:1:1: error: missing key 'time' in the deck\n");
}

Test(deck_double, missing_key_in_list_item_names_the_item, .init = cr_redirect_stderr) {
  peri_node *root = parse("materials:\n  - density: 1\n  - name: b\n");
  const peri_node *second = peri_deck_get(root, "materials")->items[1];
  double value = 0;
  cr_assert_eq(peri_deck_double(second, "density", true, &value), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:3:5: error: missing key 'density' in materials[1]\n");
}

Test(deck_double, missing_with_null_map, .init = cr_redirect_stderr) {
  double value = 0;
  cr_assert_eq(peri_deck_double(NULL, "spacing", true, &value), PERI_ERR_INPUT);
  expect_stderr("peri: error: missing key 'spacing'\n");
}

Test(deck_double, map_is_not_a_mapping, .init = cr_redirect_stderr) {
  peri_node *root = parse("solver: 3\n");
  double value = 0;
  cr_assert_eq(peri_deck_double(peri_deck_get(root, "solver"), "dt", false, &value),
               PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:9: error: expected a mapping with key 'dt', got '3'\n");
}

Test(deck_double, long_value_is_shortened, .init = cr_redirect_stderr) {
  peri_node *root = parse("a: aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa\n");
  double value = 0;
  cr_assert_eq(peri_deck_double(root, "a", true, &value), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:4: error: key 'a': expected a number, got "
                "'aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa...'\n");
}

Test(deck_node_double, sequence_item) {
  peri_node *root = parse("a: [3.5]\n");
  double value = 0;
  cr_assert_eq(peri_deck_node_double(peri_deck_get(root, "a")->items[0], "item", &value),
               PERI_OK);
  cr_assert_eq(value, 3.5);
  peri_deck_free(root);
}

Test(deck_node_double, error_uses_what, .init = cr_redirect_stderr) {
  peri_node *root = parse("a: [x1]\n");
  double value = 0;
  cr_assert_eq(peri_deck_node_double(peri_deck_get(root, "a")->items[0], "point 1", &value),
               PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:5: error: point 1: expected a number, got 'x1'\n");
}

/* ---- integers ---------------------------------------------------------------------- */

Test(deck_int, accepted_forms) {
  peri_node *root = parse("a: 42\nb: -7\nc: 1e6\nd: ' 12 '\n");
  long value = 0;
  cr_assert_eq(peri_deck_int(root, "a", true, &value), PERI_OK);
  cr_assert_eq(value, 42);
  cr_assert_eq(peri_deck_int(root, "b", true, &value), PERI_OK);
  cr_assert_eq(value, -7);
  cr_assert_eq(peri_deck_int(root, "c", true, &value), PERI_OK);
  cr_assert_eq(value, 1000000);
  cr_assert_eq(peri_deck_int(root, "d", true, &value), PERI_OK);
  cr_assert_eq(value, 12);
  value = 5;
  cr_assert_eq(peri_deck_int(root, "e", false, &value), PERI_OK);
  cr_assert_eq(value, 5);
  peri_deck_free(root);
}

Test(deck_int, fraction_and_range_rejected, .init = cr_redirect_stderr) {
  peri_node *root = parse("steps: 2.5\nbig: 99999999999999999999\nword: ten\n");
  long value = 0;
  cr_assert_eq(peri_deck_int(root, "steps", true, &value), PERI_ERR_INPUT);
  cr_assert_eq(peri_deck_int(root, "big", true, &value), PERI_ERR_INPUT);
  cr_assert_eq(peri_deck_int(root, "word", true, &value), PERI_ERR_INPUT);
  cr_assert_eq(peri_deck_int(root, "count", true, &value), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:8: error: key 'steps': expected an integer, got '2.5'\n"
                "deck.yaml:2:6: error: key 'big': expected an integer in range, "
                "got '99999999999999999999'\n"
                "deck.yaml:3:7: error: key 'word': expected an integer, got 'ten'\n"
                "deck.yaml:1:1: error: missing key 'count' in the deck\n");
}

/* ---- booleans ---------------------------------------------------------------------- */

Test(deck_bool, accepted_words) {
  peri_node *root = parse("a: true\nb: No\nc: ON\nd: off\ne: YES\nf: False\n");
  const char *keys[] = {"a", "b", "c", "d", "e", "f"};
  bool expected[] = {true, false, true, false, true, false};
  for (int i = 0; i < 6; i++) {
    bool value = !expected[i];
    cr_assert_eq(peri_deck_bool(root, keys[i], true, &value), PERI_OK);
    cr_assert_eq(value, expected[i], "key %s", keys[i]);
  }
  bool value = true;
  cr_assert_eq(peri_deck_bool(root, "g", false, &value), PERI_OK);
  cr_assert(value);
  peri_deck_free(root);
}

Test(deck_bool, other_words_rejected, .init = cr_redirect_stderr) {
  peri_node *root = parse("damage: maybe\nplot: 1\n");
  bool value = false;
  cr_assert_eq(peri_deck_bool(root, "damage", true, &value), PERI_ERR_INPUT);
  cr_assert_eq(peri_deck_bool(root, "plot", true, &value), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:9: error: key 'damage': expected true or false, got 'maybe'\n"
                "deck.yaml:2:7: error: key 'plot': expected true or false, got '1'\n");
}

/* ---- strings ----------------------------------------------------------------------- */

Test(deck_string, values) {
  peri_node *root = parse("name: glass\nnumber: 12\nempty: ''\n");
  const char *value = NULL;
  cr_assert_eq(peri_deck_string(root, "name", true, &value), PERI_OK);
  cr_assert_str_eq(value, "glass");
  cr_assert_eq(peri_deck_string(root, "number", true, &value), PERI_OK);
  cr_assert_str_eq(value, "12");
  cr_assert_eq(peri_deck_string(root, "empty", true, &value), PERI_OK);
  cr_assert_str_eq(value, "");
  value = "default";
  cr_assert_eq(peri_deck_string(root, "other", false, &value), PERI_OK);
  cr_assert_str_eq(value, "default");
  peri_deck_free(root);
}

Test(deck_string, wrong_kinds, .init = cr_redirect_stderr) {
  peri_node *root = parse("name: {a: 1}\nfile:\n");
  const char *value = NULL;
  cr_assert_eq(peri_deck_string(root, "name", true, &value), PERI_ERR_INPUT);
  cr_assert_eq(peri_deck_string(root, "file", true, &value), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:7: error: key 'name': expected a string, got a mapping\n"
                "deck.yaml:2:6: error: key 'file': expected a string, got null\n");
}

/* ---- choices ----------------------------------------------------------------------- */

static const char *const models[] = {"pmb", "lps", NULL};

Test(deck_choice, known_value) {
  peri_node *root = parse("model: lps\n");
  int index = -1;
  cr_assert_eq(peri_deck_choice(root, "model", true, models, &index), PERI_OK);
  cr_assert_eq(index, 1);
  index = 7;
  cr_assert_eq(peri_deck_choice(root, "other", false, models, &index), PERI_OK);
  cr_assert_eq(index, 7);
  peri_deck_free(root);
}

Test(deck_choice, suggestion, .init = cr_redirect_stderr) {
  peri_node *root = parse("material:\n  model: pbm\n");
  int index = -1;
  cr_assert_eq(peri_deck_choice(peri_deck_get(root, "material"), "model", true, models, &index),
               PERI_ERR_INPUT);
  cr_assert_eq(index, -1);
  peri_deck_free(root);
  expect_stderr("deck.yaml:2:10: error: key 'model': unknown value 'pbm'; did you mean 'pmb'? "
                "(choices: pmb, lps)\n");
}

Test(deck_choice, case_differs, .init = cr_redirect_stderr) {
  peri_node *root = parse("model: LPS\n");
  int index = -1;
  cr_assert_eq(peri_deck_choice(root, "model", true, models, &index), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:8: error: key 'model': unknown value 'LPS'; did you mean 'lps'? "
                "(choices: pmb, lps)\n");
}

Test(deck_choice, no_close_value, .init = cr_redirect_stderr) {
  peri_node *root = parse("model: elastic\n");
  int index = -1;
  cr_assert_eq(peri_deck_choice(root, "model", true, models, &index), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:8: error: key 'model': unknown value 'elastic' "
                "(choices: pmb, lps)\n");
}

Test(deck_choice, not_a_string, .init = cr_redirect_stderr) {
  peri_node *root = parse("model: [pmb]\n");
  int index = -1;
  cr_assert_eq(peri_deck_choice(root, "model", true, models, &index), PERI_ERR_INPUT);
  cr_assert_eq(peri_deck_choice(root, "kind", true, models, &index), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:8: error: key 'model': expected one of pmb, lps, got a list\n"
                "deck.yaml:1:1: error: missing key 'kind' in the deck\n");
}

/* ---- vectors ----------------------------------------------------------------------- */

Test(deck_vector, exact_count) {
  peri_node *root = parse("origin: [0, 1.5e-3, -2]\nblock:\n  - 4\n  - 5\n  - 6\n");
  double v[3] = {9, 9, 9};
  cr_assert_eq(peri_deck_vector(root, "origin", true, 3, v), PERI_OK);
  cr_assert_eq(v[0], 0);
  cr_assert_eq(v[1], 1.5e-3);
  cr_assert_eq(v[2], -2);
  cr_assert_eq(peri_deck_vector(root, "block", true, 3, v), PERI_OK);
  cr_assert_eq(v[2], 6);
  double untouched[2] = {7, 8};
  cr_assert_eq(peri_deck_vector(root, "size", false, 2, untouched), PERI_OK);
  cr_assert_eq(untouched[0], 7);
  cr_assert_eq(untouched[1], 8);
  peri_deck_free(root);
}

Test(deck_vector, wrong_count, .init = cr_redirect_stderr) {
  peri_node *root = parse("origin: [0, 1]\none: []\n");
  double v[3] = {9, 9, 9};
  cr_assert_eq(peri_deck_vector(root, "origin", true, 3, v), PERI_ERR_INPUT);
  cr_assert_eq(peri_deck_vector(root, "one", true, 1, v), PERI_ERR_INPUT);
  cr_assert_eq(v[0], 9);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:9: error: key 'origin': expected a list of 3 numbers, got a list "
                "of 2\n"
                "deck.yaml:2:6: error: key 'one': expected a list of 1 number, got a list of 0\n");
}

Test(deck_vector, bad_item_leaves_output, .init = cr_redirect_stderr) {
  peri_node *root = parse("origin: [0, abc, 2]\n");
  double v[3] = {9, 9, 9};
  cr_assert_eq(peri_deck_vector(root, "origin", true, 3, v), PERI_ERR_INPUT);
  cr_assert_eq(v[0], 9);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:13: error: key 'origin', item 2: expected a number, got 'abc'\n");
}

Test(deck_vector, scalar_where_list_expected, .init = cr_redirect_stderr) {
  peri_node *root = parse("origin: 5\n");
  double v[3];
  cr_assert_eq(peri_deck_vector(root, "origin", true, 3, v), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:9: error: key 'origin': expected a list of 3 numbers, got '5'\n");
}

Test(deck_vector, range) {
  peri_node *root = parse("size: [1, 2]\n");
  double v[3] = {0, 0, 0};
  int count = 0;
  cr_assert_eq(peri_deck_vector_range(root, "size", true, 1, 3, v, &count), PERI_OK);
  cr_assert_eq(count, 2);
  cr_assert_eq(v[0], 1);
  cr_assert_eq(v[1], 2);
  cr_assert_eq(v[2], 0);
  count = -1;
  cr_assert_eq(peri_deck_vector_range(root, "none", false, 1, 3, v, &count), PERI_OK);
  cr_assert_eq(count, -1);
  peri_deck_free(root);
}

Test(deck_vector, range_too_long, .init = cr_redirect_stderr) {
  peri_node *root = parse("size: [1, 2, 3, 4]\n");
  double v[3];
  int count = 0;
  cr_assert_eq(peri_deck_vector_range(root, "size", true, 2, 3, v, &count), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:7: error: key 'size': expected a list of 2 to 3 numbers, got a "
                "list of 4\n");
}

/* ---- expressions ------------------------------------------------------------------- */

Test(deck_expr, number_becomes_constant) {
  peri_node *root = parse("value: 2.5e3\n");
  peri_expr *e = NULL;
  cr_assert_eq(peri_deck_expr(root, "value", true, &e), PERI_OK);
  cr_assert(peri_expr_is_constant(e));
  cr_assert_eq(peri_expr_eval(e, 1, 2, 3, 4), 2500.0);
  peri_expr_free(e);
  peri_deck_free(root);
}

Test(deck_expr, formula) {
  peri_node *root = parse("value: 200 - 50*((z/0.05)-1)^2\nramp: '-100*t + 0.00155'\n");
  peri_expr *e = NULL;
  cr_assert_eq(peri_deck_expr(root, "value", true, &e), PERI_OK);
  cr_assert_not(peri_expr_is_constant(e));
  cr_assert_float_eq(peri_expr_eval(e, 0, 0, 0.025, 0), 187.5, 1e-12);
  peri_expr_free(e);
  cr_assert_eq(peri_deck_expr(root, "ramp", true, &e), PERI_OK);
  cr_assert_float_eq(peri_expr_eval(e, 0, 0, 0, 1e-5), 0.00055, 1e-15);
  peri_expr_free(e);
  e = NULL;
  cr_assert_eq(peri_deck_expr(root, "absent", false, &e), PERI_OK);
  cr_assert_null(e);
  peri_deck_free(root);
}

Test(deck_expr, unknown_variable, .init = cr_redirect_stderr) {
  peri_node *root = parse("a: 1\nb: 2\nc: 3\nd: 4\ne: 5\nf: 6\ng: 7\nh: 8\n"
                          "boundary:\n  value: 2*q\n");
  peri_expr *e = NULL;
  cr_assert_eq(peri_deck_expr(peri_deck_get(root, "boundary"), "value", true, &e),
               PERI_ERR_INPUT);
  cr_assert_null(e);
  peri_deck_free(root);
  expect_stderr("deck.yaml:10:10: error: key 'value': bad expression '2*q': unknown variable "
                "'q' (allowed: x, y, z, t)\n");
}

Test(deck_expr, bad_syntax_and_wrong_kind, .init = cr_redirect_stderr) {
  peri_node *root = parse("a: 2*(x\nb: [1]\nc:\n");
  peri_expr *e = NULL;
  cr_assert_eq(peri_deck_expr(root, "a", true, &e), PERI_ERR_INPUT);
  cr_assert_eq(peri_deck_expr(root, "b", true, &e), PERI_ERR_INPUT);
  cr_assert_eq(peri_deck_expr(root, "c", true, &e), PERI_ERR_INPUT);
  cr_assert_null(e);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:4: error: key 'a': bad expression '2*(x': missing parenthesis\n"
                "deck.yaml:2:4: error: key 'b': expected a number or an expression, got a list\n"
                "deck.yaml:3:3: error: key 'c': expected a number or an expression, got null\n");
}

Test(deck_expr, node_expr) {
  peri_node *root = parse("values: [x + 1, 3]\n");
  const peri_node *values = peri_deck_get(root, "values");
  peri_expr *e = NULL;
  cr_assert_eq(peri_deck_node_expr(values->items[0], "item 1", &e), PERI_OK);
  cr_assert_eq(peri_expr_eval(e, 2, 0, 0, 0), 3.0);
  peri_expr_free(e);
  cr_assert_eq(peri_deck_node_expr(values->items[1], "item 2", &e), PERI_OK);
  cr_assert(peri_expr_is_constant(e));
  peri_expr_free(e);
  peri_deck_free(root);
}

/* ---- allowed keys ------------------------------------------------------------------ */

static const char *const material_keys[] = {"density", "bulk_modulus", "critical_stretch",
                                            NULL};

Test(deck_allow, all_known) {
  peri_node *root = parse("density: 1\ncritical_stretch: 2\n");
  cr_assert_eq(peri_deck_allow(root, "materials.glass", material_keys), PERI_OK);
  cr_assert_eq(peri_deck_allow(NULL, "materials.glass", material_keys), PERI_OK);
  peri_deck_free(root);
}

Test(deck_allow, suggestion, .init = cr_redirect_stderr) {
  peri_node *root = parse("materials:\n  glass:\n    density: 1\n"
                          "    bulk_modulus: 2\n"
                          "    critical_stretch: 3\n"
                          "\n"
                          "\n"
                          "\n"
                          "\n"
                          "\n"
                          "\n"
                          "    densty: 4\n");
  const peri_node *glass = peri_deck_get(peri_deck_get(root, "materials"), "glass");
  cr_assert_eq(peri_deck_allow(glass, "materials.glass", material_keys), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:12:5: error: unknown key 'densty' in materials.glass; "
                "did you mean 'density'?\n");
}

Test(deck_allow, no_close_key_lists_accepted, .init = cr_redirect_stderr) {
  peri_node *root = parse("colour: red\nDensity: 3\n");
  cr_assert_eq(peri_deck_allow(root, "materials.glass", material_keys), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:1: error: unknown key 'colour' in materials.glass; accepted keys: "
                "density, bulk_modulus, critical_stretch\n"
                "deck.yaml:2:1: error: unknown key 'Density' in materials.glass; "
                "did you mean 'density'?\n");
}

Test(deck_allow, short_key_not_rewritten, .init = cr_redirect_stderr) {
  static const char *const axes[] = {"x", "y", NULL};
  peri_node *root = parse("q: 1\n");
  cr_assert_eq(peri_deck_allow(root, "axes", axes), PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:1: error: unknown key 'q' in axes; accepted keys: x, y\n");
}

Test(deck_allow, not_a_mapping, .init = cr_redirect_stderr) {
  peri_node *root = parse("solver: [1, 2]\n");
  cr_assert_eq(peri_deck_allow(peri_deck_get(root, "solver"), "solver", material_keys),
               PERI_ERR_INPUT);
  peri_deck_free(root);
  expect_stderr("deck.yaml:1:9: error: section 'solver': expected a mapping, got a list\n");
}

/* ---- edit distance ----------------------------------------------------------------- */

Test(deck_edit_distance, values) {
  cr_assert_eq(peri_edit_distance("kitten", "sitting"), 3);
  cr_assert_eq(peri_edit_distance("densty", "density"), 1);
  cr_assert_eq(peri_edit_distance("pbm", "pmb"), 2);
  cr_assert_eq(peri_edit_distance("", "abc"), 3);
  cr_assert_eq(peri_edit_distance("abc", ""), 3);
  cr_assert_eq(peri_edit_distance("", ""), 0);
  cr_assert_eq(peri_edit_distance("Density", "dENSITY"), 0, "case-insensitive");
  cr_assert_eq(peri_edit_distance("flaw", "lawn"), 2);
}
