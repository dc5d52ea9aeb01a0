"""FFTW wisdom kept between processes, so that a new process does not plan its FFTs again.

Planning a transform with ``FFTW_MEASURE`` times candidate algorithms (0.2-1 s per plan here, six
plans for the grids of one load path); FFTW keeps what it learnt ("wisdom") for the rest of the
process, and this module keeps it in a file: read before the first plan of a process, written
after every plan that taught FFTW something new (merged with what other processes wrote
meanwhile, replaced atomically). Wisdom is per machine: the file name holds the host name and
the architecture.

The file is ``fftw-wisdom-<host>-<machine>.json`` in the folder ``$ASPERITY_FFTW_WISDOM`` when
that is set (an empty value keeps no wisdom), else in ``$XDG_CACHE_HOME/asperity-validation``
(by default ``~/.cache/asperity-validation``, the report's cache folder; ``python -m validation
report`` keeps it in its ``--cache`` folder, and none with ``--no-cache``). A missing,
unreadable or corrupt file only means planning again.
"""

from __future__ import annotations

import json
import os
import pathlib
import platform
import tempfile



def _import_pyfftw():
    """pyFFTW, or None where it is not installed (it is optional at run time).

    Its ``interfaces`` package imports ``dask.array`` when dask is installed (for its dask
    interface, which this package does not use): a second of every start-up. That import is
    kept out while pyFFTW loads, by a ``None`` entry for ``dask.array.fft`` in ``sys.modules``
    (which makes that one import fail, as pyFFTW allows), removed again at once: dask itself,
    and pyFFTW's dask interface imported later by its name, work as before.
    """
    import sys

    blocked = "dask.array.fft" not in sys.modules
    if blocked:
        sys.modules["dask.array.fft"] = None
    try:
        import pyfftw
    except ImportError:  # pragma: no cover - exercised by a subprocess test
        return None
    finally:
        if blocked and "dask.array.fft" in sys.modules and sys.modules["dask.array.fft"] is None:
            del sys.modules["dask.array.fft"]
    return pyfftw


pyfftw = _import_pyfftw()

__all__ = ["WISDOM_VARIABLE", "wisdom_file", "load_wisdom", "save_wisdom"]

#: Environment variable naming the folder of the wisdom file ("" for none).
WISDOM_VARIABLE = "ASPERITY_FFTW_WISDOM"

_state = {"loaded_from": None, "saved": None}


def wisdom_file() -> pathlib.Path | None:
    """The wisdom file of this machine, or None when none is kept (module docstring)."""
    folder = os.environ.get(WISDOM_VARIABLE)
    if folder is None:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        folder = os.path.join(base, "asperity-validation")
    elif not folder.strip():
        return None
    name = f"fftw-wisdom-{platform.node() or 'host'}-{platform.machine() or 'cpu'}.json"
    return pathlib.Path(folder) / name


def _read(path: pathlib.Path) -> bool:
    """Import the wisdom of ``path`` into FFTW; whether anything was imported."""
    try:
        strings = json.loads(path.read_text(encoding="ascii"))
        return bool(any(pyfftw.import_wisdom(tuple(s.encode("ascii") for s in strings))))
    except (OSError, ValueError, TypeError, AttributeError, UnicodeError):
        return False


def load_wisdom() -> None:
    """Import the wisdom file once per process and file (before the first plan)."""
    path = wisdom_file()
    if pyfftw is None or path is None or _state["loaded_from"] == path:
        return
    _state["loaded_from"] = path
    _read(path)
    _state["saved"] = pyfftw.export_wisdom()


def save_wisdom() -> None:
    """Write FFTW's wisdom to the wisdom file if it grew since the last write (after a plan).

    What other processes wrote meanwhile is imported first, so the file keeps both; the write
    is atomic (a temporary file renamed over the old one). Write errors are ignored.
    """
    path = wisdom_file()
    if pyfftw is None or path is None or pyfftw.export_wisdom() == _state["saved"]:
        return
    _read(path)
    wisdom = pyfftw.export_wisdom()
    _state["saved"] = wisdom
    temporary = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(prefix=".wisdom-", dir=path.parent)
        with os.fdopen(handle, "w", encoding="ascii") as stream:
            json.dump([w.decode("ascii") for w in wisdom], stream)
        os.replace(temporary, path)
    except OSError:
        if temporary is not None:
            pathlib.Path(temporary).unlink(missing_ok=True)
