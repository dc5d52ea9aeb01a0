"""The parameters and shared physics of GW-type theories (:mod:`asperity.gw.greenwood_williamson`).

A base class validates and stores the summit parameters (density eta, radius R, height spread
sigma, mean mu_s, E*, nominal area A, height law) and evaluates plain GW theory at reduced
separations h = (d - mu_s)/sigma: area, load, contacts and stiffness from the GW functions, the
load inversion h(W), and the contact curve with its leakage. Conventions and equations: the
docstring of :mod:`asperity.gw.greenwood_williamson` and docs/theory.md, "GW theory".
"""

from __future__ import annotations

import math
import warnings
from dataclasses import KW_ONLY, dataclass

import numpy as np
from numpy.typing import ArrayLike

from bem.common import checks
from bem.common.curve import CURVE_QUANTITIES, ContactCurve
from bem.common.warnings import ConvergenceWarning

from asperity.gw.dimensionless import interaction_parameter as _interaction_parameter
from asperity.common.leakage import rigid_gaussian_aperture
from asperity.common.gw_functions import _check_distribution, gw_integrals, inverse_log_gw_integral

__all__: list[str] = []

#: GW function order behind each quantity: contacts F_0, stiffness F_1/2, area F_1, load F_3/2.
_ORDER = {"contacts": 0.0, "stiffness": 0.5, "area": 1.0, "load": 1.5}


def _orders(want: frozenset[str]) -> tuple[float, ...]:
    """GW function orders needed for the quantities asked for (area and load always)."""
    needed = {"area", "load"} | (want & {"contacts"})
    if want & {"stiffness", "conductance"}:
        needed.add("stiffness")
    return tuple(sorted(_ORDER[q] for q in needed))


def _separations(separation: ArrayLike) -> np.ndarray:
    return checks.points("separation", separation, allow_infinity=True)   # +inf: no contact


def _loads(load: ArrayLike) -> np.ndarray:
    return checks.points("load", load, non_negative=True)                # 0: separation +inf


def _warn_unconverged(converged: np.ndarray, what: str) -> None:
    if not np.all(converged):
        warnings.warn(f"{what}: {int(np.size(converged) - np.count_nonzero(converged))} of "
                      f"{np.size(converged)} points did not converge", ConvergenceWarning,
                      stacklevel=3)


@dataclass(frozen=True)
class _SummitHeightTheory:
    """Parameters shared by GW-type theories (validated, stored as floats)."""

    density: float
    radius: float
    sigma: float
    _: KW_ONLY
    mean: float = 0.0
    e_star: float = 1.0
    area: float = 1.0
    distribution: str = "gaussian"
    height_rms: float | None = None

    def __post_init__(self) -> None:
        # magnitudes in the supported range (checks.SUPPORTED_MAGNITUDE), so that products
        # such as W_ref = eta A E* R^(1/2) sigma^(3/2) neither overflow nor underflow
        for name in ("density", "radius", "sigma", "e_star", "area"):
            object.__setattr__(self, name, checks.contact_number(name, getattr(self, name),
                                                                 minimum=0.0, exclusive=True))
        if self.height_rms is not None:
            object.__setattr__(self, "height_rms", checks.contact_number(
                "height_rms", self.height_rms, minimum=0.0, exclusive=True))
        largest = checks.SUPPORTED_MAGNITUDE[1]     # an offset: any small value is fine
        mean = checks.real_number("mean", self.mean, minimum=-largest, maximum=largest)
        object.__setattr__(self, "mean", mean)
        _check_distribution(self.distribution)

    # derived constants ----------------------------------------------------------------------
    @property
    def summit_count(self) -> float:
        """N = eta A, the expected number of summits on the nominal area [-]."""
        return self.density * self.area

    @property
    def interaction_parameter(self) -> float:
        """C = eta sqrt(A R sigma) = sqrt(N eta R sigma), the paper's eq. (4) [-]."""
        return _interaction_parameter(self.density, self.radius, self.sigma, self.area)

    @property
    def reference_load(self) -> float:
        """W_ref = eta E* R^(1/2) sigma^(3/2) A [force]: load = (4/3) W_ref F_3/2(h)."""
        return self.summit_count * self.e_star * math.sqrt(self.radius) * self.sigma ** 1.5

    # shared physics -------------------------------------------------------------------------
    def _reduced(self, separation: np.ndarray) -> np.ndarray:
        with np.errstate(over="ignore"):
            return (separation - self.mean) / self.sigma

    def _gw_quantities(self, h: np.ndarray, want: frozenset[str] = frozenset(CURVE_QUANTITIES)
                       ) -> dict[str, np.ndarray]:
        """Area and load of plain GW theory at reduced separation h, plus contacts and stiffness
        when asked for (only the GW functions needed are evaluated)."""
        orders = _orders(want)
        f = dict(zip(orders, gw_integrals(orders, h, self.distribution)))
        n = self.summit_count
        out = {}
        with np.errstate(over="ignore"):             # absurdly deep contact: +inf, not NaN
            out["area"] = math.pi * n * self.radius * self.sigma * f[1.0]
            out["load"] = (4.0 / 3.0) * self.reference_load * f[1.5]
            if 0.0 in f:
                out["contacts"] = n * f[0.0]
            if 0.5 in f:
                out["stiffness"] = 2.0 * self.reference_load / self.sigma * f[0.5]
        return out

    def _reduced_at_load(self, load: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """h with (4/3) W_ref F_3/2(h) = load (h = +inf at zero load), and convergence flags."""
        with np.errstate(divide="ignore"):
            log_target = np.log(load) - math.log(self.reference_load) + math.log(0.75)
        return inverse_log_gw_integral(1.5, log_target, self.distribution)

    @property
    def gap_rms(self) -> float:
        """s [length]: the spread of the heights in the rigid gap of ``leakage``, the surface's
        ``height_rms`` when given, else sigma (the only height spread GW theory carries)."""
        return self.sigma if self.height_rms is None else self.height_rms

    def _curve(self, separation: np.ndarray, quantities: dict[str, np.ndarray],
               want: frozenset[str], load: np.ndarray | None = None, *,
               gap_separation: np.ndarray | None = None, **extras: np.ndarray) -> ContactCurve:
        load = quantities["load"] if load is None else load
        gap_separation = separation if gap_separation is None else gap_separation
        stiffness = quantities.get("stiffness")
        extras.setdefault("converged", np.ones(np.shape(load), dtype=bool))
        return ContactCurve(
            separation=separation, load=load, area=quantities["area"],
            mean_pressure=load / self.area, nominal_area=self.area, e_star=self.e_star,
            contacts=quantities.get("contacts") if "contacts" in want else None,
            stiffness=stiffness if "stiffness" in want else None,
            conductance=2.0 * stiffness / self.e_star if "conductance" in want else None,
            leakage=(rigid_gaussian_aperture(gap_separation, self.gap_rms) if "leakage" in want
                     else None),
            extras=extras)
