"""Frictionless normal contact of a rough surface with a rigid plane: constrained conjugate gradients.

The problem (docs/theory.md, "The reference")
----------------------------------------------
Find pixel pressures ``p >= 0`` with ``gap = d - z + u >= 0`` and ``p * gap = 0`` everywhere,
where ``z`` are the heights (as given: the solver never re-centres them), ``u = K * p`` the
half-space displacement (:class:`bem.HalfSpace`) and ``d`` the separation, i.e. the height of
the rigid plane above the plane ``z = 0``. For heights with zero mean (as
:func:`validation.wm_surface` returns) that plane is the mean plane of the heights, the project's
reference for the separation. The total load is ``W = h^2 sum p`` (h the grid spacing).

* Non-periodic: u vanishes in the far field, so d is measured from the far field.
* Periodic: the mean displacement is zero (``u_hat(0) = 0``), so d is measured from the mean
  plane of the *deformed* surface, which coincides with the mean plane of the undeformed heights;
  the mean gap is then exactly ``d - mean(z)``, in load and in separation control alike. Full
  contact is reached at ``d = mean(z)``, where the load is undetermined: separation control needs
  ``d > mean(z)``.

Algorithms
----------
Load control: Polonsky & Keer (1999) constrained conjugate gradients, which minimise the elastic
energy ``(1/2) p.Kp - p.z`` over ``p >= 0`` at fixed ``sum p`` (d is the Lagrange multiplier,
``d = mean over the contact set of (z - u)``). Separation control: the same iteration without the
load constraint, i.e. minimising ``(1/2) p.Kp + p.(d - z)`` over ``p >= 0`` (the
displacement-controlled variant of Rey, Anciaux & Molinari 2017). Each iteration needs one
half-space product of the search direction; the displacement of the pressure is updated from it
exactly, ``u <- c (u - tau K t + K e)``, where e are the changes the projection ``p >= 0`` and
the entering pixels make: by direct sums of influence coefficients when they touch a few pixels
(:attr:`bem.HalfSpace.direct_source_limit`), otherwise by a full product of p, which is also
made every 50 iterations and at the end. The fields of the contact set live on it alone, one value
per contact pixel, scattered into and gathered from the FFT buffers; inner products use numpy's
reductions, not BLAS, whose spinning threads stall the FFT threads (:mod:`bem.contact.constrained_cg`).

Grid-independent iteration counts (default, ``preconditioned=True``): the gap on the contact set
is preconditioned by the inverse half-space symbol ``(E*/2)|q|`` restricted to the contact set
(:mod:`bem.contact.preconditioner`, one N x M FFT pair per iteration), overlapping pixels join the
contact set at zero pressure before each step (:mod:`bem.contact.constrained_cg`), and a cold start is
the pressure of the same problem on every other grid point, solved the same way down to 64 x 64
and repeated on 2 x 2 pixels (nested iteration; ``HalfSpace.coarse`` keeps the coarse
operators). On a WM surface (D = 2.5) at 4 / 18 / 44 % contact the iterations went from 76 /
109 / 228 (N = 256) and 244 / 475 / 1026 (N = 1024) to 24 / 33 / 43 and 30 / 40 / 54
(benchmarks/bench_bem.py). The
stopping rule and hence the converged state are the same as the plain iteration's
(``preconditioned=False``): tests/test_bem_preconditioned.py checks identical contact sets and
area, load, separation and stiffness to 1e-6.

Stiffness: the incremental problem on the converged contact set C, ``K_CC q = 1`` (unit rigid
approach) solved by conjugate gradients with the same preconditioner (:mod:`bem.contact.stiffness`);
``S = -dW/dd = h^2 sum q``, and the conductance by Barber's analogy ``C rho = 2 S / E*``
(docs/theory.md, eq. T5).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from bem.common import checks
from bem.contact.area import PERIMETER_COEFFICIENT, contact_area
from bem.elastic.device import check_device, to_host
from bem.contact.cg_buffers import _Workspace
from bem.contact.constrained_cg import _constrained_cg, _Outcome, _separation_start
from bem.elastic.halfspace import HalfSpace
from bem.contact.nested_grid import _nestable, _prolonged
from bem.contact.solution import ContactSolution, _frozen
from bem.contact.stiffness import _stiffness
from bem.common.warnings import ConvergenceWarning

__all__ = ["ContactSolution", "solve_contact", "DEFAULT_TOLERANCE", "DEFAULT_MAX_ITERATIONS",
           "MINIMUM_GRID"]

#: Default ``tol`` of :func:`solve_contact` (relative pressure change, see its docstring).
DEFAULT_TOLERANCE = 1e-9
#: Default ``max_iter`` of :func:`solve_contact`.
DEFAULT_MAX_ITERATIONS = 5000
#: Smallest accepted grid side (points).
MINIMUM_GRID = 4
#: Stopping tolerance of the coarse solves of the nested iteration (starts only).
#: (the fine iteration counts were the same with 1e-4, 1e-6 and 1e-9 on WM surfaces).
_COARSE_TOLERANCE = 1e-6
#: Most iterations of each coarse solve of the nested iteration.
_COARSE_MAX_ITERATIONS = 500

#: Residual of the conjugate-gradient stiffness solve per unit of the contact solve's tolerance
#: (eq. T26): the stiffness then moves by about 0.01 tol relative, a fifth of the contact
#: solve's own 0.047 tol (docs/theory.md, eq. T40). Measured on a 512^2 AFM-like scan, 12
#: loads: the relative error of the stiffness is 0.09-0.11 times the residual tolerance, for
#: residual tolerances from 1e-4 to 1e-8 against 1e-11.
_STIFFNESS_SHARE = 0.1
#: Tightest residual of the stiffness solve (below it the iteration only chases rounding).
_STIFFNESS_FLOOR = 1e-11


# ------------------------------------------------------------------------------------------------
# input checks


def _check_problem(heights, spacing, e_star, tol, max_iter, periodic):
    """Checked (heights, spacing, e_star, tol, max_iter, periodic) of a contact problem."""
    return checks.contact_problem(heights, spacing, e_star, tol, max_iter, periodic,
                                  minimum_grid=MINIMUM_GRID)


def _check_real(name: str, value, *, positive: bool = False, non_negative: bool = False) -> float:
    return checks.contact_number(name, value, minimum=0.0 if positive or non_negative else None,
                                 exclusive=positive)


def _check_operator(operator, shape, spacing, e_star, periodic, mirror=False,
                    device="cpu") -> HalfSpace:
    if operator is None:
        return HalfSpace(shape, spacing, e_star=e_star, periodic=periodic, mirror=mirror,
                         device=device)
    if not isinstance(operator, HalfSpace):
        raise ValueError(f"operator must be a bem.HalfSpace, got {type(operator).__name__}")
    mismatch = []
    if operator.shape != tuple(shape):
        mismatch.append(f"shape {operator.shape} != {tuple(shape)}")
    if not math.isclose(operator.spacing, spacing, rel_tol=1e-12):
        mismatch.append(f"spacing {operator.spacing!r} != {spacing!r}")
    if not math.isclose(operator.e_star, e_star, rel_tol=1e-12):
        mismatch.append(f"e_star {operator.e_star!r} != {e_star!r}")
    if operator.periodic != periodic:
        mismatch.append(f"periodic {operator.periodic} != {periodic}")
    if operator.mirror != mirror:
        mismatch.append(f"mirror {operator.mirror} != {mirror}")
    if operator.device != check_device(device):
        mismatch.append(f"device {operator.device!r} != {device!r}")
    if mismatch:
        raise ValueError("operator does not match the problem: " + "; ".join(mismatch))
    return operator


def _check_initial(initial, shape) -> np.ndarray | None:
    if initial is None:
        return None
    initial = np.array(checks.real_array("initial", initial), dtype=float, copy=True)
    if initial.shape != tuple(shape):
        raise ValueError(f"initial must have the heights' shape {tuple(shape)}, got {initial.shape}")
    np.maximum(initial, 0.0, out=initial)
    return initial


# ------------------------------------------------------------------------------------------------
# public entry point


def solve_contact(
    heights,
    spacing: float,
    *,
    load: float | None = None,
    separation: float | None = None,
    e_star: float = 1.0,
    periodic: bool = False,
    tol: float = DEFAULT_TOLERANCE,
    max_iter: int = DEFAULT_MAX_ITERATIONS,
    initial=None,
    operator: HalfSpace | None = None,
    stiffness: bool = False,
    preconditioned: bool = True,
    device: str = "cpu",
) -> ContactSolution:
    """Contact of a rough elastic surface with a rigid plane, at given load or separation.

    Constrained conjugate gradients (Polonsky & Keer 1999; separation control after Rey,
    Anciaux & Molinari 2017) on the boundary-element half-space of docs/theory.md, "The reference".
    Conventions (gap, separation d, periodic mean plane): module docstring.

    Parameters
    ----------
    heights : array_like
        Heights z[j, i] [length] of the elastic surface on an N x M grid of square pixels
        (N, M >= 4; row j is y, column i is x), as given: not re-centred. The rigid plane is
        above, at ``z = d``.
    spacing : float
        Grid step h [length]; the nominal area is ``A = N M h^2``.
    load : float, optional
        Total force W >= 0 [force] (load control).
    separation : float, optional
        Separation d [length] (separation control). Exactly one of ``load`` and ``separation``.
        Periodic: must exceed ``mean(z)``. ``d >= max(z)`` gives the zero-load solution.
    e_star : float
        Composite modulus E* [pressure].
    periodic : bool
        Periodic (spectral kernel) or isolated (Love's kernel, DC-FFT) half-space.
    tol : float
        Stopping tolerance, see below. The default 1e-9 gives the area and the load to better
        than 1e-6 relative: against tol = 1e-13 the contact sets were identical and the
        separation-controlled load within 2e-10 on WM surfaces (N = 128 and 512, 1 % to 22 %
        contact), and tests/test_bem_solver.py checks it against tol = 1e-14.
    max_iter : int
        Most conjugate-gradient iterations.
    initial : array_like, optional
        Starting pressure (warm start, e.g. the previous point of a load path); clipped to
        >= 0 and, in load control, scaled to the load.
    operator : HalfSpace, optional
        A prebuilt operator of the same shape, spacing, E* and periodicity (built otherwise).
    stiffness : bool
        Also solve the incremental problem for the stiffness S = -dW/dd.
    preconditioned : bool
        Precondition the iteration and start cold solves from the coarse grid (module
        docstring); False gives the plain Polonsky-Keer iteration, whose iteration count grows
        like n. Both converge to the same state under the same stopping rule.
    device : {"cpu", "gpu"}
        Where the solve runs (:mod:`bem.elastic.device`): numpy, or CuPy on a CUDA GPU. The solution's
        arrays are numpy arrays either way.

    Returns
    -------
    ContactSolution

    Notes
    -----
    Stopping rule (Polonsky & Keer's): iteration k ends the solve when

        ``sum_ij |p_ij^(k) - p_ij^(k-1)| <= tol * sum_ij p_ij^(k)``

    the sum over every pixel, those that left the contact set by the projection ``p >= 0`` or
    entered it (a non-contact pixel with negative gap) included; with ``stiffness``, once an
    iteration also changes no contact pixel (the stiffness solve freezes the set).
    ``residual`` reports the left side over ``sum p``. The stiffness solve stops when ``||1 - (K q)_C||_2 <= 0.1 tol
    sqrt(|C|)`` (at least 1e-11), its error then a fifth of the contact solve's.
    Non-convergence gives ``converged=False``, a message and a
    :class:`bem.common.warnings.ConvergenceWarning`; the last iterate is returned.

    Raises
    ------
    ValueError
        For non-finite, non-2-D or smaller than 4 x 4 heights, spacing <= 0,
        e_star <= 0, negative load, both or neither of load/separation, a periodic separation
        <= mean(z), tol <= 0, max_iter < 1, a bad initial pressure, a mismatched operator, or
        ``device="gpu"`` without CuPy or a CUDA device.
    """
    z, spacing, e_star, tol, max_iter, periodic = _check_problem(
        heights, spacing, e_star, tol, max_iter, periodic)
    if (load is None) == (separation is None):
        raise ValueError("give exactly one of load (force) and separation (length)")
    if load is not None:
        load = _check_real("load", load, non_negative=True)
    else:
        separation = _check_real("separation", separation)
        if periodic and separation <= float(z.mean()):
            raise ValueError(
                f"separation must exceed the mean height {float(z.mean())!r} for a periodic "
                f"surface (full contact, where the load is undetermined), got {separation!r}")
    initial = _check_initial(initial, z.shape)
    operator = _check_operator(operator, z.shape, spacing, e_star, periodic, device=device)
    z = operator.xp.asarray(z)
    return _solve(operator, z, load=load, separation=separation, tol=tol, max_iter=int(max_iter),
                  initial=initial, stiffness=stiffness, ws=_Workspace(z.shape, operator.xp),
                  preconditioned=preconditioned)


def _solve(operator: HalfSpace, z: np.ndarray, *, load: float | None, separation: float | None,
           tol: float, max_iter: int, initial: np.ndarray | None, stiffness: bool,
           ws: _Workspace, preconditioned: bool = True, warn: bool = True) -> ContactSolution:
    """The solve after validation (shared with the load path); ``warn``: a solve that does not
    converge warns (ConvergenceWarning). ``z`` is an array of the operator's device; ``initial``
    may be a host array."""
    xp = operator.xp
    preconditioner = ws.inverse_kernel(operator) if preconditioned else None
    ws.preconditioned = preconditioned
    if initial is None and preconditioned:
        initial = _coarse_start(operator, z, load=load, separation=separation, tol=tol,
                                max_iter=max_iter)[0]
    if initial is not None:
        initial = xp.asarray(initial)   # (numpy: the same array; a GPU: a copy of the host's)
    pixel_area = operator.spacing**2
    nominal_area = z.size * pixel_area
    highest = float(z.max())
    zero_load = (load is not None and load == 0.0) or (separation is not None
                                                     and separation >= highest)
    if zero_load:
        d = highest if separation is None else separation
        p = xp.zeros(z.shape)
        return _record(operator, z, p, xp.zeros(z.shape), d, _Outcome(
            p, True, 0, 0.0, "zero load: no contact"), stiffness, ws, nominal_area, tol, warn)
    if load is not None:
        total = load / pixel_area
        if initial is not None and initial.sum() > 0.0:
            p = _owned(initial)
            p *= total / float(p.sum())
        else:
            p = xp.full(z.shape, total / z.size)
        outcome = _constrained_cg(operator, z, p, total=total, separation=None, tol=tol,
                                  max_iter=max_iter, ws=ws,
                                  preconditioner=preconditioner, settle=stiffness)
    else:
        if initial is not None and initial.any():
            p = _owned(initial)
        else:
            p = _separation_start(operator, z, separation, ws)
        outcome = _constrained_cg(operator, z, p, total=None, separation=separation, tol=tol,
                                  max_iter=max_iter, ws=ws,
                                  preconditioner=preconditioner, settle=stiffness)
    u = ws.take_displacement()
    p = outcome.pressure
    contact = p > 0.0
    if separation is None:
        d = float(np.mean((z - u)[contact]))
    else:
        d = separation
    return _record(operator, z, p, u, d, outcome, stiffness, ws, nominal_area, tol, warn)


def _coarse_start(operator: HalfSpace, z: np.ndarray, *, load: float | None,
                  separation: float | None, tol: float, max_iter: int,
                  previous: np.ndarray | None = None, ws: _Workspace | None = None
                  ) -> tuple[np.ndarray | None, np.ndarray | None]:
    """Nested iteration: the pressure of the same problem on every other grid point (the same
    continuous surface sampled at spacing 2h), interpolated onto the fine grid
    (:func:`bem.contact.nested_grid._prolonged`), and that coarse pressure.

    The coarse problem starts from ``previous`` (a coarse pressure, e.g. of the previous point
    of a load path) when given, else it is solved recursively the same way. ``ws`` is a
    workspace of the coarse grid to reuse. (None, None) when the grid is odd, its half is below
    ``bem.contact.nested_grid._COARSEST_GRID`` or the coarse problem has no contact.
    """
    if not _nestable(z.shape):
        return None, None
    heights = operator.xp.ascontiguousarray(z[::2, ::2])
    if operator.periodic and separation is not None and separation <= float(heights.mean()):
        return None, None  # full contact on the coarse grid: no load to start from
    coarse = operator.coarse()
    # an unconverged start is still a start: no warning (and no change of the process's
    # warning filters, which other threads share)
    solution = _solve(coarse, heights, load=load, separation=separation,
                      tol=max(tol, _COARSE_TOLERANCE),
                      max_iter=min(max_iter, _COARSE_MAX_ITERATIONS), initial=previous,
                      stiffness=False,
                      ws=_Workspace(coarse.shape, coarse.xp) if ws is None else ws,
                      warn=False)
    pressure = np.asarray(solution.pressure)
    if not pressure.any():
        return None, None
    return _prolonged(pressure, operator), pressure


def _owned(initial: np.ndarray) -> np.ndarray:
    """The start pressure to iterate on in place: ``initial`` itself (the callers hand over
    arrays they made), unless it is read-only, i.e. a previous result."""
    return initial if getattr(initial.flags, "writeable", True) else np.array(initial)


def _record(operator: HalfSpace, z: np.ndarray, p: np.ndarray, u: np.ndarray, d: float,
            outcome: _Outcome, stiffness: bool, ws: _Workspace,
            nominal_area: float, tol: float, warn: bool = True) -> ContactSolution:
    """The solution of a solved (or zero-load) state; with ``stiffness`` also the incremental
    stiffness (T26) to a residual of ``_STIFFNESS_SHARE * tol``."""
    pixel_area = operator.spacing**2
    contact = p > 0.0
    gap = d - z + u
    message = outcome.message
    converged = outcome.converged
    if not converged and warn:
        warnings.warn(f"bem.solve_contact: {message}", ConvergenceWarning, stacklevel=3)
    stiffness_value = None
    if stiffness:
        stiffness_value, stiffness_converged, stiffness_iterations = _stiffness(
            operator, contact, tol=max(_STIFFNESS_SHARE * tol, _STIFFNESS_FLOOR), max_iter=max(1000, 10 * max(z.shape)),
            preconditioner=(ws.inverse_kernel(operator, "double")
                            if ws.preconditioned else None),
            correction=ws.correction if ws.preconditioned else None)
        if not stiffness_converged:
            converged = False
            message += f"; stiffness solve not converged after {stiffness_iterations} iterations"
            warnings.warn(f"bem.solve_contact: stiffness solve not converged after "
                          f"{stiffness_iterations} iterations", ConvergenceWarning, stacklevel=3)
    load = float(p.sum()) * pixel_area
    p, u, gap, contact = (to_host(array) for array in (p, u, gap, contact))
    return ContactSolution(
        pressure=_frozen(p),
        displacement=_frozen(u),
        gap=_frozen(gap),
        contact=_frozen(contact),
        load=load,
        mean_pressure=load / nominal_area,
        area=contact_area(contact, operator.spacing, periodic=operator.wraps,
                          alpha=PERIMETER_COEFFICIENT[operator.periodic]),
        separation=float(d),
        mean_gap=float(gap.mean()),
        converged=bool(converged),
        iterations=int(outcome.iterations),
        residual=float(outcome.residual),
        message=message,
        stiffness=None if stiffness_value is None else float(stiffness_value),
        nominal_area=float(nominal_area),
        e_star=float(operator.e_star),
        pixel_area=float(np.count_nonzero(contact)) * pixel_area,
    )
