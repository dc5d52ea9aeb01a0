"""A stand-in for CuPy on the CPU, to run the GPU code path of :mod:`bem` where no GPU is.

Its arrays hold numpy arrays but behave as CuPy's do towards numpy: numpy's functions and ufuncs
take them over (``__array_function__``, ``__array_ufunc__``) and return arrays of the double,
and an implicit conversion to a numpy array (``np.asarray``) raises ``TypeError`` as CuPy does.
So a host conversion that would fail or silently copy on a GPU fails here, and an array the
GPU path creates with numpy instead of the device module shows up as a numpy array mixed
with the double's. Only :func:`to_host` (the array's ``get``) brings values back.
"""

from __future__ import annotations

import types

import numpy as np
import scipy.fft
from numpy.lib.mixins import NDArrayOperatorsMixin

def _unwrap(value):
    if isinstance(value, DeviceArray):
        return value.data
    if isinstance(value, (list, tuple)):
        return type(value)(_unwrap(v) for v in value)
    if isinstance(value, dict):
        return {k: _unwrap(v) for k, v in value.items()}
    return value


def _wrap(value):
    if isinstance(value, np.ndarray):
        return DeviceArray(value)
    if isinstance(value, tuple):
        return tuple(_wrap(v) for v in value)
    if isinstance(value, list):
        return [_wrap(v) for v in value]
    return value


class DeviceArray(NDArrayOperatorsMixin):
    """An array "on the device": numpy data behind the protocols CuPy implements."""

    __slots__ = ("data",)

    def __init__(self, data: np.ndarray) -> None:
        if isinstance(data, DeviceArray):
            raise TypeError("nested device array")
        self.data = data

    # -- numpy's protocols -----------------------------------------------------------------
    def __array__(self, dtype=None, copy=None):
        raise TypeError("Implicit conversion to a NumPy array is not allowed (device_double); "
                        "use .get()")

    def __array_ufunc__(self, ufunc, method, *inputs, **kwargs):
        out = kwargs.get("out")
        if out is not None:
            for item in out:
                if not isinstance(item, DeviceArray):
                    raise TypeError("a ufunc writes a host array from a device array")
        for item in inputs:
            if isinstance(item, np.ndarray) and item.ndim > 0:
                raise TypeError(f"{ufunc.__name__}: a host array mixed with a device array")
        result = getattr(ufunc, method)(*_unwrap(inputs), **_unwrap(kwargs))
        if out is not None:
            return out[0] if len(out) == 1 else out
        return _wrap(result)

    def __array_function__(self, func, types_, args, kwargs):
        for item in list(args) + list(kwargs.values()):
            if isinstance(item, np.ndarray) and item.ndim > 0:
                raise TypeError(f"{func.__name__}: a host array mixed with a device array")
        return _wrap(func(*_unwrap(args), **_unwrap(kwargs)))

    # -- the ndarray API the solver uses ----------------------------------------------------
    def __getitem__(self, key):
        return _wrap(self.data[_unwrap(key)])

    def __setitem__(self, key, value):
        if isinstance(value, np.ndarray) and value.ndim > 0:
            raise TypeError("a host array assigned into a device array")
        self.data[_unwrap(key)] = _unwrap(value)

    def __len__(self):
        return len(self.data)

    def __float__(self):
        return float(self.data)

    def __int__(self):
        return int(self.data)

    def __bool__(self):
        return bool(self.data)

    def __repr__(self):
        return f"DeviceArray({self.data!r})"

    shape = property(lambda self: self.data.shape)
    size = property(lambda self: self.data.size)
    ndim = property(lambda self: self.data.ndim)
    dtype = property(lambda self: self.data.dtype)
    real = property(lambda self: _wrap(self.data.real))
    flags = property(lambda self: types.SimpleNamespace(
        c_contiguous=self.data.flags.c_contiguous, owndata=self.data.flags.owndata))

    def get(self):
        return self.data.copy()

    def __getattr__(self, name):
        # methods (reshape, view, copy, fill, sum, mean, max, any, astype, ...) on the data,
        # their array results kept on the device
        attribute = getattr(self.data, name)
        if not callable(attribute):
            raise AttributeError(name)

        def method(*args, **kwargs):
            return _wrap(attribute(*_unwrap(args), **_unwrap(kwargs)))
        return method


# -- the module's functions (those of CuPy the bem package calls) ------------------------------
float64, complex128 = np.float64, np.complex128


def asarray(value, dtype=None):
    if isinstance(value, DeviceArray):
        return value if dtype is None else DeviceArray(value.data.astype(dtype))
    return DeviceArray(np.array(value, dtype=dtype, copy=True))


def _creator(name):
    function = getattr(np, name)
    return lambda *args, **kwargs: DeviceArray(function(*_unwrap(args), **_unwrap(kwargs)))


zeros, empty, full, ones = (_creator(n) for n in ("zeros", "empty", "full", "ones"))
ascontiguousarray = _creator("ascontiguousarray")


def _fft(name):
    function = getattr(scipy.fft, name)
    return lambda *args, **kwargs: DeviceArray(function(*_unwrap(args), **_unwrap(kwargs)))


scipy_fft = types.SimpleNamespace(**{n: _fft(n) for n in ("rfft2", "irfft2", "dctn")})
