"""Greenwood-Williamson (GW) theory and the improved GW theory with uniform interaction.

Paper: Ciavarella, Greenwood & Paggi, Wear 2008, Section 2; equations in docs/theory.md, sections
"GW theory" and "Improved GW".

Conventions and units
---------------------
N = eta A summits of radius R [length] on the nominal area A [length^2]; summit heights have
mean mu_s ("mean") above the mean plane of the surface heights and standard deviation sigma
[length]. The separation d [length] is measured from the rigid plane to that mean plane, so the
reduced separation is ``h = (d - mu_s)/sigma``. E* [pressure] is the composite modulus. With
``W_ref = N E* R^(1/2) sigma^(3/2)``:

* contacts ``N F_0(h)`` (an expectation, not an integer), real area ``pi N R sigma F_1(h)``,
* load ``W = (4/3) W_ref F_3/2(h)`` (eq. 1 times A),
* stiffness ``S = -dW/dd = 2 W_ref F_1/2(h) / sigma``, conductance ``2 S / E*`` (Barber),
* leakage: the effective hydraulic aperture of the rigid gap ``max(d - z, 0)`` over Gaussian
  heights z ~ N(0, s^2), s = ``height_rms`` or else sigma (docs/theory.md, eq. L5); improved GW
  evaluates it at d1 (the paper: "d1 is a measure of the leakage").

Improved GW (eq. 2): the mean pressure lowers every summit by ``m p_nom sqrt(A) / E*``, i.e.
``m W / (E* sqrt(A))``. With the effective separation ``d1 = d + m W/(E* sqrt A)`` every
quantity is the plain GW value at d1, and the true stiffness is the series compliance
``1/S = 1/S1 + m/(E* sqrt A)`` with S1 the GW stiffness at d1. In reduced form
``h = h1 - (4/3) m C F_3/2(h1)`` with ``C = eta sqrt(A R sigma)`` (eq. 4): a strictly increasing
function of h1, solved by a bracketed monotone Newton iteration when a separation is given;
a load gives h1 directly.

The parameters both theories share, and plain GW physics at a reduced separation, live in
:mod:`asperity.gw.gw_base`.
"""

from __future__ import annotations

import math
from dataclasses import KW_ONLY, dataclass
from typing import Iterable

import numpy as np

from bem.common import checks
from numpy.typing import ArrayLike
from scipy.special import lambertw

from bem.common.curve import CURVE_QUANTITIES, ContactCurve
from bem.model import check_quantities

from asperity.gw.gw_base import _loads, _separations, _SummitHeightTheory, _warn_unconverged
from asperity.common.gw_functions import gw_integrals
from asperity.common.roots import monotone_root

__all__ = ["GreenwoodWilliamson", "ImprovedGreenwoodWilliamson"]


@dataclass(frozen=True)
class GreenwoodWilliamson(_SummitHeightTheory):
    """Greenwood-Williamson theory of independent Hertzian summits (paper eq. 1).

    Parameters
    ----------
    density : float
        Summit density eta = N/A [1/length^2].
    radius : float
        Summit radius of curvature R [length].
    sigma : float
        Standard deviation of the summit heights sigma [length] (not the rms of the surface).
    mean : float, keyword-only
        Mean summit height mu_s above the mean plane of the surface heights [length]. For
        exponential heights, the origin of the law (1/sigma) exp(-(z - mu_s)/sigma).
    e_star : float, keyword-only
        Composite modulus E* [pressure].
    area : float, keyword-only
        Nominal contact area A = L^2 [length^2].
    distribution : {"gaussian", "exponential"}, keyword-only
        Summit-height law (see :func:`asperity.gw_integral`).
    height_rms : float, optional, keyword-only
        rms of the surface heights [length], used only by ``leakage``: the rigid gap
        ``max(d - z, 0)`` with z ~ N(0, height_rms^2). Default: sigma.

    Raises
    ------
    ValueError
        density, radius, sigma, e_star or area not > 0, or of a magnitude outside
        1e-30..1e30 (:data:`bem.common.checks.SUPPORTED_MAGNITUDE`), where ``W_ref = eta A E* R^(1/2)
        sigma^(3/2)`` could overflow or underflow (rescale the units); ``|mean| > 1e30``.

    Examples
    --------
    >>> gw = GreenwoodWilliamson(density=500.0, radius=1e-4, sigma=1e-3, area=1.0)
    >>> curve = gw.at_separation([0.0, 1e-3, 2e-3])
    >>> curve.load, curve.area, curve.stiffness      # doctest: +SKIP
    """

    name = "gw"

    def at_separation(self, separation: ArrayLike, *,
                      quantities: Iterable[str] = CURVE_QUANTITIES) -> ContactCurve:
        """Contact curve at separations d [length] (any shape; +inf means out of contact).

        Returns a :class:`bem.ContactCurve` (:class:`bem.ContactModel` contract) with
        separation, load, area and mean_pressure (W/A), and, if in ``quantities``, contacts,
        stiffness (S = -dW/dd), conductance (2S/E*) and leakage (h_eff of the rigid gap at d,
        eq. L5). Extras: ``converged`` (all True).
        """
        d = _separations(separation)
        want = check_quantities(quantities)
        values = self._gw_quantities(self._reduced(d), want)
        checks.no_overflow("separation", values["load"], "the GW load (far below the summits)")
        return self._curve(d, values, want)

    def at_load(self, load: ArrayLike, *,
                quantities: Iterable[str] = CURVE_QUANTITIES) -> ContactCurve:
        """Contact curve at total loads W [force] (any shape; W = 0 gives separation +inf).

        F_3/2 is inverted in logarithmic form, so loads far below the reference
        ``W_ref = eta E* R^(1/2) sigma^(3/2) A`` (down to the smallest positive double) still
        give a finite separation. The curve's ``load`` is the requested load; extras:
        ``converged`` (bool per point).
        """
        w = _loads(load)
        want = check_quantities(quantities)
        h, converged = self._reduced_at_load(w)
        _warn_unconverged(converged, "GW load inversion")
        d = self.mean + self.sigma * h
        return self._curve(d, self._gw_quantities(h, want), want, load=w, converged=converged)


@dataclass(frozen=True)
class ImprovedGreenwoodWilliamson(_SummitHeightTheory):
    """Improved GW theory: GW plus the uniform interaction of the mean pressure (eq. 2).

    Parameters are those of :class:`GreenwoodWilliamson`, plus

    m : float, keyword-only
        Interaction factor: the mean displacement of a uniform pressure p over the compact
        nominal area is ``m p sqrt(A) / E*`` (0.96 circle, 0.95 square, 0.9464 the exact mean
        over a square; the paper takes 1). ``m = 0`` recovers GW theory.
    one_iteration : bool, keyword-only
        If true, :meth:`at_separation` uses the paper's footnote approximation: the GW
        pressure at d estimates the interaction, ``d1 = d + m W_GW(d)/(E* sqrt A)``; its load
        is W_GW(d1). The approximation loses monotonicity where ``2 m C F_1/2(h) > 1``.
        :meth:`at_load` needs no iteration (the load gives d1 directly) and is exact in both
        modes, so at_load does not invert the approximate curve. In this mode the stiffness
        is the slope of the approximate curve itself, ``S1(d1) (1 - m S_GW(d)/(E* sqrt A))``
        (negative where the approximation's load falls as d decreases).

    The curves carry extras ``effective_separation`` (d1 [length]) and ``gw_stiffness`` (S1,
    the GW stiffness dW/dd1 [force/length]); ``stiffness`` is the true dW/dd from
    ``1/S = 1/S1 + m/(E* sqrt A)``. ``leakage`` is that of GW theory's rigid gap evaluated at
    d1 instead of d (docs/theory.md, eq. L5): at equal load it equals GW's, at equal d it is
    larger.
    """

    _: KW_ONLY
    m: float = 1.0
    one_iteration: bool = False

    @property
    def name(self) -> str:
        """``"improved_gw"``, or ``"improved_gw_one_iteration"`` for the footnote's form."""
        return "improved_gw_one_iteration" if self.one_iteration else "improved_gw"

    def __post_init__(self) -> None:
        super().__post_init__()
        m = checks.non_negative("m", self.m)
        object.__setattr__(self, "m", m)
        if not isinstance(self.one_iteration, (bool, np.bool_)):
            raise ValueError(f"one_iteration must be True or False, got {self.one_iteration!r}")
        object.__setattr__(self, "one_iteration", bool(self.one_iteration))

    @property
    def greenwood_williamson(self) -> GreenwoodWilliamson:
        """The plain GW theory with the same summits (no interaction)."""
        return GreenwoodWilliamson(self.density, self.radius, self.sigma, mean=self.mean,
                                   e_star=self.e_star, area=self.area,
                                   distribution=self.distribution, height_rms=self.height_rms)

    @property
    def interaction_compliance(self) -> float:
        """m / (E* sqrt A) [length/force]: the uniform lowering per unit total load."""
        return self.m / (self.e_star * math.sqrt(self.area))

    def _improved_curve(self, separation: np.ndarray, h1: np.ndarray, load: np.ndarray | None,
                        want: frozenset[str], *, one_iteration_h: np.ndarray | None = None,
                        **extras: np.ndarray) -> ContactCurve:
        quantities = self._gw_quantities(h1, want)
        effective = self.mean + self.sigma * h1
        if "stiffness" not in quantities:
            return self._curve(separation, quantities, want, load=load,
                               gap_separation=effective, effective_separation=effective,
                               **extras)
        gw_stiffness = quantities["stiffness"]
        compliance = self.interaction_compliance
        if one_iteration_h is None:
            # exact theory: series compliance 1/S = 1/S1 + m/(E* sqrt A)
            quantities["stiffness"] = gw_stiffness / (1.0 + compliance * gw_stiffness)
        else:
            # the footnote's approximation W(d) = W_GW(d + c W_GW(d)), c = m/(E* sqrt A), has
            # its own slope: S = S1(d1) (1 - c S_GW(d)), negative where its load decreases
            at_d = self._gw_quantities(one_iteration_h, frozenset({"stiffness"}))["stiffness"]
            with np.errstate(invalid="ignore"):
                quantities["stiffness"] = gw_stiffness * (1.0 - compliance * at_d)
        return self._curve(separation, quantities, want, load=load, gap_separation=effective,
                           effective_separation=effective, gw_stiffness=gw_stiffness, **extras)

    def effective_reduced_separation(self, h: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Solve ``h = h1 - (4/3) m C F_3/2(h1)`` for h1 (exact eq. 2), elementwise.

        The right side increases strictly with h1 (slope ``1 + 2 m C F_1/2 >= 1``) and is
        concave, so Newton's iteration from the bracket's left end ``h1 = h`` rises
        monotonically to the root; the bracket is ``[h, h + (4/3) m C F_3/2(h)]``.
        Returns ``(h1, converged)``.
        """
        h = checks.separations("h", h)
        k = (4.0 / 3.0) * self.m * self.interaction_parameter
        flat = h.ravel()
        h1 = flat.copy()                                   # +inf stays +inf
        converged = np.ones(flat.shape, dtype=bool)
        finite = np.isfinite(flat)
        if k == 0 or not finite.any():
            return h1.reshape(h.shape), converged.reshape(h.shape)
        goal = flat[finite]
        if self.distribution == "exponential":
            # u = h1 - h solves u exp(u) = z, z = k Gamma(5/2) exp(-h): Lambert's W.
            h1[finite] = goal + _lambert_w_of_exp(math.log(k * math.gamma(2.5)) - goal)
            return h1.reshape(h.shape), converged.reshape(h.shape)
        (f_three_halves,) = gw_integrals((1.5,), goal)
        with np.errstate(over="ignore"):
            # Widened by 1e-9 relative (plus a few ulp) so that the first Newton step from the
            # left, which lands just below the exact bound, stays strictly inside.
            upper = goal + k * f_three_halves * (1 + 1e-9) + 1e-15 * np.maximum(1, np.abs(goal))
        if not np.all(np.isfinite(upper)):
            raise ValueError("separation is too far below the summits: the GW load overflows")

        def function(x, index):
            f_half, f_3_2 = gw_integrals((0.5, 1.5), x)
            return x - k * f_3_2 - goal[index], 1.0 + 1.5 * k * f_half

        root, ok, _ = monotone_root(function, goal, upper, goal, increasing=True)
        h1[finite] = root
        converged[finite] = ok
        return h1.reshape(h.shape), converged.reshape(h.shape)

    def at_separation(self, separation: ArrayLike, *,
                      quantities: Iterable[str] = CURVE_QUANTITIES) -> ContactCurve:
        """Contact curve at separations d [length] (eq. 2 solved exactly, or one iteration).

        Fields as :meth:`GreenwoodWilliamson.at_separation`. Extras: ``effective_separation``
        d1, ``converged`` (all True in one-iteration mode) and, when stiffness or conductance
        is asked for, ``gw_stiffness`` S1.
        """
        d = _separations(separation)
        want = check_quantities(quantities)
        h = self._reduced(d)
        if self.one_iteration:
            (f_three_halves,) = gw_integrals((1.5,), h, self.distribution)
            with np.errstate(over="ignore", invalid="ignore"):
                h1 = h + (4.0 / 3.0) * self.m * self.interaction_parameter * f_three_halves
            h1 = np.where(np.isinf(h), h, h1)
            return self._improved_curve(d, h1, None, want, one_iteration_h=h)
        h1, converged = self.effective_reduced_separation(h)
        _warn_unconverged(converged, "improved GW effective separation")
        return self._improved_curve(d, h1, None, want, converged=converged)

    def at_load(self, load: ArrayLike, *,
                quantities: Iterable[str] = CURVE_QUANTITIES) -> ContactCurve:
        """Contact curve at total loads W [force]: d1 from plain GW, then d = d1 - m W/(E* sqrt A).

        Exact in both modes (no iteration is involved). W = 0 gives separation +inf.
        Extras: ``effective_separation``, ``gw_stiffness``, ``converged``.
        """
        w = _loads(load)
        want = check_quantities(quantities)
        h1, converged = self._reduced_at_load(w)
        _warn_unconverged(converged, "GW load inversion")
        d = self.mean + self.sigma * h1 - self.interaction_compliance * w
        return self._improved_curve(d, h1, w, want, converged=converged)


def _lambert_w_of_exp(log_z: np.ndarray) -> np.ndarray:
    """W0(exp(log_z)) for real log_z, without overflow: Newton on u + ln u = log_z for large z."""
    log_z = np.asarray(log_z, dtype=float)
    out = np.empty_like(log_z)
    small = log_z < 700.0
    out[small] = lambertw(np.exp(log_z[small])).real
    if (~small).any():
        target = log_z[~small]
        u = target - np.log(target)
        for _ in range(8):                               # quadratic; 3-4 steps suffice
            u = u - (u + np.log(u) - target) / (1.0 + 1.0 / u)
        out[~small] = u
    return out
