"""Persson's theory of contact between randomly rough surfaces, as a model of the project.

Equations (P1)-(P9) are those of docs/theory.md, section 7 (Persson 2001, J. Chem. Phys. 115,
3840; Persson 2007, Phys. Rev. Lett. 99, 125502; Yang & Persson 2008, J. Phys.: Condens.
Matter 20, 215214; Campana, Persson & Muser 2011, J. Phys.: Condens. Matter 23, 085001).

Conventions and units
---------------------
The spectrum C(q) [length^4] follows eq. (P1) (``asperity.spectral.spectrum``). E* [pressure] is the
project's composite modulus, which is Persson's E/(1 - nu^2) for a rigid counter-surface.
Loads are total forces W [force] on the nominal area A = L^2, p0 = W/A. The curve's
``separation`` is Persson's mean gap u-bar [length]: the average distance between the rigid
plane and the *deformed* surface, also given as ``extras["mean_gap"]``. It is to be compared
with the BEM's mean gap, not with the far-field separation d of the asperity models: for the
project's non-periodic half-space the two differ by the mean elastic displacement.

With ``m(q) = integral_{q_L}^q q'^3 C dq'``, ``w(q) = (pi m(q))^(-1/2)`` and
``x = w(q) p / E*``:

* area, eq. (P3): ``A_real/A = erf(p0 / (2 sqrt G))``, ``G = (pi/4) E*^2 m(q_1)
  = E*^2 h'_rms^2 / 8``, i.e. ``erf(x(q_1))``;
* mean gap, eq. (P5): ``u(p) = sqrt(pi) integral dq q^2 C w I(x)`` with the kernel
  ``I(x0) = integral_{x0}^inf (dx/x) [gamma + 3 (1 - gamma) erf(x)^2] exp(-x^2)`` (P6);
* stiffness, eq. (P8): ``S = A (-dp/du)``, ``-du/dp = (sqrt(pi)/p) integral dq q^2 C w g(x)``,
  ``g(x) = [gamma + 3 (1 - gamma) erf(x)^2] exp(-x^2)``; conductance ``2 S / E*`` (P9).

Numerics
--------
The substitution ``m = tau^2`` turns ``q^2 C w dq`` into ``2 dtau / (sqrt(pi) q(tau))`` and
removes the square-root singularity of w at q_L (P7): ``u = 2 integral_0^T I(c/tau) dtau /
q(tau)`` with ``c = p/(sqrt(pi) E*)`` and ``T = sqrt(m(q_1))``. ``q(tau)`` is a closed form on
each piece of the piecewise power-law spectrum. The tau integral is Gauss-Legendre in ln tau
on panels bounded by the pieces' ends and a grid of ln tau between
``tau_lo = c/sqrt(x_T^2 + 50)`` (the integrand is below exp(-50) of its peak under it) and T,
uniform over the top 46 e-folds; agreement with independent quadrature to 1e-12 relative is
tested in tests/test_persson.py (observed ~1e-15). The kernel I is
``(gamma/2) E1(x^2) + 3 (1 - gamma) J(x)``; ``J(x) = integral_x^inf erf^2 exp(-t^2) dt/t`` is a
Chebyshev interpolant of its logarithm on [0, 4] and ``E1(x^2)/2 - R(x)`` above, the small R
by Gauss-Laguerre.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Iterable
from dataclasses import KW_ONLY, dataclass
from functools import cached_property

import numpy as np
from numpy.polynomial import legendre
from numpy.typing import ArrayLike
from scipy import special

from asperity.spectral.persson_kernel import (YANG_PERSSON_GAMMA, _separation_kernel, _stiffness_kernel,
                                     separation_kernel)
from asperity.common.roots import monotone_root
from asperity.spectral.spectrum import IsotropicSpectrum, radial_power_spectrum
from bem.common.checks import integer, points, positive, real_array, real_number
from bem.common.curve import ContactCurve
from bem.model import check_quantities
from bem.common.warnings import ConvergenceWarning

__all__ = ["PERSSON_QUANTITIES", "YANG_PERSSON_GAMMA", "Persson", "separation_kernel"]

#: Quantities :class:`Persson` can compute (``contacts`` is not predicted by the theory).
PERSSON_QUANTITIES = ("separation", "load", "area", "stiffness", "conductance",
                      "mean_pressure", "leakage")

_DECAY = 50.0                     # integrate while the kernel exceeds exp(-50) of its peak
_FULL_CONTACT = 25.0              # x_T = p/(sqrt(pi) E* T) beyond which u and 1/S underflow
_FLOOR = 1e-250                   # smallest pressure integrated, in units of sqrt(pi) E* T
_GRID_PANELS = 48                 # uniform panels in ln tau, besides the spectrum's pieces
_FINE_RANGE = 46.0                # ... over at most this many e-folds below T
_NODES, _WEIGHTS = legendre.leggauss(12)


def _quantity_names(quantities: Iterable[str] | None) -> frozenset[str]:
    """The quantities asked for (all by default); "contacts" is accepted and left None."""
    return check_quantities(PERSSON_QUANTITIES if quantities is None else quantities,
                            PERSSON_QUANTITIES + ("contacts",))


@dataclass(frozen=True, eq=False)
class Persson:
    """Persson's contact theory for a surface of given isotropic PSD (eqs. P3-P9).

    Parameters
    ----------
    spectrum : IsotropicSpectrum
        C(q) on [q_L, q_1] [length^4], convention eq. (P1).
    nominal_area : float
        A = L^2 [length^2].
    e_star : float, keyword-only
        Composite modulus E* [pressure].
    gamma : float, keyword-only
        Correction factor of Yang & Persson (2008) in the mean-gap relation (P5), in (0, 1];
        default 0.42 (the value used with this correction in later comparisons, e.g. Almqvist
        et al. 2011; see docs/theory.md); 1 gives Persson (2007). The area (P3) does
        not use it.

    Examples
    --------
    >>> model = Persson.from_spectrum([1.0, 100.0], [1e-6, 1e-14], 1.0, e_star=1.0)
    >>> model.at_load([1e-4, 1e-3]).area                 # doctest: +SKIP
    """

    spectrum: IsotropicSpectrum
    nominal_area: float
    _: KW_ONLY
    e_star: float = 1.0
    gamma: float = YANG_PERSSON_GAMMA

    def __post_init__(self) -> None:
        if not isinstance(self.spectrum, IsotropicSpectrum):
            raise TypeError(f"spectrum must be an IsotropicSpectrum, got {self.spectrum!r}")
        object.__setattr__(self, "nominal_area", positive("nominal_area", self.nominal_area))
        object.__setattr__(self, "e_star", positive("e_star", self.e_star))
        gamma = real_number("gamma", self.gamma, minimum=0.0, exclusive=True)
        if gamma > 1.0:
            raise ValueError(f"gamma must be in (0, 1], got {self.gamma!r}")
        object.__setattr__(self, "gamma", gamma)

    @property
    def name(self) -> str:
        """Short identifier of the model (:class:`bem.ContactModel`)."""
        return "persson"

    # constructors ---------------------------------------------------------------------------
    @classmethod
    def from_spectrum(cls, wavevector: ArrayLike, psd: ArrayLike | Callable, nominal_area: float,
                      *, e_star: float = 1.0, gamma: float = YANG_PERSSON_GAMMA,
                      samples: int = 257) -> Persson:
        """From samples of C(q) (piecewise power law through them), or a callable C(q).

        For a callable, ``wavevector`` is ``(q_L, q_1)`` and C is sampled at ``samples``
        log-spaced points; exact for power laws, otherwise interpolation error O(dln q^2).
        """
        samples = integer("samples", samples, minimum=2)
        if callable(psd):
            q_bounds = real_array("wavevector", wavevector).ravel()
            if q_bounds.size != 2:
                raise ValueError("wavevector must be (q_L, q_1) when psd is a callable")
            q = np.geomspace(positive("q_L", q_bounds[0]), positive("q_1", q_bounds[1]),
                             samples)
            psd = real_array("psd(wavevector)", psd(q), finite=False)
            wavevector = q
        return cls(IsotropicSpectrum(wavevector, psd), nominal_area, e_star=e_star, gamma=gamma)

    @classmethod
    def from_heights(cls, heights: ArrayLike, spacing: float, *, e_star: float = 1.0,
                     gamma: float = YANG_PERSSON_GAMMA, window: str = "hann") -> Persson:
        """From a height map: radially averaged 2-D PSD (``asperity.spectral.spectrum``, eq. P1).

        The nominal area is the map's area, ``N_x N_y spacing^2``.
        """
        spectrum = radial_power_spectrum(heights, spacing, window=window)
        shape = np.shape(heights)
        return cls(spectrum, shape[0] * shape[1] * float(spacing) ** 2, e_star=e_star,
                   gamma=gamma)

    # integrals ------------------------------------------------------------------------------
    @property
    def _top(self) -> float:
        """T = sqrt(m(q_1)) [-]."""
        return math.sqrt(self.spectrum.moment(3))

    def _nodes(self, c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Gauss nodes tau (shape (n, k)) and weights (dtau, same shape) for each c > 0."""
        top = self._top
        x_top = c / top
        log_low = np.log(c) - 0.5 * np.log(x_top**2 + _DECAY)
        log_top = math.log(top)
        # 48 panels over the top 46 e-folds of tau (all of [tau_lo, T] unless the load is
        # below ~1e-20 E* h'_rms), 8 below them, where tau (the weight in ln tau) is e^-46
        # times smaller than at T
        split = np.maximum(log_low, log_top - _FINE_RANGE)
        fine = split[:, None] + (log_top - split)[:, None] * np.linspace(0, 1, _GRID_PANELS + 1)
        coarse = log_low[:, None] + (split - log_low)[:, None] * np.linspace(0, 1, 9)[:-1]
        grid = np.concatenate((coarse, fine), axis=1)
        pieces = 0.5 * np.log(self.spectrum.cumulative_fourth_moment()[1:-1])
        pieces = np.clip(pieces[None, :], log_low[:, None], log_top)
        edges = np.sort(np.concatenate((grid, pieces), axis=1), axis=1)
        left, width = edges[:, :-1, None], np.diff(edges, axis=1)[:, :, None]
        log_tau = left + 0.5 * width * (_NODES + 1.0)
        tau = np.exp(log_tau)
        return tau.reshape(c.size, -1), (0.5 * width * _WEIGHTS * tau).reshape(c.size, -1)

    def _integrals(self, pressure: np.ndarray, *, gap: bool, slope: bool,
                   chunk: int = 32) -> tuple[np.ndarray | None, np.ndarray | None]:
        """u(p) (P5) and -du/dp (P8) for pressures 0 < p < inf (1-D)."""
        u = np.empty(pressure.size) if gap else None
        du = np.empty(pressure.size) if slope else None
        for start in range(0, pressure.size, chunk):
            p = pressure[start:start + chunk]
            c = p / (math.sqrt(math.pi) * self.e_star)
            tau, weight = self._nodes(c)
            # panels of zero width (pieces of the spectrum outside [tau_lo, T]) drop out
            row, column = np.nonzero(weight)
            tau, weight = tau[row, column], weight[row, column]
            weight = 2.0 * weight / self.spectrum.wavevector_at_fourth_moment(tau * tau)
            x = c[row] / tau
            if gap:
                u[start:start + chunk] = np.bincount(
                    row, weight * _separation_kernel(x, self.gamma), minlength=p.size)
            if slope:
                du[start:start + chunk] = np.bincount(
                    row, weight * _stiffness_kernel(x, self.gamma), minlength=p.size) / p
        return u, du

    def mean_gap(self, pressure: ArrayLike) -> np.ndarray:
        """u(p0) [length], eq. (P5); +inf at p0 = 0, 0 at p0 = +inf."""
        p = points("pressure", pressure, non_negative=True, allow_infinity=True)
        out = np.where(p == 0, np.inf, 0.0)
        inside = (p > 0) & (p < self._pressure_range[1])
        out[inside] = self._integrals(p[inside], gap=True, slope=False)[0]
        return out

    # the contact-model contract -------------------------------------------------------------
    def at_load(self, load: ArrayLike, *, quantities: Iterable[str] | None = None
                ) -> ContactCurve:
        """Contact curve at total loads W [force] (any shape; W = 0 gives mean gap +inf).

        ``separation`` is the mean gap u-bar (P5); area (P3); stiffness S = -dW/du-bar (P8);
        conductance 2 S / E* (P9); mean_pressure W/A; leakage, the effective-medium aperture of
        Persson's gap distribution (docs/theory.md, eqs. L2 and L6), with the extra
        ``leakage_two_phase`` (eq. L4). ``contacts`` is None (not predicted).
        Extras: ``mean_gap`` (= separation), ``converged`` (all True).

        ``quantities`` (names from :data:`PERSSON_QUANTITIES`; "contacts" is accepted and left
        None): separation, load, area and mean_pressure are always returned, as by every model
        of the project; stiffness and conductance (one more integral) only when asked for.
        Loads above ``17.7 E* h'_rms A`` (x_T > 25) give mean gap 0 and infinite stiffness: the
        gap underflows in double precision. Loads must be finite and >= 0 (``ValueError``).
        """
        w = points("load", load, non_negative=True)
        return self._curve(w / self.nominal_area, w, None, _quantity_names(quantities))

    def at_separation(self, separation: ArrayLike, *,
                      quantities: Iterable[str] | None = None) -> ContactCurve:
        """Contact curve at mean gaps u-bar [length] (> 0; +inf means no load; 0 full contact).

        Inverts the decreasing u(p) (P5) by Newton's method on ln u against ln p inside a
        bracket; ``extras["converged"]`` says where it met the tolerance.
        """
        u = points("separation", separation, non_negative=True, allow_infinity=True)
        pressure, converged = self._invert(u.ravel())
        pressure = pressure.reshape(u.shape)
        if not np.all(converged):
            failed = np.size(converged) - np.count_nonzero(converged)
            warnings.warn(f"Persson mean-gap inversion: {failed} of {np.size(converged)} points "
                          "did not converge (mean gap below the full-contact underflow)",
                          ConvergenceWarning, stacklevel=2)
        return self._curve(pressure, pressure * self.nominal_area, u,
                           _quantity_names(quantities), converged.reshape(u.shape))

    # internals --------------------------------------------------------------------------------
    @property
    def _pressure_range(self) -> tuple[float, float]:
        """Pressures between which u(p) is a positive double: (floor, full contact)."""
        scale = math.sqrt(math.pi) * self.e_star * self._top
        return _FLOOR * scale, _FULL_CONTACT * scale

    @cached_property
    def _gap_table(self) -> tuple[np.ndarray, np.ndarray]:
        """(ln p, ln u) on 80 pressures from the floor to full contact, u decreasing."""
        floor, ceiling = self._pressure_range
        pressure = np.concatenate((np.geomspace(floor, 1e-6 * ceiling, 16, endpoint=False),
                                   np.geomspace(1e-6 * ceiling, ceiling, 64)))
        u = self._integrals(pressure, gap=True, slope=False)[0]
        return np.log(pressure), np.log(u)

    def _invert(self, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pressures p with u(p) = target (1-D): bracketed Newton on ln u against ln p, started
        from a table of u(p) and bracketed by its neighbouring entries."""
        pressure = np.where(target == 0, np.inf, 0.0)
        converged = np.ones(target.shape, dtype=bool)
        log_p, log_u = self._gap_table
        with np.errstate(divide="ignore"):
            goal_all = np.log(target)
        # above u(floor) the load is below the double range (0); at or below u(ceiling) it is
        # the full-contact pressure, where u(p) underflows: flagged as not converged
        pressure[(goal_all >= log_u[0]) & np.isfinite(target)] = 0.0
        high = (target > 0) & (goal_all <= log_u[-1])
        pressure[high], converged[high] = math.exp(log_p[-1]), False
        inside = (goal_all < log_u[0]) & (goal_all > log_u[-1])
        if not inside.any():
            return pressure, converged
        goal = goal_all[inside]
        right = np.searchsorted(-log_u, -goal)          # log_u[right - 1] > goal >= log_u[right]
        lower, upper = log_p[right - 1], log_p[right]
        fraction = (log_u[right - 1] - goal) / (log_u[right - 1] - log_u[right])
        start = lower + fraction * (upper - lower)
        # widen by a few ulp so that Newton's first steps do not land on the bounds
        lower, upper = lower - 1e-12 * np.abs(lower) - 1e-300, upper + 1e-12 * np.abs(upper)

        def function(log_pressure: np.ndarray, index: np.ndarray
                     ) -> tuple[np.ndarray, np.ndarray]:
            p = np.exp(log_pressure)
            u, du = self._integrals(p, gap=True, slope=True)
            return np.log(u) - goal[index], -p * du / u

        root, ok, _ = monotone_root(function, lower, upper, start, increasing=False)
        pressure[inside] = np.exp(root)
        converged[inside] = ok
        return pressure, converged

    def _curve(self, pressure: np.ndarray, load: np.ndarray, gap: np.ndarray | None,
               names: frozenset[str], converged: np.ndarray | None = None) -> ContactCurve:
        shape = pressure.shape
        flat = pressure.ravel()
        inside = (flat > 0) & (flat < self._pressure_range[1])
        want_gap = gap is None              # the mean gap is always returned, as in every model
        want_slope = bool(names & {"stiffness", "conductance"})
        u_in, du_in = self._integrals(flat[inside], gap=want_gap, slope=want_slope)
        if gap is None:
            gap = np.where(flat == 0, np.inf, 0.0)
            gap[inside] = u_in
            gap = gap.reshape(shape)
        stiffness = conductance = None
        if want_slope:
            s = np.where(flat == 0, 0.0, np.inf)
            with np.errstate(divide="ignore"):
                s[inside] = self.nominal_area / du_in
            stiffness = s.reshape(shape)
            conductance = 2.0 * stiffness / self.e_star
        with np.errstate(over="ignore", invalid="ignore"):
            x_top = pressure / (math.sqrt(math.pi) * self.e_star * self._top)
        area = self.nominal_area * special.erf(x_top)
        if converged is None:
            converged = np.ones(shape, dtype=bool)
        extras = {"mean_gap": gap, "converged": converged}
        if "leakage" in names:
            from asperity.spectral.persson_gaps import persson_leakage
            extras.update(persson_leakage(self, pressure, gap))
        return ContactCurve(
            separation=gap, load=load, area=area, mean_pressure=pressure,
            nominal_area=self.nominal_area, e_star=self.e_star,
            stiffness=stiffness if "stiffness" in names else None,
            conductance=conductance if "conductance" in names else None,
            leakage=extras.pop("leakage", None), extras=extras)
