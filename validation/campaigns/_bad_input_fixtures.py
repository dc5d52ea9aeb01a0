"""The valid calls the bad-input campaign starts from (:mod:`validation.campaigns.bad_input`).

:class:`EntryPoint` (one public callable and a valid call of it) and the small inputs its rows
share: an 8 x 8 WM surface, its summits, a GW curve, three realization results. Everything is
fast enough to be called hundreds of times in the test suite. The rows themselves are in
``_bad_input_asperity``, ``_bad_input_bem`` and ``_bad_input_validation``, gathered by
:func:`validation.campaigns._bad_input_table.table`.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Any, Callable
import pathlib

import numpy as np

__all__ = ["EntryPoint"]


@dataclass(frozen=True)
class EntryPoint:
    """One public callable and a valid call of it.

    ``name`` is the exported name (``"bem.solve_contact"``, ``"asperity.Summits"``) or, for a
    method, ``"Class.method"``; a variant of the same callable adds a parenthesised note
    (``"bem.solve_contact(separation)"``). ``call(**arguments())`` must succeed.

    ``scalars`` maps a parameter to its domain: ``"real"``, ``"positive"``,
    ``"non_negative"`` or ``"integer"`` (a seed is an ``"integer"``); ``"choice"`` (a name such
    as an FFT backend), ``"object"`` (one of the project's objects, a collection of them, or a
    path) or ``"callable"`` (a callback): no value of
    :data:`validation.campaigns.bad_input.BAD_SCALARS` is valid for these three; ``"text"``
    (any string is valid, nothing else) or ``"path"`` (a folder or file to write: strings and
    ``os.PathLike`` are valid, and not tried); plus the word ``"optional"`` when ``None`` is a valid
    value. ``arrays`` maps an array parameter to ``""`` or to words among ``"optional"`` (None
    is valid), ``"inf"`` (+inf entries are valid, e.g. a separation out of contact), ``"nan"``
    (NaN entries are valid, e.g. an error not computed) and ``"mask"`` (booleans are valid: a
    contact map).
    """

    name: str
    call: Callable[..., Any]
    arguments: Callable[[], dict]
    scalars: dict = field(default_factory=dict)
    arrays: dict = field(default_factory=dict)


N = 8
SPACING = 1.0 / N
#: The shipped example map (a Gwyddion ASCII export that states its size and unit).
EXAMPLE = str(pathlib.Path(__file__).resolve().parents[2] / "examples" / "example_topography.txt")


@functools.lru_cache(maxsize=1)
def surface() -> np.ndarray:
    """An 8 x 8 WM height map (read-only, built once)."""
    from validation.surfaces.wm import wm_surface

    heights = wm_surface(N, D=2.3, rms_slope=0.1, seed=1)
    heights.setflags(write=False)
    return heights


def points():
    """Three spot or summit positions x, y."""
    return dict(x=np.array([0.0, 1.0, 2.0]), y=np.array([0.0, 0.0, 1.0]))


def gw(**extra):
    """Arguments of a GW-type theory: density, radius, sigma, plus ``extra``."""
    return dict(density=50.0, radius=0.05, sigma=0.01, **extra)


def curve():
    """A GW contact curve at two loads."""
    from asperity import GreenwoodWilliamson

    return GreenwoodWilliamson(**gw()).at_load(np.array([1e-4, 1e-3]))


@functools.lru_cache(maxsize=1)
def summits():
    """The summits of :func:`surface` (built once)."""
    from asperity import find_summits

    return find_summits(surface(), SPACING)


def realizations() -> list:
    """Three duck-typed realization results (a BEM-labelled reference and a GW curve); the
    reference carries its own per-point error estimates, as a BEM run with
    ``error_estimate=True`` does (without them its band is NaN, "not estimated", by design).
    Three, the fewest with a per-surface tolerance interval (fewer leave it NaN, by design)."""
    from dataclasses import replace
    from types import SimpleNamespace

    model = curve()
    estimates = {f"{name}_error": 0.01 * np.abs(getattr(model, name))
                 for name in ("area", "separation", "load")}
    reference = replace(model, extras={**model.extras, **estimates})
    task = SimpleNamespace(seed=0, surface=SimpleNamespace(L=1.0, sweep_name="D"),
                           quantities=("area", "separation"), sweep_value=2.3)
    return [SimpleNamespace(task=task, curves={"bem": reference, "gw": model}, sigma=0.01)] * 3


def theories(model, load=(1e-4, 1e-3), separation=(0.0, 0.01)):
    """A GW-type theory evaluated along both paths (the parameters meet at the evaluation)."""
    def call(**parameters):
        theory = model(**parameters)
        return theory.at_load(np.array(load)), theory.at_separation(np.array(separation))
    return call


def validity_range_call(**arguments):
    """``validation.validity_range``, its points and total."""
    from validation import validity_range

    found = validity_range(**arguments)   # NaN bounds mean "holds nowhere", by design
    return found.points, found.total


