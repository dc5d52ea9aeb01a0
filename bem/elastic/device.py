"""Where the boundary-element reference computes: the CPU (numpy) or a CUDA GPU (CuPy).

One code path serves both: the operator (:class:`bem.HalfSpace`), the preconditioner, the
constrained conjugate gradients and the stiffness solve keep their fields in the arrays of the
device's module (:func:`array_module`) and use numpy's functions on them, which CuPy's arrays
take over (numpy's ``__array_ufunc__`` and ``__array_function__`` protocols); only the arrays
they create, and the FFTs (cuFFT through :mod:`cupyx.scipy.fft`, :mod:`bem.elastic.fft_device`), are
chosen by device. Results come back to the host as numpy arrays (:func:`to_host`), so callers
and the cache see the same types from either device.

Asking for the GPU where it cannot be had is an error naming the option and what is missing
(CuPy, or a CUDA device), never a silent fall-back to the CPU.
"""

from __future__ import annotations

from types import ModuleType
from typing import Any

import numpy as np

__all__ = ["DEVICES", "array_module", "check_device", "to_host"]

#: The devices a solve can run on.
DEVICES = ("cpu", "gpu")
#: How to install CuPy for the GPU (the project's optional extra).
INSTALL_HINT = "pip install 'asperity-validation[gpu]' (CuPy for CUDA 12)"


def check_device(device: Any, name: str = "device") -> str:
    """``device`` checked: one of :data:`DEVICES`.

    Raises
    ------
    TypeError
        When it is not a string.
    ValueError
        When it is not one of :data:`DEVICES`.
    """
    if not isinstance(device, str):
        raise TypeError(f"{name} must be one of {', '.join(map(repr, DEVICES))}, got "
                        f"{type(device).__name__} {device!r}")
    if device not in DEVICES:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, DEVICES))}, got {device!r}")
    return device


def array_module(device: str, name: str = "device") -> ModuleType:
    """numpy for ``"cpu"``; CuPy for ``"gpu"``, once it is importable and sees a CUDA device.

    Raises
    ------
    ValueError
        For a device not in :data:`DEVICES`, or ``"gpu"`` without CuPy or without a CUDA
        device (the message names ``name`` and what is missing).
    """
    if check_device(device, name) == "cpu":
        return np
    try:
        import cupy
    except ImportError as error:
        raise ValueError(f"{name}='gpu' needs CuPy, which is not installed ({error}): "
                         f"{INSTALL_HINT}, or use {name}='cpu'") from None
    try:
        count = int(cupy.cuda.runtime.getDeviceCount())
    except Exception as error:   # CUDA driver or runtime missing: CuPy raises its own types
        raise ValueError(f"{name}='gpu': CuPy is installed but finds no CUDA device "
                         f"({type(error).__name__}: {error}); use {name}='cpu'") from None
    if count < 1:
        raise ValueError(f"{name}='gpu': CuPy is installed but finds no CUDA device; "
                         f"use {name}='cpu'")
    return cupy


def to_host(array: Any) -> Any:
    """A device array as a numpy array (numpy arrays and scalars unchanged)."""
    if isinstance(array, np.ndarray) or np.isscalar(array):
        return array
    get = getattr(array, "get", None)
    return get() if callable(get) else np.asarray(array)
