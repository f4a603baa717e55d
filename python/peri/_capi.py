"""libperi through ctypes: finding the shared library and declaring the C API
(include/peri/api.h)."""
import ctypes
import ctypes.util
import os

_HERE = os.path.dirname(os.path.abspath(__file__))


def _candidates():
    """Where libperi.so may be, most specific first."""
    explicit = os.environ.get("PERI_LIBRARY")
    if explicit:
        yield explicit
        return
    try:  # written by `make install`: the library's folder relative to this package
        from . import _installed
        yield os.path.normpath(os.path.join(_HERE, _installed.LIBRARY))
    except ImportError:
        pass
    # a source checkout: python/peri next to the build folder
    yield os.path.normpath(os.path.join(_HERE, "..", "..", "build", "libperi.so"))
    found = ctypes.util.find_library("peri")
    if found:
        yield found


def _load():
    tried = []
    for path in _candidates():
        if os.path.sep in path and not os.path.exists(path):
            tried.append(path)
            continue
        try:
            return ctypes.CDLL(path, mode=ctypes.RTLD_GLOBAL), path
        except OSError as error:
            tried.append(f"{path} ({error})")
    raise ImportError("peri: cannot find libperi.so; build it (make build) or install it (make install), "
                      "or point PERI_LIBRARY at it. Tried: " + "; ".join(tried))


lib, library_path = _load()

_handle = ctypes.c_void_p
_status = ctypes.c_int
_strings = ctypes.POINTER(ctypes.c_char_p)


def _declare(name, restype, *argtypes):
    function = getattr(lib, name)
    function.restype = restype
    function.argtypes = list(argtypes)


_declare("peri_api_version", ctypes.c_char_p)
_declare("peri_api_last_error", ctypes.c_char_p)
_declare("peri_api_open_deck", _status, ctypes.c_char_p, ctypes.c_int, _strings, ctypes.POINTER(_handle))
_declare("peri_api_open_string", _status, ctypes.c_char_p, ctypes.c_char_p, ctypes.c_int, _strings,
         ctypes.POINTER(_handle))
_declare("peri_api_set_output", _status, _handle, ctypes.c_char_p)
_declare("peri_api_set_quiet", _status, _handle, ctypes.c_int)
_declare("peri_api_set_restart", _status, _handle, ctypes.c_char_p)
_declare("peri_api_set_threads", None, ctypes.c_int)
_declare("peri_api_start", _status, _handle)
_declare("peri_api_step", _status, _handle, ctypes.c_long)
_declare("peri_api_run", _status, _handle)
_declare("peri_api_step_index", ctypes.c_long, _handle)
_declare("peri_api_steps", ctypes.c_long, _handle)
_declare("peri_api_time", ctypes.c_double, _handle)
_declare("peri_api_dimension", ctypes.c_int, _handle)
_declare("peri_api_nodes", ctypes.c_long, _handle)
_declare("peri_api_is_quasi_static", ctypes.c_int, _handle)
_declare("peri_api_finished", ctypes.c_int, _handle)
_declare("peri_api_field_name", ctypes.c_char_p, ctypes.c_int)
_declare("peri_api_field", _status, _handle, ctypes.c_char_p, ctypes.POINTER(ctypes.POINTER(ctypes.c_double)),
         ctypes.POINTER(ctypes.POINTER(ctypes.c_int32)), ctypes.POINTER(ctypes.c_int))
_declare("peri_api_history", _status, _handle, ctypes.POINTER(ctypes.POINTER(ctypes.c_double)),
         ctypes.POINTER(ctypes.c_long), ctypes.POINTER(ctypes.c_int))
_declare("peri_api_history_column", ctypes.c_char_p, _handle, ctypes.c_int)
_declare("peri_api_close", _status, _handle)
