"""Summits as plain named arrays and back, for caches that store arrays
(:meth:`asperity.Summits.to_arrays` and :meth:`~asperity.Summits.from_arrays` as functions)."""

from __future__ import annotations

import numpy as np

from asperity.gw.summits import Summits
from bem.common import checks

__all__ = ["summits_from_arrays", "summits_to_arrays"]


def summits_to_arrays(summits: Summits) -> dict[str, np.ndarray]:
    """:meth:`Summits.to_arrays` as a function (for caches that store plain arrays)."""
    if not isinstance(summits, Summits):
        raise checks.InputTypeError(f"summits must be an asperity.Summits, got "
                                    f"{type(summits).__name__}")
    return summits.to_arrays()


def summits_from_arrays(arrays) -> Summits:
    """:meth:`Summits.from_arrays` as a function."""
    return Summits.from_arrays(arrays)
