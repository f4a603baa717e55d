"""peri from Python: build a simulation from a deck (a YAML file or a dict), run it or step
it, and read its node fields and history as NumPy arrays (docs/python.md).

    import peri
    with peri.Simulation("examples/quickstart.yaml",
                         overrides={"solver.end_time": 20e-6}, output="out") as sim:
        sim.step(100)                 # 100 time steps (load steps for a quasi-static solver)
        u = sim.field("displacement")  # (nodes, 3)
        sim.run()                     # to the end
        print(sim.history()["mean_damage"][-1], sim.field("damage").mean())

The module is a thin layer over libperi's C API (include/peri/api.h) through ctypes: a run
is the run of `peri run DECK --quiet` and writes the same files. A bad deck raises DeckError
with the program's message (file:line:column: error: ...), a failure during the run
RunError; nothing exits the interpreter (except running out of memory).
"""
import ctypes

import numpy as np

from . import _capi
from ._yaml import dump as deck_to_yaml, flow as _flow

__all__ = ["Simulation", "History", "Error", "DeckError", "RunError", "deck_to_yaml", "field_names",
           "version", "library_path", "set_threads"]

library_path = _capi.library_path
_lib = _capi.lib


class Error(Exception):
    """An error reported by peri: `status` is the program's exit status (1 a failure during
    the run, 2 bad input) and `messages` the lines the program would have printed."""

    def __init__(self, status, messages):
        self.status = status
        self.messages = messages
        super().__init__(messages)


class DeckError(Error, ValueError):
    """Bad input (status 2): the deck, an override, a field name, a call out of order."""


class RunError(Error, RuntimeError):
    """A failure during the run (status 1): divergence, output that cannot be written."""


def _check(status):
    if status == 0:
        return
    messages = _lib.peri_api_last_error().decode("utf-8", "replace")
    raise (DeckError if status == 2 else RunError)(status, messages)


def version():
    """The version of libperi, e.g. '0.1.0'."""
    return _lib.peri_api_version().decode()


def field_names():
    """The names Simulation.field accepts."""
    names, k = [], 0
    while True:
        name = _lib.peri_api_field_name(k)
        if name is None:
            return names
        names.append(name.decode())
        k += 1


def set_threads(threads):
    """OpenMP threads of later runs of this thread (the program's --threads)."""
    _lib.peri_api_set_threads(int(threads))


def _override_strings(overrides):
    """--set KEY=VALUE strings from a dict {"key.path": value} or a list of "key=value"."""
    if overrides is None:
        return []
    if isinstance(overrides, dict):
        return [f"{key}={_flow(value)}" for key, value in overrides.items()]
    if isinstance(overrides, str):
        return [overrides]
    return [str(item) for item in overrides]


class History:
    """The rows of history.csv as a NumPy array: `array` (rows x columns), `columns` (the
    header's names); history["name"] is one column, len(history) the number of rows."""

    def __init__(self, columns, array):
        self.columns = list(columns)
        self.array = array

    def __getitem__(self, name):
        try:
            return self.array[:, self.columns.index(name)]
        except ValueError:
            raise KeyError(f"history has no column '{name}' (columns: {', '.join(self.columns)})") from None

    def __contains__(self, name):
        return name in self.columns

    def __len__(self):
        return self.array.shape[0]

    def as_dict(self):
        """{column: 1D array}."""
        return {name: self.array[:, k] for k, name in enumerate(self.columns)}

    def __repr__(self):
        return f"History({len(self)} rows: {', '.join(self.columns)})"


class Simulation:
    """A simulation built from a deck.

    deck       a path to a YAML deck, or a dict with the deck's structure
    overrides  values to change first, as the program's --set: a dict {"key.path": value}
               ({"discretization.spacing": 1e-3, "boundary_conditions.0.y": "1e6 * t"}) or
               a list of "key.path=value" strings
    output     the output directory (the program's --output); default: output.directory
    quiet      no summary and no progress line (default True)
    threads    OpenMP threads (default: OMP_NUM_THREADS or all cores)
    restart    a checkpoint to continue from (the program's --restart)
    name       for a dict deck, the name its messages give it (default "<dict>")

    Errors in the deck raise DeckError here, before any work.
    """

    def __init__(self, deck, overrides=None, output=None, quiet=True, threads=None, restart=None, name=None):
        self._handle = None
        sets = [s.encode() for s in _override_strings(overrides)]
        array = (ctypes.c_char_p * max(len(sets), 1))(*sets)
        handle = ctypes.c_void_p()
        if isinstance(deck, dict):
            self.deck_text = deck_to_yaml(deck)
            _check(_lib.peri_api_open_string(self.deck_text.encode(), (name or "<dict>").encode(), len(sets),
                                             array, ctypes.byref(handle)))
        else:
            path = str(deck)
            try:
                with open(path, encoding="utf-8", errors="replace") as f:
                    self.deck_text = f.read()
            except OSError:
                self.deck_text = None  # peri says why below, as the program would
            _check(_lib.peri_api_open_deck(path.encode(), len(sets), array, ctypes.byref(handle)))
        self._handle = handle
        if threads is not None:
            set_threads(threads)
        if output is not None:
            _check(_lib.peri_api_set_output(self._handle, str(output).encode()))
        _check(_lib.peri_api_set_quiet(self._handle, 1 if quiet else 0))
        if restart is not None:
            _check(_lib.peri_api_set_restart(self._handle, str(restart).encode()))

    # ---- running --------------------------------------------------------------------

    def _h(self):
        if self._handle is None:
            raise DeckError(2, "peri: error: the simulation is closed")
        return self._handle

    def start(self):
        """Starts the run (output directory, first frame and history row); step, run, field and
        history do it when needed."""
        _check(_lib.peri_api_start(self._h()))
        return self

    def step(self, n=1):
        """Runs n time steps (n load steps for a quasi-static solver), or to the end if fewer are
        left. Stepping n then m steps gives the state of n + m steps bit for bit."""
        _check(_lib.peri_api_step(self._h(), int(n)))
        return self

    def run(self):
        """Runs to the end; the picture and plot are written as the program writes them."""
        _check(_lib.peri_api_run(self._h()))
        return self

    def close(self):
        """Finishes a run stopped midway (picture, plot) and frees the simulation."""
        if self._handle is not None:
            handle, self._handle = self._handle, None
            _check(_lib.peri_api_close(handle))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __del__(self):
        try:
            if self._handle is not None:
                _lib.peri_api_close(self._handle)
                self._handle = None
        except Exception:
            pass

    # ---- state ----------------------------------------------------------------------

    @property
    def step_index(self):
        """The steps (load steps) done."""
        return _lib.peri_api_step_index(self._h())

    @property
    def steps(self):
        """The steps (load steps) of the whole run."""
        return _lib.peri_api_steps(self._h())

    @property
    def time(self):
        return _lib.peri_api_time(self._h())

    @property
    def dimension(self):
        return _lib.peri_api_dimension(self._h())

    @property
    def nodes(self):
        """The number of nodes (this rank's, under MPI)."""
        return _lib.peri_api_nodes(self._h())

    @property
    def quasi_static(self):
        return bool(_lib.peri_api_is_quasi_static(self._h()))

    @property
    def finished(self):
        """Whether the run has reached its end (or stopped at an error)."""
        return bool(_lib.peri_api_finished(self._h()))

    # ---- fields and history -----------------------------------------------------------

    def field(self, name):
        """A node field at the current state, as a new NumPy array: (nodes,) for a scalar,
        (nodes, 3) for a vector (3 components in every dimension), (nodes, 3, 3) for stress and
        strain; int32 for material and block. Names: field_names()."""
        data = ctypes.POINTER(ctypes.c_double)()
        idata = ctypes.POINTER(ctypes.c_int32)()
        ncomp = ctypes.c_int()
        _check(_lib.peri_api_field(self._h(), str(name).encode(), ctypes.byref(data), ctypes.byref(idata),
                                   ctypes.byref(ncomp)))
        n, c = self.nodes, ncomp.value
        if n == 0:
            values = np.zeros(n * c, dtype=np.int32 if idata else np.float64)
        else:
            values = np.ctypeslib.as_array(idata if idata else data, shape=(n * c,)).copy()
        if c == 1:
            return values
        return values.reshape((n, 3, 3) if c == 9 else (n, c))

    @property
    def fields(self):
        """The names field() accepts."""
        return field_names()

    @property
    def positions(self):
        """Current positions x + u, (nodes, 3)."""
        return self.field("position")

    @property
    def displacement(self):
        return self.field("displacement")

    @property
    def velocity(self):
        return self.field("velocity")

    @property
    def force(self):
        """Internal force density, (nodes, 3)."""
        return self.field("force")

    @property
    def damage(self):
        """Damage index, (nodes,)."""
        return self.field("damage")

    def history(self):
        """The rows of history.csv recorded so far (full precision), as a History."""
        rows = ctypes.POINTER(ctypes.c_double)()
        n_rows = ctypes.c_long()
        n_columns = ctypes.c_int()
        _check(_lib.peri_api_history(self._h(), ctypes.byref(rows), ctypes.byref(n_rows), ctypes.byref(n_columns)))
        r, c = n_rows.value, n_columns.value
        columns = [_lib.peri_api_history_column(self._h(), k).decode() for k in range(c)]
        if r == 0 or c == 0:
            return History(columns, np.zeros((r, c)))
        return History(columns, np.ctypeslib.as_array(rows, shape=(r * c,)).copy().reshape(r, c))

    def __repr__(self):
        state = "closed" if self._handle is None else f"step {self.step_index}/{self.steps}, t = {self.time:g} s"
        return f"<peri.Simulation {state}>"
