"""On-disk cache of expensive results (summits, BEM and discrete load paths).

An entry is a ``.npz`` file of named arrays under a key that hashes exactly the inputs that
determine it, plus the package version (a new version never reads an old result). Entries are
written to a temporary file in the same folder and renamed into place (``os.replace`` is
atomic), so a crash or a concurrent writer never leaves a half-written entry under a valid
name. Every entry records its own key and a checksum of its arrays; an entry that cannot be
read back (truncated, corrupt, missing its checksum, stored under another entry's name, or
rejected by the caller's decoder because an array is missing) is treated as absent, deleted,
and recomputed. Temporary files left by a killed writer are removed once they are an hour old
(a younger one may belong to a writer still at work). Failing to *write* an entry warns
(:class:`CacheWarning`) and never stops a computation: the cache only saves time.

What keys and entries of the runner's results hold is here too: the source version every key
includes (:func:`source_version`), a contact curve as named arrays and back
(:func:`curve_arrays`, :func:`curve_from_arrays`) and whether a path entry holds the stiffness
solves (:func:`needs_stiffness`) and its leakage (:func:`needs_leakage`), and what every model
is asked for (:func:`model_quantities`).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import pathlib
import shutil
import tempfile
import threading
import time
import warnings
import zipfile
from dataclasses import asdict, is_dataclass
from typing import Any, Callable, TypeVar

import numpy as np

from bem.common.curve import CURVE_QUANTITIES, ContactCurve

__all__ = ["Cache", "CacheWarning", "REPORT_ONLY_MODULES", "cache_key", "check_directory",
           "curve_arrays", "curve_from_arrays", "default_cache_dir", "model_quantities",
           "needs_leakage", "needs_stiffness",
           "report_version", "source_version"]

_CHECKSUM = "__checksum__"
_KEY = "__key__"
#: Age [s] after which a temporary file is taken to be left by a killed writer.
STALE_SECONDS = 3600.0
# numpy reads an archive member's header with ``ast.literal_eval``; CPython 3.11 keeps the AST
# constructor's recursion depth in state shared by all threads, so two threads of one process
# reading at once (the models computed beside the reference) can fail with "SystemError: AST
# constructor recursion depth mismatch" (python/cpython#106905). Reads take turns.
_READING = threading.Lock()
#: What a broken entry or a decoder of one may raise: all mean "recompute".
_UNREADABLE = (OSError, ValueError, KeyError, IndexError, TypeError, EOFError,
               zipfile.BadZipFile)

T = TypeVar("T")


class CacheWarning(UserWarning):
    """A cache entry could not be written (the result is still returned)."""


def check_directory(path: str | os.PathLike, what: str) -> pathlib.Path:
    """Create ``path`` if needed and check that files can be written in it.

    Raises
    ------
    ValueError
        Naming ``what`` and the reason (a file in the way, no permission, a read-only or
        virtual file system), so that a command fails before any computing starts.
    """
    path = pathlib.Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=path, prefix=".write-check-"):
            pass
    except (OSError, ValueError) as error:
        reason = error.strerror if isinstance(error, OSError) and error.strerror else str(error)
        raise ValueError(f"{what} {str(path)!r} is not a writable directory: {reason}") from None
    return path


def default_cache_dir() -> pathlib.Path:
    """``$XDG_CACHE_HOME/asperity-validation`` (``~/.cache/asperity-validation`` by default)."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return pathlib.Path(base) / "asperity-validation"


def _canonical(value: Any) -> Any:
    """A JSON-ready, order-independent form of the inputs; floats kept exactly (repr)."""
    if is_dataclass(value) and not isinstance(value, type):
        return _canonical(asdict(value))
    if isinstance(value, dict):
        return {str(k): _canonical(v) for k, v in sorted(value.items())}
    if isinstance(value, (list, tuple)):
        return [_canonical(v) for v in value]
    if isinstance(value, np.ndarray):
        return {"array": hashlib.sha256(np.ascontiguousarray(value).tobytes()).hexdigest(),
                "shape": list(value.shape), "dtype": str(value.dtype)}
    if isinstance(value, (bool, type(None), str)):
        return value
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        value = float(value)
        return repr(value) if math.isfinite(value) else str(value)
    raise TypeError(f"cannot use {type(value).__name__} in a cache key")


def cache_key(kind: str, version: str, **inputs: Any) -> str:
    """Hash of the result kind, the package version and the inputs (sha256, hex)."""
    text = json.dumps({"kind": kind, "version": version, "inputs": _canonical(inputs)},
                      sort_keys=True, separators=(",", ":"))
    return f"{kind}-{hashlib.sha256(text.encode()).hexdigest()[:32]}"


def _checksum(arrays: dict[str, np.ndarray]) -> str:
    digest = hashlib.sha256()
    for name in sorted(arrays):
        array = np.ascontiguousarray(arrays[name])
        digest.update(name.encode())
        digest.update(str(array.dtype).encode())
        digest.update(str(array.shape).encode())
        digest.update(array.tobytes())
    return digest.hexdigest()


class Cache:
    """A folder of cache entries; ``Cache(None)`` caches nothing.

    Parameters
    ----------
    directory : path or None
        Where entries live (created on first write). ``None`` disables the cache.
    """

    def __init__(self, directory: str | os.PathLike | None) -> None:
        self.directory = None if directory is None else pathlib.Path(directory)
        if self.directory is not None:
            self.clean()

    @property
    def enabled(self) -> bool:
        return self.directory is not None

    def path(self, key: str) -> pathlib.Path:
        return self.directory / f"{key}.npz"

    def clean(self, max_age: float = STALE_SECONDS) -> int:
        """Remove temporary files older than ``max_age`` seconds; returns how many."""
        if self.directory is None or not self.directory.is_dir():
            return 0
        removed = 0
        now = time.time()
        for temporary in self.directory.glob(".*.tmp"):
            try:
                if now - temporary.stat().st_mtime > max_age:
                    temporary.unlink()
                    removed += 1
            except OSError:
                continue          # taken by another cleaner, or not ours to remove
        return removed

    def _discard(self, path: pathlib.Path) -> None:
        try:
            if path.is_dir() and not path.is_symlink():
                shutil.rmtree(path)
            else:
                path.unlink(missing_ok=True)
        except OSError:
            pass                  # the next store() reports what is in the way

    def load(self, key: str, decode: Callable[[dict[str, np.ndarray]], T] | None = None
             ) -> dict[str, np.ndarray] | T | None:
        """The arrays stored under ``key`` (passed through ``decode`` when given), or ``None``
        when absent or unreadable.

        An entry is unreadable when it is not a valid ``.npz`` file, its checksum does not
        match, it records another key, or ``decode`` raises (an array it needs is missing or
        malformed); such an entry is deleted so that the caller recomputes and replaces it.
        """
        if self.directory is None:
            return None
        path = self.path(key)
        if not path.exists():
            return None
        try:
            with _READING, np.load(path, allow_pickle=False) as data:
                arrays = {name: data[name] for name in data.files}
            stored = str(arrays.pop(_CHECKSUM))
            if stored != _checksum(arrays):
                raise ValueError("checksum mismatch")
            if str(arrays.pop(_KEY)) != key:
                raise ValueError("entry stored under another key")
            return arrays if decode is None else decode(arrays)
        except _UNREADABLE:
            self._discard(path)  # corrupt or foreign: drop it, the caller recomputes
            return None

    def store(self, key: str, arrays: dict[str, np.ndarray]) -> None:
        """Write ``arrays`` under ``key`` atomically (a :class:`CacheWarning` if impossible)."""
        if self.directory is None:
            return
        arrays = {name: np.asarray(value) for name, value in arrays.items()}
        payload = dict(arrays)
        payload[_KEY] = np.array(key)
        payload[_CHECKSUM] = np.array(_checksum(payload))
        temporary = None
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
            if self.path(key).is_dir():
                self._discard(self.path(key))
            handle, temporary = tempfile.mkstemp(dir=self.directory, prefix=f".{key}.",
                                                 suffix=".tmp")
            with os.fdopen(handle, "wb") as stream:
                np.savez(stream, **payload)
            os.replace(temporary, self.path(key))
        except OSError as error:
            if temporary is not None:
                pathlib.Path(temporary).unlink(missing_ok=True)
            warnings.warn(f"cache entry {key} not written to {self.directory}: {error}",
                          CacheWarning, stacklevel=2)
        except BaseException:
            if temporary is not None:
                pathlib.Path(temporary).unlink(missing_ok=True)
            raise


# --------------------------------------------------------------------------------------------
# what the runner's entries hold

_SOURCE_VERSION: str | None = None
#: Modules that only read results (comparison, verdicts, findings, figures, tables, command
#: line, how many realizations run, the error atlas's design, fit and prediction, the surface
#: descriptors): editing them leaves every cached result valid, so they are
#: not part of its hash. Paths relative to the ``validation`` folder.
REPORT_ONLY_MODULES = frozenset({"__main__.py", "cli.py", "judge/analysis.py", "judge/compare.py",
                                 "run/cost.py", "report/figures.py", "judge/findings.py",
                                 "common/labels.py", "run/progress.py", "report/write.py", "report/folder.py",
                                 "report/sections.py", "report/tables.py", "judge/verdicts.py",
                                 "judge/tolerance.py", "run/sequential.py", "judge/sampling.py",
                                 "report/sampling.py", "judge/sealing.py",
                                 "report/sealing_figures.py", "judge/errors.py",
                                 "report/layout.py", "judge/decide.py", "common/verdicts.py",
                                 "judge/headline.py", "judge/frames.py", "judge/bands.py",
                                 "report/front.py", "report/summary.py", "judge/claims.py",
                                 "report/atlas.py", "check/__init__.py", "check/command.py",
                                 "check/figure.py", "check/physical.py", "check/request.py",
                                 "check/resolution.py", "check/units.py", "check/glance.py",
                                 "check/frames.py", "check/library.py", "check/result.py",
                                 "check/plausible.py", "check/scan_input.py",
                                 "report/conventions.py", "surfaces/descriptors.py",
                                 "atlas/__init__.py", "atlas/build.py", "atlas/command.py",
                                 "atlas/design.py", "atlas/fit.py", "atlas/model.py",
                                 "atlas/predict.py", "atlas/report.py"})


def report_version() -> str:
    """A hash of the modules :data:`REPORT_ONLY_MODULES` names (the drawing and writing code
    that :func:`source_version` leaves out): a figure cached by one state of the drawing code
    is never read back by another."""
    global _REPORT_VERSION
    if _REPORT_VERSION is None:
        root = pathlib.Path(__file__).resolve().parents[1]
        _REPORT_VERSION = _sources_digest((name, root / name) for name in sorted(REPORT_ONLY_MODULES)
                                          if (root / name).is_file())
    return _REPORT_VERSION


def _sources_digest(files) -> str:
    """16 hex digits of a hash of ``(name, path)`` pairs: each name and its file's bytes."""
    digest = hashlib.sha256()
    for name, path in files:
        digest.update(name.encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


_REPORT_VERSION: str | None = None


def source_version() -> str:
    """Package version plus a hash of the three packages' sources: results cached by one state
    of the code are never read back by another (a fixed bug does not survive in the cache)."""
    global _SOURCE_VERSION
    if _SOURCE_VERSION is None:
        from validation._version import __version__

        root = pathlib.Path(__file__).resolve().parents[2]
        files = ((path.relative_to(root / package).as_posix(), path)
                 for package in ("asperity", "bem", "validation")
                 for path in sorted((root / package).rglob("*.py")))
        _SOURCE_VERSION = f"{__version__}+" + _sources_digest(
            (name, path) for name, path in files
            if not (path.is_relative_to(root / "validation") and name in REPORT_ONLY_MODULES))
    return _SOURCE_VERSION


def curve_arrays(curve: ContactCurve) -> dict[str, np.ndarray]:
    """A contact curve as named arrays for :meth:`Cache.store` (its per-point numeric extras
    as ``extra:<name>``)."""
    arrays = {name: getattr(curve, name) for name in CURVE_QUANTITIES
              if getattr(curve, name) is not None}
    arrays["nominal_area"] = np.array(curve.nominal_area)
    arrays["e_star"] = np.array(curve.e_star)
    for name, value in curve.extras.items():
        value = np.asarray(value)
        if value.ndim == 1 and value.shape == curve.load.shape and value.dtype.kind in "fiub":
            arrays[f"extra:{name}"] = value
    return arrays


def curve_from_arrays(arrays: dict[str, np.ndarray]) -> ContactCurve:
    """The contact curve of :func:`curve_arrays` (a decoder for :meth:`Cache.load`)."""
    kwargs = {name: arrays[name] for name in CURVE_QUANTITIES if name in arrays}
    extras = {name[6:]: value for name, value in arrays.items() if name.startswith("extra:")}
    return ContactCurve(nominal_area=float(arrays["nominal_area"]), e_star=float(arrays["e_star"]),
                        extras=extras, **kwargs)


def needs_stiffness(quantities) -> bool:
    """Whether a path is solved with its stiffness (asked for by stiffness or conductance); the
    cache keys hold this flag, not the quantity list, so either name reuses the same solves."""
    return "stiffness" in quantities or "conductance" in quantities


def needs_leakage(quantities) -> bool:
    """Whether a path is solved with its leakage (the BEM's Reynolds solves on its gaps); the
    cache keys hold this flag too."""
    return "leakage" in quantities


def model_quantities(quantities) -> tuple[str, ...]:
    """What every model of a task is asked for, from the scene's quantities: the load path,
    area and contact counts always (counts are cheap); stiffness and conductance when either
    is asked for (one stiffness solve gives both); leakage only when asked for."""
    return (("area", "load", "separation", "contacts")
            + (("stiffness", "conductance") if needs_stiffness(quantities) else ())
            + (("leakage",) if needs_leakage(quantities) else ()))
