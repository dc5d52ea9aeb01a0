"""Theory scenes: GW against improved GW in the paper's reduced variables (Figs. 1-3).

No surface is generated: the curves come straight from :func:`asperity.interaction_curves`.
"""

from __future__ import annotations

import numpy as np

from validation.scenes.scene import TheorySpec

__all__ = ["theory_curves"]


def theory_curves(spec: TheorySpec) -> dict:
    """Curves of Figs. 1-3 for every C of the scene.

    Returns
    -------
    dict
        ``{"C": (C values), "m": m, C: asperity.InteractionCurves, ...}``.
    """
    from asperity import interaction_curves

    separation = np.linspace(spec.separation_min, spec.separation_max, spec.count)
    out: dict = {"C": spec.C, "m": spec.m}
    for C in spec.C:
        out[C] = interaction_curves(C, m=spec.m, separation=separation)
    return out
