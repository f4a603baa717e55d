#!/usr/bin/env bash
# `make install` into a staging folder (DESTDIR), then what a user of the installation does:
# a C program built with `pkg-config --cflags --libs peri` runs a deck through the installed
# libperi.so and checks its answer against theory (bar.c, bar.yaml), and again linked with
# libperi.a and `pkg-config --static --libs peri`; the installed peri runs;
# the installed Python module imports, finds the installed library and runs the same deck.
# usage: pkg_config.sh BUILD_DIR [PYTHON_WITH_NUMPY]
set -euo pipefail
build=$1
python=${2:-}
here=$(cd "$(dirname "$0")" && pwd)
stage=$(mktemp -d /tmp/peri_install_XXXXXX)
trap 'rm -rf "$stage"' EXIT
fail() { echo "FAIL: install: $*"; exit 1; }

DESTDIR="$stage" cmake --install "$build" >"$stage/install.log" || { cat "$stage/install.log"; fail "cmake --install"; }
pc=$(find "$stage" -name peri.pc)
[[ -n "$pc" ]] || fail "no peri.pc installed"
export PKG_CONFIG_PATH=$(dirname "$pc")
prefix=$(cd "$(pkg-config --variable=prefix peri)" && pwd)
libdir=$(pkg-config --variable=libdir peri)
for file in bin/peri include/peri/api.h include/peri/sim.h; do
  [[ -f "$prefix/$file" ]] || fail "$prefix/$file is missing"
done
ls "$libdir"/libperi.a "$libdir"/libperi.so >/dev/null || fail "libperi.a or libperi.so missing in $libdir"
pkg-config --exists --print-errors peri || fail "pkg-config cannot read peri.pc"
[[ $(pkg-config --modversion peri) == $("$prefix/bin/peri" --version | awk '{print $2}') ]] || fail "peri.pc and peri disagree on the version"

# the C program, compiled and linked as the README says, against the staged library
cc -std=c11 -Wall -Wextra -Werror -o "$stage/bar" "$here/bar.c" $(pkg-config --cflags --libs peri) -lm ||
  fail "bar.c does not build with pkg-config --cflags --libs peri: $(pkg-config --cflags --libs peri)"
linked=$(LD_LIBRARY_PATH="$libdir" ldd "$stage/bar")
[[ $linked == *"$libdir/libperi.so"* ]] || fail "bar is not linked to the installed libperi.so: $linked"
LD_LIBRARY_PATH="$libdir" "$stage/bar" "$here/bar.yaml" "$stage/bar_output" || fail "bar.c: the deck's answer is not u = eps x"
[[ -f "$stage/bar_output/history.csv" ]] || fail "the run through the library wrote no history.csv"

# the same against the static library, with the dependencies of peri.pc's private fields
cc -std=c11 -o "$stage/bar_static" "$here/bar.c" $(pkg-config --cflags peri) "$libdir/libperi.a" \
  $(pkg-config --static --libs peri | sed 's/-lperi\b//') -lm || fail "bar.c does not link libperi.a with pkg-config --static --libs peri"
[[ $(ldd "$stage/bar_static") != *libperi* ]] || fail "bar_static uses libperi.so"
"$stage/bar_static" "$here/bar.yaml" "$stage/bar_static_output" || fail "bar.c linked statically: the deck's answer is not u = eps x"

# the installed program
"$prefix/bin/peri" check "$here/bar.yaml" >/dev/null || fail "the installed peri cannot check the deck"

# the installed Python module finds the installed library
if [[ -n "$python" ]]; then
  init=$(find "$stage" -path '*/peri/__init__.py' | head -n 1)
  [[ -n "$init" ]] || fail "the Python module is not installed"
  PYTHONPATH=$(dirname "$(dirname "$init")") PYTHONDONTWRITEBYTECODE=1 "$python" - "$stage" "$here/bar.yaml" "$stage/py_output" <<'PY' || fail "the installed Python module"
import sys
import numpy as np
import peri
stage, deck, out = sys.argv[1:]
assert peri.library_path.startswith(stage), f"loaded {peri.library_path}, not the installed library"
with peri.Simulation(deck, output=out) as sim:
    sim.run()
    x, u = sim.field("reference_position")[:, 0], sim.displacement[:, 0]
worst = np.abs(u - 1e-3 * x).max() / 1e-3
assert worst < 1e-6, worst
print(f"python: peri {peri.version()} from {peri.library_path}: largest |u - eps x| / (eps L) = {worst:.3g}")
PY
fi
echo "PASS: install: bin/peri, libperi.a/.so, headers, peri.pc and the Python module in $prefix; a C program built with pkg-config runs a deck"
