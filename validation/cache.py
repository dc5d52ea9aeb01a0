"""On-disk cache of expensive results (summits, BEM and discrete load paths).

An entry is a ``.npz`` file of named arrays under a key that hashes exactly the inputs that
determine it, plus the package version (a new version never reads an old result). Entries are
written to a temporary file in the same folder and renamed into place (``os.replace`` is
atomic), so a crash or a concurrent writer never leaves a half-written entry under a valid
name. An entry that cannot be read back (truncated, corrupt, or missing its checksum) is
treated as absent, deleted, and recomputed.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import pathlib
import tempfile
import zipfile
from dataclasses import asdict, is_dataclass
from typing import Any

import numpy as np

__all__ = ["Cache", "cache_key", "default_cache_dir"]

_CHECKSUM = "__checksum__"


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

    @property
    def enabled(self) -> bool:
        return self.directory is not None

    def path(self, key: str) -> pathlib.Path:
        return self.directory / f"{key}.npz"

    def load(self, key: str) -> dict[str, np.ndarray] | None:
        """The arrays stored under ``key``, or ``None`` when absent or unreadable."""
        if self.directory is None:
            return None
        path = self.path(key)
        if not path.is_file():
            return None
        try:
            with np.load(path, allow_pickle=False) as data:
                arrays = {name: data[name] for name in data.files}
            stored = str(arrays.pop(_CHECKSUM))
            if stored != _checksum(arrays):
                raise ValueError("checksum mismatch")
        except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):
            path.unlink(missing_ok=True)  # corrupt: drop it, the caller recomputes
            return None
        return arrays

    def store(self, key: str, arrays: dict[str, np.ndarray]) -> None:
        """Write ``arrays`` under ``key`` atomically."""
        if self.directory is None:
            return
        self.directory.mkdir(parents=True, exist_ok=True)
        arrays = {name: np.asarray(value) for name, value in arrays.items()}
        payload = dict(arrays)
        payload[_CHECKSUM] = np.array(_checksum(arrays))
        handle, temporary = tempfile.mkstemp(dir=self.directory, prefix=f".{key}.", suffix=".tmp")
        try:
            with os.fdopen(handle, "wb") as stream:
                np.savez(stream, **payload)
            os.replace(temporary, self.path(key))
        except BaseException:
            pathlib.Path(temporary).unlink(missing_ok=True)
            raise
