"""Assembly of the discrete asperity system: summits -> Hertz laws and interaction operator.

docs/theory.md, eqs. T18-T21 (paper Section 4). Every summit i (height z_i above
the mean plane, radius R_i) is a Hertzian asperity::

    force              P_i = (4/3) E* R_i^1/2 delta_i^3/2
    contact stiffness  dP_i/d delta_i = 2 E* a_i,   a_i = sqrt(R_i delta_i)

and every force lowers every other asperity by ``P_j / (pi E* r_ij)`` (the pairwise operator G,
:class:`asperity.discrete.interaction.PointForceInteraction`), or, in the mean-field variant, every
asperity by ``m W / (E* sqrt A)`` (the uniform term of the improved GW theory, eq. 2).

:class:`DiscreteProblem` holds only these data and the products they define; it has no solver
state. The solver is :mod:`asperity.discrete.complementarity`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from bem.common.checks import InputTypeError, flag, non_negative, positive, supported_magnitude

from asperity.discrete.interaction import PointForceInteraction
from bem.reference import UNIFORM_SQUARE_MEAN_DEFLECTION
from asperity.gw.summits import Summits

__all__ = ["DiscreteProblem", "assemble"]


@dataclass(frozen=True, eq=False)
class DiscreteProblem:
    """The assembled discrete system (read-only).

    Attributes
    ----------
    summits : Summits
        The asperities.
    e_star : float
        Composite modulus E* [pressure].
    height, radius : ndarray
        Summit heights z_i [length] above the mean plane and radii R_i [length].
    hertz : ndarray
        ``(4/3) E* R_i^1/2`` [pressure length^1/2]: ``P_i = hertz_i delta_i^3/2``.
    operator : PointForceInteraction or None
        The pairwise interaction G (``None`` without interaction).
    uniform : float
        Uniform lowering per unit total load, ``m / (E* sqrt A)`` [length/force] (0 if off).
    """

    summits: Summits
    e_star: float
    height: np.ndarray
    radius: np.ndarray
    hertz: np.ndarray
    operator: PointForceInteraction | None
    uniform: float

    @property
    def size(self) -> int:
        """Number of asperities."""
        return int(self.height.size)

    @property
    def first_contact(self) -> float:
        """Separation of first contact, the highest summit [length]."""
        return float(self.height.max())

    @property
    def interacting(self) -> bool:
        """Whether the asperities interact at all (pairwise or uniformly)."""
        return self.operator is not None or self.uniform != 0.0

    def forces(self, delta: np.ndarray, indices: np.ndarray) -> np.ndarray:
        """Hertz forces P_i [force] at approaches delta_i [length] of ``indices``."""
        return self.hertz[indices] * delta[indices] ** 1.5

    def contact_stiffness(self, delta: np.ndarray, indices: np.ndarray) -> np.ndarray:
        """dP_i/d delta_i = 2 E* sqrt(R_i delta_i) [force/length] of ``indices``."""
        return 2.0 * self.e_star * np.sqrt(self.radius[indices] * delta[indices])

    def displacement(self, forces: np.ndarray, sources: np.ndarray, targets: np.ndarray,
                     total: float, coupling: float = 1.0) -> np.ndarray:
        """Lowering [length] at ``targets`` by ``forces`` at ``sources``: the pairwise sum
        scaled by ``coupling`` (1 except inside a continuation in the interaction strength)
        plus the uniform term ``uniform * total``."""
        u = np.zeros(targets.size)
        if self.operator is not None and sources.size and targets.size:
            u += self.operator.displacement(forces, sources=sources, targets=targets)
            if coupling != 1.0:
                u *= coupling
        if self.uniform:
            u += self.uniform * total
        return u

    def interaction_map(self, active: np.ndarray, coupling: float = 1.0
                        ) -> Callable[[np.ndarray], np.ndarray]:
        """The product by ``H = coupling G_AA + uniform 1 1^T`` on the active set."""
        kernel = self.operator.linear_map(active) if self.operator is not None else None
        uniform = self.uniform

        def apply(values: np.ndarray) -> np.ndarray:
            out = kernel(values) if kernel is not None else np.zeros_like(values)
            if coupling != 1.0:
                out *= coupling
            if uniform:
                out = out + uniform * values.sum()
            return out
        return apply

    def mean_field_coefficient(self) -> float:
        """Uniform displacement per unit load [length/force] of cold-start estimates.

        The pairwise sum averaged over asperities spread uniformly on a square of area A is
        about ``0.95 W / (E* sqrt(A))`` (the m of the improved GW theory); used only to start
        Newton's method far from first contact, never in the solution.
        """
        if self.operator is None:
            return self.uniform
        return max(0.95 / (self.e_star * math.sqrt(self.summits.area)) + self.uniform, 0.0)


def assemble(summits: Summits, *, e_star: float = 1.0, interaction: bool = True,
             m: float | None = None, method: str = "auto", local: bool = False,
             device: str = "cpu") -> DiscreteProblem:
    """Build the discrete system of ``summits`` (see :class:`asperity.DiscreteAsperityModel`
    for the parameters). Raises ``ValueError`` naming a bad parameter."""
    if not isinstance(summits, Summits):
        raise InputTypeError(f"summits must be an asperity.Summits record, got "
                         f"{type(summits).__name__}")
    if summits.count == 0:
        raise ValueError("summits must contain at least one summit")
    e_star = supported_magnitude("e_star", positive("e_star", e_star))
    interaction = flag("interaction", interaction)
    local = flag("local", local)
    if local and (not interaction or m is not None):
        raise ValueError("local (the pairwise interaction without its uniform part) needs "
                         "interaction=True and no m")
    if m is not None:
        m = non_negative("m", m)
        if interaction:
            raise ValueError("m (uniform interaction) replaces the pairwise interaction: "
                             "use it with interaction=False")
    operator = (PointForceInteraction.from_summits(summits, e_star=e_star, method=method,
                                                   device=device)
                if interaction else None)
    return DiscreteProblem(
        summits=summits, e_star=e_star, height=summits.height, radius=summits.radius,
        hertz=(4.0 / 3.0) * e_star * np.sqrt(summits.radius), operator=operator,
        uniform=(-UNIFORM_SQUARE_MEAN_DEFLECTION if local else 0.0 if m is None else m)
        / (e_star * math.sqrt(summits.area)))
