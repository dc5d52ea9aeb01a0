"""Load paths: solve points in the order of increasing load, each warm-started from the last.

One stepper for every model that solves a path of loads or separations: the points are visited
in the order of increasing load (increasing loads, or decreasing separations), each solved by
``step(previous, target)`` from the previous point's answer, and returned in the caller's order.

The discrete asperity model walks its paths with it (:mod:`asperity.discrete.path`);
:func:`bem.contact_curve` still has its own copy of the same loop (sorted order, each point
started from the previous one's coarse-grid or fine pressure) until its rewrite can call
:func:`follow_path`.
"""

from __future__ import annotations

from typing import Callable, TypeVar

import numpy as np

__all__ = ["follow_path", "path_order"]

State = TypeVar("State")


def path_order(targets: np.ndarray, *, control: str) -> np.ndarray:
    """Indices visiting ``targets`` from light to heavy contact: increasing loads
    (``control="load"``) or decreasing separations (``control="separation"``); stable."""
    if control == "load":
        return np.argsort(targets, kind="stable")
    if control == "separation":
        return np.argsort(-targets, kind="stable")
    raise ValueError(f"control must be 'load' or 'separation', got {control!r}")


def follow_path(targets: np.ndarray, start: State, step: Callable[[State, float], State], *,
                control: str) -> list[State]:
    """Solve a 1-D array of targets as a warm-started path.

    Parameters
    ----------
    targets : ndarray
        Loads [force] or separations [length], any order.
    start : object
        The state before the lightest point (e.g. the solution at first contact).
    step : callable
        ``step(previous_state, target) -> state``.
    control : {"load", "separation"}
        What the targets are.

    Returns
    -------
    list
        The state of every target, in the caller's order.
    """
    results: list = [None] * targets.size
    state = start
    for index in path_order(targets, control=control):
        state = step(state, float(targets[index]))
        results[index] = state
    return results
