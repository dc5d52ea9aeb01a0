"""A call run in a background daemon thread, its result or its exception read later.

For work that releases the GIL (FFTs, sparse factorisations, dense products) done beside the
caller's own: the call starts at once, :meth:`BackgroundCall.result` waits for it and returns
its value or re-raises its exception in the caller's thread. The thread is a daemon, so a
caller interrupted by Ctrl-C exits without waiting for it.
"""

from __future__ import annotations

import threading
from typing import Any, Callable

__all__ = ["BackgroundCall", "running"]

_lock = threading.Lock()
_running = 0


def running() -> int:
    """Background calls of this process running now (each keeps a core busy, e.g. the models
    a realization computes beside its reference: :func:`bem.elastic.fft_threads.fft_threads` leaves
    their cores to them)."""
    return _running


class BackgroundCall(threading.Thread):
    """``function(*arguments)`` in a daemon thread, started at construction.

    Parameters
    ----------
    function : callable
        What to run.
    *arguments
        Its positional arguments.
    name : str
        The thread's name.
    """

    def __init__(self, function: Callable[..., Any], *arguments, name: str = "background"):
        if not callable(function):
            raise TypeError(f"function must be callable, got {type(function).__name__}")
        super().__init__(name=str(name), daemon=True)
        self._call = (function, arguments)
        self._value: Any = None
        self._error: BaseException | None = None
        global _running
        with _lock:   # counted from now on, not from when the thread gets scheduled
            _running += 1
        try:
            self.start()
        except BaseException:
            with _lock:
                _running -= 1
            raise

    def run(self) -> None:
        global _running
        function, arguments = self._call
        try:
            self._value = function(*arguments)
        except BaseException as error:   # re-raised in the caller's thread by result()
            self._error = error
        finally:
            with _lock:
                _running -= 1

    def result(self) -> Any:
        """The call's value, once it has returned; its exception re-raised if it raised."""
        self.join()
        if self._error is not None:
            raise self._error
        return self._value
