"""Bush-Gibson-Thomas (BGT) theory: elliptic Hertzian summits with Nayak's statistics.

Bush, Gibson & Thomas, Wear 35 (1975); restated by Carbone & Bottiglione, JMPS 56 (2008).
Equations in docs/theory.md, section "Bush-Gibson-Thomas theory", eqs. S8-S12.

Model
-----
The summits of an isotropic Gaussian surface of profile moments m0, m2, m4
(:mod:`asperity.spectral.spectral_summits`, eq. S1) are elliptic paraboloids. Write ``s = m4/3``; at a
summit of height z the principal curvatures are ``kappa = a +- r``, with a the mean curvature
and r half their difference. Nayak's density of summits per unit area (eq. S8) is

    n(z, a, r) = (a^2 - r^2) / (2 pi m2) * N2(z, a) * (r/s) exp(-r^2/(2 s)),   0 <= r < a,

N2 the bivariate normal density of z (variance m0) and a (variance 2s), covariance m2; the
factor r/s exp(...) is the Rayleigh law of r. Each summit above the rigid plane at
separation d (from the mean plane of the heights) is a Hertz contact of approach ``w = z - d``
(:mod:`asperity.spectral.hertz_elliptic`): area ``pi w f_A / sqrt(a^2 - r^2)``, load
``(4/3) E* w^(3/2) f_P / (a^2 - r^2)^(1/4)``, stiffness ``dP/dw``, f_A and f_P functions of
the ratio ``(a - r)/(a + r)``. The totals over the nominal area A are integrals over n (S10).

Evaluation
----------
With ``a = sqrt(s) x`` and ``r = a t`` (t in [0, 1)), the height enters only through the
conditional normal law of z given x: mean ``mu(x) = m2 x / (2 sqrt(s))``, standard deviation
``sd = sqrt(m0 - 3 m2^2 / (2 m4))`` (real for alpha > 3/2). The height integral is then a
GW function, ``integral_d^inf (z - d)^n N(z; mu, sd) dz = sd^n F_n((d - mu)/sd)``, and

    Q(d) = A s/(2 pi m2) sum_i W_i x_i^4 phi_2(x_i) c_Q(x_i) T_Q(x_i) sd^n F_n((d - mu(x_i))/sd)

(eq. S11): phi_2 is the N(0, 2) density of x, ``T_Q(x) = integral_0^1 t (1 - t^2)^beta_Q
g_Q(t) exp(-x^2 t^2/2) dt`` holds the curvature-ratio integral, and (W_i, x_i) is a
Gauss-Legendre rule. T_Q and the weights are computed once per model; each separation costs
one GW function per node and quantity. Sums are taken in logarithms (loads far below the
reference do not underflow), and the load is inverted by a safeguarded Newton iteration on
log W(d). The node spacing follows the conditional spread of x at a given height, so the
rule resolves the integrand up to heights of 40 sqrt(m0) (loads down to the smallest double).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import KW_ONLY, dataclass, field
from typing import Iterable

import numpy as np
from numpy.typing import ArrayLike
from scipy.special import logsumexp

from bem.common import checks
from bem.common.curve import CURVE_QUANTITIES, ContactCurve
from bem.model import check_quantities, empty_curve
from bem.common.warnings import ConvergenceWarning

from asperity.common.gw_functions import log_gw_integrals
from asperity.common.leakage import rigid_gaussian_aperture
from asperity.spectral.hertz_elliptic import hertz_elliptic_factors
from asperity.common.roots import monotone_root
from asperity.spectral.spectral_summits import SpectralMoments, SpectralSummits

__all__ = ["BushGibsonThomas"]

#: Highest reduced summit height z/sqrt(m0) the quadrature resolves.
_TOP = 40.0
#: Gauss-Legendre nodes per panel.
_ORDER = 8
#: GW order behind each quantity: count F_0, stiffness F_1/2, area F_1, load F_3/2.
_GW_ORDER = {"contacts": 0.0, "stiffness": 0.5, "area": 1.0, "load": 1.5}
#: Exponent beta of (1 - t^2) in T_Q, and which Hertz factor g_Q enters (index into (1, f_A, f_P)).
_CURVATURE = {"contacts": (1.0, 0), "area": (0.5, 1), "load": (0.75, 2)}
#: At most this many points are evaluated at once (memory: points x nodes doubles).
_CHUNK = 2 ** 18


def _gauss_panels(edges: np.ndarray, order: int = _ORDER) -> tuple[np.ndarray, np.ndarray]:
    """Composite Gauss-Legendre nodes and weights on the panels between ``edges``."""
    unit_nodes, unit_weights = np.polynomial.legendre.leggauss(order)
    half = 0.5 * np.diff(edges)[:, None]
    centre = 0.5 * (edges[:-1] + edges[1:])[:, None]
    return (centre + half * unit_nodes).ravel(), (half * unit_weights).ravel()


def _curvature_integrals(x: np.ndarray, elliptic: bool) -> dict[str, np.ndarray]:
    """T_Q(x) for the count, area and load (stiffness shares the load's), by t = sin(theta)
    on geometrically graded panels in theta (exp(-x^2 t^2/2) narrows as x grows)."""
    edges = np.concatenate(([0.0], np.geomspace(2e-3, 0.5 * math.pi, 33)))
    theta, weight = _gauss_panels(edges)
    t, cos = np.sin(theta), np.cos(theta)
    ratio = (1.0 - t) / (1.0 + t)
    factors = (np.ones_like(t),) + (hertz_elliptic_factors(ratio) if elliptic
                                    else (np.ones_like(t), np.ones_like(t)))
    kernel = np.exp(-0.5 * np.square(np.outer(x, t)))
    out = {}
    for name, (beta, which) in _CURVATURE.items():
        # dt = cos(theta) dtheta, (1 - t^2)^beta = cos(theta)^(2 beta)
        out[name] = kernel @ (weight * t * cos ** (2.0 * beta + 1.0) * factors[which])
    return out


@dataclass(frozen=True, eq=False)
class BushGibsonThomas:
    """Bush-Gibson-Thomas theory of an isotropic Gaussian surface (module docstring).

    Parameters
    ----------
    m0, m2, m4 : float
        Profile spectral moments (eq. S1): mean square height [length^2], mean square
        profile slope [-], mean square profile curvature [1/length^2]; alpha = m0 m4/m2^2
        must exceed 3/2.
    e_star : float, keyword-only
        Composite modulus E* [pressure].
    area : float, keyword-only
        Nominal contact area A [length^2].
    elliptic : bool, keyword-only
        True (default, BGT): elliptic Hertz contacts. False: every summit a sphere of the
        geometric-mean radius (Greenwood's simplified elliptic model, 2006).

    Separations d are measured from the rigid plane to the mean plane of the surface heights
    (the BEM's convention). Every curve carries ``extras["converged"]``.
    """

    m0: float
    m2: float
    m4: float
    _: KW_ONLY
    e_star: float = 1.0
    area: float = 1.0
    elliptic: bool = True
    _nodes: dict = field(init=False, repr=False, compare=False)

    name = "bgt"

    def __post_init__(self) -> None:
        moments = SpectralMoments(self.m0, self.m2, self.m4)
        for name in ("m0", "m2", "m4"):
            object.__setattr__(self, name, getattr(moments, name))
        for name in ("e_star", "area"):
            object.__setattr__(self, name, checks.positive(name, getattr(self, name)))
        object.__setattr__(self, "elliptic", checks.flag("elliptic", self.elliptic))
        if not moments.alpha > 1.5 * (1.0 + 1e-6):
            raise ValueError(f"m4: BGT theory needs the bandwidth alpha = m0 m4 / m2^2 > 1.5 "
                             f"(summit heights and curvatures not fully correlated), got "
                             f"alpha = {moments.alpha:.9g}")
        object.__setattr__(self, "_nodes", self._build_nodes())

    def __getstate__(self):
        return {name: getattr(self, name) for name in ("m0", "m2", "m4", "e_star", "area",
                                                        "elliptic")}

    def __setstate__(self, state) -> None:
        for name, value in state.items():
            object.__setattr__(self, name, value)
        object.__setattr__(self, "_nodes", self._build_nodes())

    # ------------------------------------------------------------------ statistics
    @property
    def moments(self) -> SpectralMoments:
        """The profile moments."""
        return SpectralMoments(self.m0, self.m2, self.m4)

    @property
    def summits(self) -> SpectralSummits:
        """Nayak's summit statistics of the surface (density, mean height, ...)."""
        return self.moments.summits()

    @property
    def alpha(self) -> float:
        """Nayak's bandwidth m0 m4 / m2^2 [-]."""
        return self.moments.alpha

    # ------------------------------------------------------------------ quadrature
    def _build_nodes(self) -> dict:
        s = self.m4 / 3.0
        rho = math.sqrt(1.5 / self.moments.alpha)       # correlation of z and a
        spread = math.sqrt(2.0 * (1.0 - rho * rho))     # std of x given z
        top = math.sqrt(2.0) * (rho * _TOP + 9.0)
        width = min(1.0, 0.6 * spread)
        panels = math.ceil(top / width)
        if panels > 20000:
            raise ValueError(f"m4: alpha = {self.moments.alpha:.9g} is too close to 1.5 for the "
                             "BGT quadrature (summit heights and curvatures nearly degenerate)")
        x, w = _gauss_panels(np.linspace(0.0, top, panels + 1))
        curvature = _curvature_integrals(x, self.elliptic)
        sd = math.sqrt(self.m0 - 1.5 * self.m2**2 / self.m4)
        log_x = np.log(x)
        base = (np.log(w) + 4.0 * log_x - 0.25 * x * x - math.log(2.0 * math.sqrt(math.pi))
                + math.log(self.area * s / (2.0 * math.pi * self.m2)))
        scale = {
            "contacts": base + np.log(curvature["contacts"]),
            "area": base + np.log(curvature["area"]) + math.log(math.pi * sd)
            - 0.5 * math.log(s) - log_x,
            "load": base + np.log(curvature["load"])
            + math.log(4.0 / 3.0 * self.e_star * sd**1.5) - 0.25 * math.log(s) - 0.5 * log_x,
            "stiffness": base + np.log(curvature["load"])
            + math.log(2.0 * self.e_star * math.sqrt(sd)) - 0.25 * math.log(s) - 0.5 * log_x,
        }
        mean = self.m2 * x / (2.0 * math.sqrt(s))
        return {"log_weight": scale, "mean": mean, "sd": sd}

    def _log_quantities(self, d: np.ndarray, names: Iterable[str]) -> dict[str, np.ndarray]:
        """log of each quantity at finite separations d (1-D), chunked over the points."""
        names = tuple(names)
        nodes = self._nodes
        out = {name: np.empty(d.size) for name in names}
        step = max(1, _CHUNK // nodes["mean"].size)
        orders = tuple(sorted({_GW_ORDER[name] for name in names}))
        for start in range(0, d.size, step):
            part = d[start:start + step]
            h = (part[:, None] - nodes["mean"][None, :]) / nodes["sd"]
            logs = dict(zip(orders, log_gw_integrals(orders, h)))
            for name in names:
                terms = logs[_GW_ORDER[name]] + nodes["log_weight"][name][None, :]
                out[name][start:start + step] = logsumexp(terms, axis=1)
        return out

    def _quantities(self, d: np.ndarray, want: frozenset[str]) -> dict[str, np.ndarray]:
        """Area, load (and contacts, stiffness if wanted) at separations d (+inf allowed)."""
        names = {"area", "load"} | (want & {"contacts"})
        if want & {"stiffness", "conductance"}:
            names.add("stiffness")
        flat = d.ravel()
        finite = np.isfinite(flat)
        out = {name: np.zeros(flat.shape) for name in names}
        if finite.any():
            logs = self._log_quantities(flat[finite], names)
            with np.errstate(over="ignore"):
                for name in names:
                    out[name][finite] = np.exp(logs[name])
        return {name: value.reshape(d.shape) for name, value in out.items()}

    def _curve(self, d, values, want, load=None, converged=None) -> ContactCurve:
        load = values["load"] if load is None else load
        if converged is None:
            converged = np.ones(np.shape(load), dtype=bool)
        stiffness = values.get("stiffness")
        return ContactCurve(
            separation=d, load=load, area=values["area"], mean_pressure=load / self.area,
            nominal_area=self.area, e_star=self.e_star,
            contacts=values.get("contacts") if "contacts" in want else None,
            stiffness=stiffness if "stiffness" in want else None,
            conductance=2.0 * stiffness / self.e_star if "conductance" in want else None,
            leakage=(rigid_gaussian_aperture(d, math.sqrt(self.m0)) if "leakage" in want
                     else None),
            extras={"converged": converged})

    # ------------------------------------------------------------------ the contract
    def at_separation(self, separation: ArrayLike, *,
                      quantities: Iterable[str] = CURVE_QUANTITIES) -> ContactCurve:
        """Contact curve at separations d [length] (any shape; +inf: out of contact).

        Returns a :class:`bem.ContactCurve` (:class:`bem.ContactModel` contract): load, area,
        mean pressure and, if asked for, contacts (the expected number of summits touching),
        stiffness ``S = -dW/dd``, conductance ``2S/E*`` and leakage (the effective-medium
        aperture of the rigid gap ``max(d - z, 0)`` over Gaussian heights of rms sqrt(m0),
        docs/theory.md section 10.3, as for GW theory). Extras: ``converged`` (all True).
        """
        d = checks.points("separation", separation, allow_infinity=True)
        want = check_quantities(quantities)
        if d.size == 0:
            return empty_curve(self.area, self.e_star, want)
        values = self._quantities(d, want)
        checks.no_overflow("separation", values["load"], "the BGT load (far below the summits)")
        return self._curve(d, values, want)

    def at_load(self, load: ArrayLike, *,
                quantities: Iterable[str] = CURVE_QUANTITIES) -> ContactCurve:
        """Contact curve at total loads W [force] (any shape; W = 0: separation +inf).

        log W(d) is inverted by Newton's iteration safeguarded by bisection
        (:func:`asperity.common.roots.monotone_root`) in the reduced separation d/sqrt(m0), from a
        bracket found by stepping down (or up) from the mean summit height. Extras:
        ``converged`` (bool per point; unconverged points are warned).
        """
        w = checks.points("load", load, non_negative=True)
        want = check_quantities(quantities)
        if w.size == 0:
            return empty_curve(self.area, self.e_star, want)
        d, converged = self._separation_at_load(w.ravel())
        d, converged = d.reshape(w.shape), converged.reshape(w.shape)
        if not converged.all():
            warnings.warn(f"BGT load inversion: {int(np.size(converged) - converged.sum())} of "
                          f"{converged.size} points did not converge", ConvergenceWarning,
                          stacklevel=2)
        return self._curve(d, self._quantities(d, want), want, load=w, converged=converged)

    def _separation_at_load(self, load: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        d = np.full(load.shape, np.inf)
        converged = np.ones(load.shape, dtype=bool)
        positive = load > 0
        if not positive.any():
            return d, converged
        goal = np.log(load[positive])
        unit = math.sqrt(self.m0)
        origin = self.summits.mean / unit

        def log_load(x: np.ndarray) -> np.ndarray:
            return self._log_quantities(x * unit, ("load",))["load"]

        # Bracket: step away from the mean summit height by doubling strides; "near" keeps
        # the last point short of the goal, "far" the first point beyond it.
        heavy = goal > log_load(np.array([origin]))[0]
        sign = np.where(heavy, -1.0, 1.0)
        near = np.full(goal.shape, origin)
        far = near.copy()
        open_ = np.ones(goal.shape, dtype=bool)
        stride = 1.0
        for _ in range(64):
            index = np.flatnonzero(open_)
            if index.size == 0:
                break
            trial = origin + sign[index] * stride
            values = log_load(trial)
            reached = np.where(heavy[index], values >= goal[index], values <= goal[index])
            far[index] = trial
            near[index[~reached]] = trial[~reached]
            open_[index[reached]] = False
            stride *= 2.0
        lower, upper = np.where(heavy, far, near), np.where(heavy, near, far)

        def function(x, index):
            logs = self._log_quantities(x * unit, ("load", "stiffness"))
            return logs["load"] - goal[index], -unit * np.exp(logs["stiffness"] - logs["load"])

        start = 0.5 * (lower + upper)
        root, ok, _ = monotone_root(function, lower, upper, start, increasing=False)
        d[positive] = root * unit
        converged[positive] = ok & ~open_
        return d, converged
