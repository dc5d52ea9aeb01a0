"""Persson's distribution of interfacial gaps and the leakage it predicts (docs/theory.md, eq. L6).

After Almqvist, Campana, Prodanov & Persson (2011) and Dapp, Lucke, Persson & Muser (2012).
Magnification q (the roughness resolved up to wavevector q) loses contact gradually: the
contact fraction seen at q is ``a(q) = erf(p0 / (E* sqrt(pi m(q))))`` (P3 with the cumulative
moment m(q) instead of m(q_1)). The area ``-da`` that falls out of contact between q and q + dq
is given a gap distributed as a normal law folded at 0 (the density of ``|X|``), X ~ N(u_q, h_q^2):

* h_q^2 = 2 pi integral_q^{q_1} q' C dq', the variance of the roughness not yet resolved at q;
* u_q, the mean gap (P5) of that unresolved roughness (m measured from q) under the mean
  pressure ``p0 / a(q)`` of the area still in contact at q.

The area in contact at full resolution, a(q_1) (the area of eq. P3), is a weight at gap 0::

    P(g) = a(q_1) delta(g) + integral_{a(q_1)}^{1} da [N(g; u_q, h_q) + N(-g; u_q, h_q)]   (L6)

Quadrature: Gauss-Legendre in the area lost, da (``magnifications`` nodes, through
``erfc`` so that heavy loads keep their digits); for u_q the substitution
``tau^2 = m(q') - m(q)`` of eq. (P7) with Gauss-Legendre panels uniform in ln tau. The mixture
of folded normal laws is then binned on gaps, geometric bins near 0 (where the effective medium
decides whether a channel still conducts near the percolation threshold) and equal bins above;
each bin carries its exact probability at its conditional mean gap. (A Gauss-Hermite rule per
normal law resolves the small gaps too coarsely: its leakage near percolation still moved by
10 % from 64 to 96 nodes.) The leakage is the effective-medium aperture (L2) of
these samples (:func:`asperity.common.leakage.effective_medium_aperture`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.polynomial import legendre
from numpy.typing import ArrayLike
from scipy import special

from bem.common.checks import integer, points

from asperity.common.leakage import (BRUGGEMAN_CRITICAL_AREA, effective_medium_aperture,
                              two_phase_aperture)
from asperity.spectral.persson_kernel import separation_kernel

__all__ = ["GapDistribution", "gap_distribution", "persson_leakage"]

_PANEL_NODES, _PANEL_WEIGHTS = legendre.leggauss(8)
_PANELS = 32                      # uniform panels in ln tau for u_q (within 1e-6 of eq. P5)
_DECAY = 50.0                     # start where the kernel is below exp(-50) of its peak


@dataclass(frozen=True, eq=False)
class GapDistribution:
    """Samples of Persson's gap distribution (L6) at n nominal pressures.

    Attributes
    ----------
    gaps : ndarray, shape (n, M)
        Gap samples g >= 0 [length].
    weights : ndarray, shape (n, M)
        Their probabilities; each row adds up to ``1 - contact_fraction``.
    contact_fraction : ndarray, shape (n,)
        a(q_1), the weight at g = 0 (the relative contact area of eq. P3).
    """

    gaps: np.ndarray
    weights: np.ndarray
    contact_fraction: np.ndarray

    @property
    def mean(self) -> np.ndarray:
        """integral g P(g) dg [length] per pressure (contact counted as gap 0)."""
        return np.sum(self.gaps * self.weights, axis=1)

    def aperture(self, critical_area: float = BRUGGEMAN_CRITICAL_AREA) -> np.ndarray:
        """Effective hydraulic aperture h_eff [length] per pressure, eq. (L2)."""
        return effective_medium_aperture(self.gaps, self.weights,
                                         contact_fraction=self.contact_fraction,
                                         critical_area=critical_area)


def _unresolved_mean_gap(model: Any, start: np.ndarray, c: np.ndarray) -> np.ndarray:
    """u_q [length]: eq. (P7) for the roughness above the magnification whose cumulative
    moment is ``start`` (1-D), with ``c = p / (sqrt(pi) E*)`` (1-D, > 0)."""
    spectrum = model.spectrum
    top = np.sqrt(np.maximum(spectrum.moment(3) - start, 0.0))
    out = np.zeros(start.shape)
    live = top > 0
    top, c, start = top[live], c[live], start[live]
    log_low = np.log(c) - 0.5 * np.log((c / top) ** 2 + _DECAY)
    edges = log_low[:, None] + (np.log(top) - log_low)[:, None] * np.linspace(0, 1, _PANELS + 1)
    left, width = edges[:, :-1, None], np.diff(edges, axis=1)[:, :, None]
    tau = np.exp(left + 0.5 * width * (_PANEL_NODES + 1.0))
    weight = 0.5 * width * _PANEL_WEIGHTS * tau
    q = spectrum.wavevector_at_fourth_moment(start[:, None, None] + tau * tau)
    kernel = separation_kernel(c[:, None, None] / tau, model.gamma)
    out[live] = 2.0 * np.sum(weight * kernel / q, axis=(1, 2))
    return out


def _bins(top: np.ndarray, fine: int) -> np.ndarray:
    """Bin edges [length] per row (n, B + 1): [0, 1e-9 top], then geometric to top/20 with
    ``fine`` bins per e-fold, then 200 equal bins to ``top``."""
    geometric = np.exp(np.linspace(math.log(1e-9), math.log(0.05), int(17.7 * fine) + 1))
    relative = np.concatenate(([0.0], geometric, np.linspace(0.05, 1.0, 201)[1:]))
    return top[:, None] * relative


def _folded_normal_bins(edges: np.ndarray, centre: np.ndarray, spread: np.ndarray
                        ) -> tuple[np.ndarray, np.ndarray]:
    """Probability and first moment of ``|X|``, X ~ N(centre, spread^2), in each bin: edges
    (n, B + 1), centre and spread (n, J) -> two arrays (n, J, B)."""
    edge = edges[:, None, :]
    mu, h = centre[:, :, None], np.maximum(spread, 1e-300)[:, :, None]
    mass = np.zeros(edge.shape[:1] + centre.shape[1:] + (edges.shape[1] - 1,))
    moment = np.zeros_like(mass)
    for sign in (1.0, -1.0):              # the law and its mirror image in 0
        z = (edge - sign * mu) / h
        cdf, pdf = special.ndtr(z), np.exp(-0.5 * z * z) / math.sqrt(2.0 * math.pi)
        part = np.diff(cdf, axis=-1)
        mass += part
        moment += sign * mu * part - h * np.diff(pdf, axis=-1)
    return mass, moment


def gap_distribution(model: Any, pressure: ArrayLike, *, magnifications: int = 32,
                     fine: int = 10) -> GapDistribution:
    """Persson's gap distribution (L6) at nominal pressures 0 < p0 [pressure] (1-D).

    Parameters
    ----------
    model : Persson
        The theory (spectrum, E*, gamma).
    pressure : array_like
        Nominal pressures p0 = W/A, finite and > 0 [pressure].
    magnifications : int
        Gauss-Legendre nodes in the area lost (>= 2).
    fine : int
        Gap bins per e-fold between 1e-9 and 0.05 of the largest gap (>= 1); 200 equal bins
        above. Each bin is one sample: its exact probability under (L6) and, as its gap, the
        conditional mean. The defaults change the leakage by less than 1e-3 relative when
        doubled (tests/test_leakage_theory.py).
    """
    if not all(hasattr(model, name) for name in ("spectrum", "gamma", "e_star", "mean_gap")):
        raise TypeError(f"model must be a Persson theory, got {type(model).__name__}")
    p = points("pressure", pressure).ravel()
    if np.any(p <= 0):
        raise ValueError("pressure must be > 0 (zero pressure: the gap is infinite)")
    count = integer("magnifications", magnifications, minimum=2)
    fine = integer("fine", fine, minimum=1)
    x_a, w_a = legendre.leggauss(count)
    spectrum = model.spectrum
    m_top = spectrum.moment(3)
    c0 = p / (math.sqrt(math.pi) * model.e_star)
    open_fraction = special.erfc(c0 / math.sqrt(m_top))          # 1 - a(q_1)
    # the area lost, 1 - a, at Gauss-Legendre nodes of (0, 1 - a(q_1))
    lost = open_fraction[:, None] * 0.5 * (x_a + 1.0)
    weight_a = open_fraction[:, None] * 0.5 * w_a
    area = 1.0 - lost                                            # a(q) at those magnifications
    with np.errstate(divide="ignore"):
        tau = c0[:, None] / special.erfcinv(lost)                # a(q) = erf(c0 / tau)
    start = np.minimum(tau * tau, m_top)                         # m(q)
    q = spectrum.wavevector_at_fourth_moment(start)
    variance = 2.0 * math.pi * (spectrum.moment(1) - spectrum.cumulative_moment(1, q))
    spread = np.sqrt(np.maximum(variance, 0.0))
    centre = _unresolved_mean_gap(model, start.ravel(), (c0[:, None] / area).ravel())
    centre = centre.reshape(start.shape)
    edges = _bins(np.max(centre + 9.0 * spread, axis=1), fine)
    mass, moment = _folded_normal_bins(edges, centre, spread)
    weights = np.einsum("nj,njb->nb", weight_a, mass)
    first = np.einsum("nj,njb->nb", weight_a, moment)
    middle = 0.5 * (edges[:, 1:] + edges[:, :-1])
    with np.errstate(divide="ignore", invalid="ignore"):
        gaps = np.where(weights > 0, np.clip(first / weights, edges[:, :-1], edges[:, 1:]),
                        middle)
    return GapDistribution(gaps, weights, 1.0 - open_fraction)


def persson_leakage(model: Any, pressure: ArrayLike, mean_gap: ArrayLike | None = None,
                    *, critical_area: float = BRUGGEMAN_CRITICAL_AREA) -> dict[str, np.ndarray]:
    """Leakage predictions of Persson's theory at nominal pressures p0 >= 0 (any shape).

    Returns ``{"leakage": h_eff, "leakage_two_phase": ...}`` [length], arrays of the shape of
    ``pressure``: ``leakage`` is the effective-medium aperture (L2) of the gap distribution
    (L6), +inf at p0 = 0 and 0 from the full-contact pressure of the model on;
    ``leakage_two_phase`` is the closed form (L4) from Persson's mean gap ``mean_gap`` (P5;
    computed when not given) and contact area (P3).
    """
    p = points("pressure", pressure, non_negative=True, allow_infinity=True)
    flat = p.ravel()
    full_contact = model._pressure_range[1]
    inside = (flat > 0) & (flat < full_contact)
    leakage = np.where(flat == 0, np.inf, 0.0)
    if inside.any():
        leakage[inside] = gap_distribution(model, flat[inside]).aperture(critical_area)
    u = (model.mean_gap(p) if mean_gap is None
         else points("mean_gap", mean_gap, non_negative=True, allow_infinity=True))
    area = special.erf(np.minimum(flat, full_contact)
                       / (math.sqrt(math.pi) * model.e_star * math.sqrt(model.spectrum.moment(3))))
    two_phase = np.where(flat == 0, np.inf, 0.0)
    two_phase[inside] = two_phase_aperture(np.ravel(u)[inside], area[inside],
                                           critical_area=critical_area)
    return {"leakage": leakage.reshape(p.shape), "leakage_two_phase": two_phase.reshape(p.shape)}
