"""A deck given as a Python dict, written as the YAML text peri reads.

The dict has the structure of a YAML deck (docs/deck.md): mappings are dicts, lists are
lists, scalars are numbers, booleans, strings (expressions such as "2e6 * t" too) or None.
Mappings and lists of mappings are written in block style, one key per line, so that the
line and column of an error message point at one key; lists of scalars in flow style,
[a, b, c]. Strings are double-quoted, so no text is taken for something else.
"""
import json
import math
import numbers
import re

_PLAIN_KEY = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.\-]*$")


def scalar(value):
    """The YAML text of one scalar."""
    if value is None:
        return "null"
    if isinstance(value, bool) or type(value).__name__ == "bool_":
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        x = float(value)
        if math.isnan(x):
            return ".nan"
        if math.isinf(x):
            return ".inf" if x > 0 else "-.inf"
        return repr(x)
    if isinstance(value, str):
        return json.dumps(value)  # a YAML double-quoted scalar
    raise TypeError(f"deck value {value!r} of type {type(value).__name__}: expected a number, "
                    "a boolean, a string, None, a list or a dict")


def _key(key):
    if not isinstance(key, str):
        raise TypeError(f"deck key {key!r}: expected a string")
    return key if _PLAIN_KEY.match(key) else json.dumps(key)


def _as_list(value):
    """Lists, tuples and NumPy arrays as lists; anything else unchanged."""
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):
        value = value.tolist()
    return list(value) if isinstance(value, tuple) else value


def flow(value):
    """The YAML text of a value on one line: [a, b], {k: v}, or a scalar (an override)."""
    value = _as_list(value)
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_key(k)}: {flow(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(flow(v) for v in value) + "]"
    return scalar(value)


def _is_flat(value):
    """A list of scalars, or of lists of scalars (coordinates, vertices): one line."""
    return all(not isinstance(_as_list(v), (dict, list)) or
               (isinstance(_as_list(v), list) and _is_flat(_as_list(v))) for v in value)


def _block(value, indent, lines):
    pad = " " * indent
    value = _as_list(value)
    if isinstance(value, dict):
        for key, item in value.items():
            item = _as_list(item)
            if isinstance(item, dict) and item:
                lines.append(f"{pad}{_key(key)}:")
                _block(item, indent + 2, lines)
            elif isinstance(item, list) and item and not _is_flat(item):
                lines.append(f"{pad}{_key(key)}:")
                _block(item, indent + 2, lines)
            else:
                lines.append(f"{pad}{_key(key)}: {flow(item)}")
    elif isinstance(value, list):
        for item in value:
            item = _as_list(item)
            if isinstance(item, dict) and item:
                sub = []
                _block(item, indent + 2, sub)
                sub[0] = pad + "- " + sub[0][indent + 2:]
                lines.extend(sub)
            else:
                lines.append(f"{pad}- {flow(item)}")
    else:
        lines.append(pad + scalar(value))


def dump(deck):
    """The YAML text of a deck given as a dict."""
    if not isinstance(deck, dict):
        raise TypeError(f"a deck is a dict (the YAML deck's structure), got {type(deck).__name__}")
    lines = []
    _block(deck, 0, lines)
    return "\n".join(lines) + "\n"
