"""Frictionless normal contact of a rough surface with a rigid plane: constrained conjugate gradients.

The problem (THEORY.md, "The reference")
-----------------------------------------
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
made every 50 iterations and at the end. On rough surfaces the contact set changes in most
iterations: 1.25 to 1.8 products per iteration overall (benchmarks/bench_bem.py). Element-wise
work runs in place on preallocated arrays; inner products use numpy's reductions, not BLAS,
whose spinning threads stall the FFT threads.

Stiffness: the incremental problem on the converged contact set C, ``K_CC q = 1`` (unit rigid
approach) solved by conjugate gradients; ``S = -dW/dd = h^2 sum q``, and the conductance by
Barber's analogy ``C rho = 2 S / E*`` (THEORY.md, "Conventions").
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from bem import checks
from bem.area import contact_area

from bem.halfspace import HalfSpace
from bem.warnings import ConvergenceWarning

__all__ = ["ContactSolution", "solve_contact", "DEFAULT_TOLERANCE", "DEFAULT_MAX_ITERATIONS",
           "MINIMUM_GRID"]

#: Default ``tol`` of :func:`solve_contact` (relative pressure change, see its docstring).
DEFAULT_TOLERANCE = 1e-9
#: Default ``max_iter`` of :func:`solve_contact`.
DEFAULT_MAX_ITERATIONS = 5000
#: Smallest accepted grid side (points).
MINIMUM_GRID = 4
#: Exact recomputation of u = K p every this many iterations (bounds rounding drift).
_REFRESH_INTERVAL = 50
#: Relative residual of the conjugate-gradient stiffness solve.
_STIFFNESS_TOLERANCE = 1e-11


def _frozen(array: np.ndarray) -> np.ndarray:
    return checks.frozen_array(array, dtype=None)


@dataclass(frozen=True, eq=False)
class ContactSolution:
    """The converged (or last) state of a contact problem; all arrays are fresh and read-only.

    Attributes
    ----------
    pressure : numpy.ndarray
        Pixel pressures p >= 0 [pressure], indexed like the heights.
    displacement : numpy.ndarray
        Surface displacement u = K * p [length], positive into the body.
    gap : numpy.ndarray
        ``d - z + u`` [length]: >= 0 outside the contact set and zero on it, both to the
        solver's tolerance (the computed values are reported, not clipped).
    contact : numpy.ndarray of bool
        Contact set, ``pressure > 0``.
    load : float
        Total force W = h^2 sum p [force].
    mean_pressure : float
        W / A with A = (n h)^2 the nominal area [pressure].
    area : float
        Real contact area [length^2] by the default estimator of :mod:`bem.area` (the pixel
        count corrected for the staircase perimeter; ``pixel_area`` is the plain count).
    separation : float
        d [length] (module docstring for the reference plane). Given in separation control,
        ``mean over the contact set of (z - u)`` in load control; for zero load, ``max(z)``
        (first contact) unless a larger separation was given.
    mean_gap : float
        Mean of ``gap`` over the grid [length].
    converged : bool
        Whether the stopping rule of :func:`solve_contact` was met.
    iterations : int
        Conjugate-gradient iterations done.
    residual : float
        The last relative pressure change (the stopping rule's left-hand side).
    message : str
        How the iteration ended.
    stiffness : float or None
        Incremental normal stiffness S = -dW/dd [force/length] on the contact set, when asked for
        (``inf`` for full periodic contact).
    nominal_area : float
        A = (n h)^2 [length^2].
    e_star : float
        Composite modulus E* [pressure].
    pixel_area : float
        h^2 times the number of contact pixels [length^2] (what most codes report; its error
        is of the order of the perimeter times h, see :mod:`bem.area`).
    """

    pressure: np.ndarray
    displacement: np.ndarray
    gap: np.ndarray
    contact: np.ndarray
    load: float
    mean_pressure: float
    area: float
    separation: float
    mean_gap: float
    converged: bool
    iterations: int
    residual: float
    message: str
    stiffness: float | None = None
    nominal_area: float = 1.0
    e_star: float = 1.0
    pixel_area: float = math.nan

    @property
    def conductance(self) -> float | None:
        """``2 S / E*`` [length]: constriction conductance times resistivity (Barber's analogy)."""
        if self.stiffness is None:
            return None
        return 2.0 * self.stiffness / self.e_star

    @property
    def area_fraction(self) -> float:
        """Real over nominal contact area [-]."""
        return self.area / self.nominal_area


# ------------------------------------------------------------------------------------------------
# input checks


def _check_heights(heights) -> np.ndarray:
    try:
        z = np.array(heights, dtype=float, copy=True)
    except (TypeError, ValueError):
        raise ValueError("heights must be a 2-D array of real numbers") from None
    if z.ndim != 2:
        raise ValueError(f"heights must be a 2-D array, got {z.ndim} dimension(s)")
    if z.shape[0] != z.shape[1]:
        raise ValueError(f"heights must be a square grid (n x n), got shape {z.shape}")
    if z.shape[0] < MINIMUM_GRID:
        raise ValueError(f"heights must be at least {MINIMUM_GRID} x {MINIMUM_GRID}, "
                         f"got shape {z.shape}")
    if not np.all(np.isfinite(z)):
        raise ValueError("heights must be finite (no NaN or inf)")
    return z


def _check_problem(heights, spacing, e_star, tol, max_iter, periodic):
    """Checked (heights, spacing, e_star, tol, max_iter, periodic) of a contact problem."""
    z = _check_heights(heights)
    spacing = _check_real("spacing", spacing, positive=True)
    e_star = _check_real("e_star", e_star, positive=True)
    tol = _check_real("tol", tol, positive=True)
    if isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer)) or max_iter < 1:
        raise ValueError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    if not isinstance(periodic, (bool, np.bool_)):
        raise ValueError(f"periodic must be True or False, got {periodic!r}")
    return z, spacing, e_star, tol, int(max_iter), bool(periodic)


def _check_real(name: str, value, *, positive: bool = False, non_negative: bool = False) -> float:
    if positive:
        return checks.positive(name, value)
    return checks.real_number(name, value, minimum=0.0 if non_negative else None)


def _check_operator(operator, shape, spacing, e_star, periodic) -> HalfSpace:
    if operator is None:
        return HalfSpace(shape, spacing, e_star=e_star, periodic=periodic)
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
    if mismatch:
        raise ValueError("operator does not match the problem: " + "; ".join(mismatch))
    return operator


def _check_initial(initial, shape) -> np.ndarray | None:
    if initial is None:
        return None
    initial = np.array(initial, dtype=float, copy=True)
    if initial.shape != tuple(shape):
        raise ValueError(f"initial must have the heights' shape {tuple(shape)}, got {initial.shape}")
    if not np.all(np.isfinite(initial)):
        raise ValueError("initial must be finite (no NaN or inf)")
    np.maximum(initial, 0.0, out=initial)
    return initial


# ------------------------------------------------------------------------------------------------
# the constrained conjugate-gradient iteration


class _Workspace:
    """Preallocated arrays of one grid, reused by every iteration (and along a load path)."""

    def __init__(self, shape: tuple[int, int]) -> None:
        self.u = np.empty(shape)
        self.g = np.empty(shape)
        self.g_contact = np.empty(shape)
        self.t = np.zeros(shape)
        self.r = np.empty(shape)
        self.work = np.empty(shape)
        self.contact_weight = np.empty(shape)
        self.contact = np.empty(shape, dtype=bool)
        self.flag = np.empty(shape, dtype=bool)


@dataclass
class _Outcome:
    pressure: np.ndarray
    converged: bool
    iterations: int
    residual: float
    message: str


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    """Inner product of two arrays of one shape without BLAS.

    OpenBLAS worker threads keep spinning after a call and then compete with the FFT threads
    for the cores (a 60x slowdown of the next FFT measured here on 2 cores), so the iteration
    uses numpy's own reductions.
    """
    return float(np.einsum("ij,ij->", a, b))


def _constrained_cg(operator: HalfSpace, z: np.ndarray, p: np.ndarray, *, total: float | None,
                    separation: float | None, tol: float, max_iter: int,
                    ws: _Workspace) -> _Outcome:
    """Polonsky-Keer iteration from the start ``p >= 0`` (modified in place).

    ``total`` is the target ``sum p`` (load control; p must already sum to it), or
    ``separation`` is d (separation control). Returns with ``ws.u = K p`` exact.

    Implementation notes (each full-grid pass costs about a tenth of an FFT pair, so they are
    counted): the search direction t and its displacement r = K t live in the operator's FFT
    buffers (no copies around the product); t is saved around the occasional full product of p
    only when the next iteration needs it. In load control the sum of t follows the recurrence
    t <- beta t + gc (gc sums to zero) and is summed afresh only after a step that clipped
    pixels (t is then masked); sum p after the step follows from it and the few changed pixels
    when they are known.
    """
    load_control = total is not None
    u, g, gc, saved_t, work = ws.u, ws.g, ws.g_contact, ws.t, ws.work
    weight, contact, flag = ws.contact_weight, ws.contact, ws.flag
    t, r = operator._direction_buffers()
    flat_p, flat_g = p.reshape(-1), g.reshape(-1)
    direct_limit = operator.direct_source_limit
    if direct_limit:
        operator.centred_kernel  # noqa: B018 - build the influence coefficients once, up front
    operator._apply(p, u)
    reset = True        # next direction is the steepest descent one (beta = 0)
    shrunk = True       # the last step removed pixels from the contact set
    g_norm_old = 1.0
    residual = math.inf
    since_refresh = 0
    tau_fallback = None
    t_sum = 0.0
    flat_contact, flat_weight = contact.reshape(-1), weight.reshape(-1)
    stale = True        # contact / weight / n_contact must be recomputed from p
    n_contact = 0
    restarted = False   # separation control restarted after losing every contact
    for iteration in range(1, max_iter + 1):
        # contact set: recomputed after bulk changes, else kept up to date pixel by pixel
        if stale:
            np.greater(p, 0.0, out=contact)
            n_contact = int(np.count_nonzero(contact))
            np.copyto(weight, contact)
            stale = False
        # gap at the current state: g = u - z + d, d given or the mean of z - u on the contacts
        np.subtract(u, z, out=g)
        if load_control:
            g -= _dot(g, weight) / n_contact
        else:
            g += separation
        np.multiply(g, weight, out=gc)
        g_norm = _dot(gc, gc)
        # conjugate search direction on the contact set
        # t_sum = sum of t (zero outside the contact set); gc sums to zero in load control
        if reset or g_norm_old == 0.0:
            np.copyto(t, gc)
            t_sum = 0.0
        else:
            beta = g_norm / g_norm_old
            if shrunk:
                np.multiply(t, weight, out=t)
            t *= beta
            t += gc
            if load_control:
                t_sum = float(t.sum()) if shrunk else beta * t_sum
        g_norm_old = g_norm
        operator._transform_direction()  # r = K t
        rt = _dot(r, t)
        if t_sum != 0.0:
            rt -= _dot(r, weight) / n_contact * t_sum
        if rt > 0.0 and math.isfinite(rt):
            tau = _dot(gc, t) / rt
            tau_fallback = tau
        else:  # t = 0: the contact set is solved exactly; only new contacts may remain
            if tau_fallback is None:
                tau_fallback = 1.0 / operator.self_influence
            tau = tau_fallback
        step = gc  # the contact gap is not needed any more: reuse its buffer for tau t
        np.multiply(t, tau, out=step)
        p -= step
        # project on p >= 0 (boolean masks and counts are the cheap passes; ufuncs with
        # where= and float count_nonzero are 10-50x slower than a plain pass)
        np.less(p, 0.0, out=flag)
        clipped = int(np.count_nonzero(flag))
        sources = []  # (flat indices, values) of p_new / scale - (p_old - tau t), if few
        change = 0.0  # their sum
        if clipped:
            if clipped <= direct_limit:
                clipping = np.flatnonzero(flag)
                values = -flat_p[clipping]
                flat_p[clipping] = 0.0
                flat_contact[clipping] = False
                flat_weight[clipping] = 0.0
                n_contact -= clipped
                sources.append((clipping, values))
                change += float(values.sum())
            else:
                np.maximum(p, 0.0, out=p)
                stale = True
        # points outside the contact set that overlap enter it: p = 0 and g < 0
        np.less(g, 0.0, out=flag)
        if stale:
            np.logical_and(flag, p == 0.0, out=flag)
        else:
            np.greater(flag, contact, out=flag)  # g < 0 and not in contact
        entered = int(np.count_nonzero(flag))
        if entered:
            entering = np.flatnonzero(flag)
            values = -tau * flat_g[entering]
            flat_p[entering] = values
            flat_contact[entering] = True
            flat_weight[entering] = 1.0
            n_contact += entered
            sources.append((entering, values))
            change += float(values.sum())
        scale = 1.0
        if load_control:
            if clipped <= direct_limit:
                current = total - tau * t_sum + change
            else:
                current = float(p.sum())
            if current <= 0.0:  # everything was clipped: restart from a uniform pressure
                p.fill(total / p.size)
                operator._apply(p, u)
                reset = shrunk = stale = True
                continue
            scale = total / current
            p *= scale
        elif (n_contact == 0) if not stale else not p.any():
            # Separation control and the step clipped every pixel. The caller enters this loop
            # only when some point overlaps the plane (d < max z), so an empty contact set is an
            # overshoot (from a poor initial pressure, say), never the answer: restart once from
            # the interference start, and report failure if it happens again.
            if restarted:
                operator._apply(p, u)
                return _Outcome(p, False, iteration, math.inf,
                                "lost every contact although the plane overlaps the surface")
            restarted = True
            np.copyto(p, _separation_start(operator, z, separation, ws))
            operator._apply(p, u)
            reset = shrunk = stale = True
            continue
        reset, shrunk = entered > 0, clipped > 0
        # displacement of the new pressure, u = scale (u - tau K t + K e) with e the changes
        # made by the projection and the entering points: by direct sums when they are few,
        # otherwise (and every _REFRESH_INTERVAL iterations) by a full product
        since_refresh += 1
        if (clipped > direct_limit or clipped + entered > direct_limit
                or since_refresh >= _REFRESH_INTERVAL):
            if not reset:
                np.copyto(saved_t, t)
            operator._apply(p, u)  # overwrites the FFT buffers t and r
            if not reset:
                np.copyto(t, saved_t)
            since_refresh = 0
            stale = True  # resynchronise the contact set with p > 0
        else:
            np.multiply(r, tau, out=r)
            u -= r
            for indices, values in sources:
                operator._add_sources(indices, values, u, work)
            if scale != 1.0:
                u *= scale
        if clipped or entered:
            continue  # the contact set changed: not converged
        # stopping rule: relative pressure change; with an unchanged contact set the new
        # pressure is scale (p_old - tau t), so p - p_old = (1 - 1/scale) p - tau t
        if scale != 1.0:
            np.multiply(p, 1.0 - 1.0 / scale, out=work)
            np.subtract(work, step, out=work)
            np.abs(work, out=work)
            residual = float(work.sum()) / total
        else:
            np.abs(step, out=work)
            total_now = float(p.sum())
            residual = float(work.sum()) / total_now
        if residual <= tol:
            if since_refresh:
                operator._apply(p, u)
            return _Outcome(p, True, iteration, residual, "converged")
    operator._apply(p, u)
    return _Outcome(p, False, max_iter, residual,
                    f"not converged after {max_iter} iterations (relative pressure change "
                    f"{residual:.3g} > tol = {tol:.3g})")


def _separation_start(operator: HalfSpace, z: np.ndarray, separation: float,
                      ws: _Workspace) -> np.ndarray:
    """Start for separation control: the interference ``max(z - d, 0)`` as a pressure shape,
    scaled to minimise the energy along it (one half-space product)."""
    p = np.maximum(z - separation, 0.0)
    operator._apply(p, ws.u)
    curvature = _dot(p, ws.u)
    slope = _dot(p, z - separation)
    if curvature > 0.0:
        p *= slope / curvature
    return p


# ------------------------------------------------------------------------------------------------
# incremental stiffness


def _stiffness(operator: HalfSpace, contact: np.ndarray, *, tol: float, max_iter: int,
               ws: _Workspace) -> tuple[float, bool, int]:
    """Solve ``K_CC q = 1`` on the contact set C by conjugate gradients; ``S = h^2 sum q``.

    Stops when ``||1 - (K q)_C|| <= tol sqrt(|C|)``. Returns (S, converged, iterations).
    """
    n_contact = int(np.count_nonzero(contact))
    if n_contact == 0:
        return 0.0, True, 0
    if operator.periodic and n_contact == contact.size:
        return math.inf, True, 0
    weight = np.asarray(contact, dtype=float)
    q = weight / operator.self_influence
    product, work = ws.r, ws.work
    operator._apply(q, product)
    residual = weight - product * weight
    direction = residual.copy()
    rr = _dot(residual, residual)
    target = (tol**2) * n_contact
    iterations = 0
    converged = rr <= target
    while not converged and iterations < max_iter:
        iterations += 1
        operator._apply(direction, product)
        np.multiply(product, weight, out=product)
        step = rr / _dot(direction, product)
        np.multiply(direction, step, out=work)
        q += work
        np.multiply(product, step, out=work)
        residual -= work
        rr_new = _dot(residual, residual)
        converged = rr_new <= target
        direction *= rr_new / rr
        direction += residual
        rr = rr_new
    return float(q.sum()) * operator.spacing**2, converged, iterations


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
) -> ContactSolution:
    """Contact of a rough elastic surface with a rigid plane, at given load or separation.

    Constrained conjugate gradients (Polonsky & Keer 1999; separation control after Rey,
    Anciaux & Molinari 2017) on the boundary-element half-space of THEORY.md, "The reference".
    Conventions (gap, separation d, periodic mean plane): module docstring.

    Parameters
    ----------
    heights : array_like
        Heights z[j, i] [length] of the elastic surface on an n x n grid (n >= 4; row j is y,
        column i is x), as given: not re-centred. The rigid plane is above, at ``z = d``.
    spacing : float
        Grid step h [length]; the nominal area is ``A = (n h)^2``.
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

    Returns
    -------
    ContactSolution

    Notes
    -----
    Stopping rule: iteration k ends the solve when

        ``sum_ij |p_ij^(k) - p_ij^(k-1)| <= tol * sum_ij p_ij^(k)``

    and iteration k changed no contact pixel (none left the contact set by the projection
    ``p >= 0`` and no non-contact pixel with negative gap entered it). ``residual`` reports the
    left side over ``sum p``. The stiffness solve stops when ``||1 - (K q)_C||_2 <= 1e-11
    sqrt(|C|)``. Non-convergence gives ``converged=False``, a message and a
    :class:`bem.warnings.ConvergenceWarning`; the last iterate is returned.

    Raises
    ------
    ValueError
        For non-finite, non-square, non-2-D or smaller than 4 x 4 heights, spacing <= 0,
        e_star <= 0, negative load, both or neither of load/separation, a periodic separation
        <= mean(z), tol <= 0, max_iter < 1, a bad initial pressure or a mismatched operator.
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
    operator = _check_operator(operator, z.shape, spacing, e_star, periodic)
    return _solve(operator, z, load=load, separation=separation, tol=tol, max_iter=int(max_iter),
                  initial=initial, stiffness=stiffness, ws=_Workspace(z.shape))


def _solve(operator: HalfSpace, z: np.ndarray, *, load: float | None, separation: float | None,
           tol: float, max_iter: int, initial: np.ndarray | None, stiffness: bool,
           ws: _Workspace) -> ContactSolution:
    """The solve after validation (shared with the load path)."""
    pixel_area = operator.spacing**2
    nominal_area = z.size * pixel_area
    highest = float(z.max())
    zero_load = (load is not None and load == 0.0) or (separation is not None
                                                     and separation >= highest)
    if zero_load:
        d = highest if separation is None else separation
        p = np.zeros(z.shape)
        return _record(operator, z, p, np.zeros(z.shape), d, _Outcome(
            p, True, 0, 0.0, "zero load: no contact"), stiffness, ws, nominal_area)
    if load is not None:
        total = load / pixel_area
        if initial is not None and initial.sum() > 0.0:
            p = initial * (total / float(initial.sum()))
        else:
            p = np.full(z.shape, total / z.size)
        outcome = _constrained_cg(operator, z, p, total=total, separation=None, tol=tol,
                                  max_iter=max_iter, ws=ws)
    else:
        if initial is not None and initial.any():
            p = initial
        else:
            p = _separation_start(operator, z, separation, ws)
        outcome = _constrained_cg(operator, z, p, total=None, separation=separation, tol=tol,
                                  max_iter=max_iter, ws=ws)
    u = ws.u.copy()
    p = outcome.pressure
    contact = p > 0.0
    if separation is None:
        d = float(np.mean((z - u)[contact]))
    else:
        d = separation
    return _record(operator, z, p, u, d, outcome, stiffness, ws, nominal_area)


def _record(operator: HalfSpace, z: np.ndarray, p: np.ndarray, u: np.ndarray, d: float,
            outcome: _Outcome, stiffness: bool, ws: _Workspace,
            nominal_area: float) -> ContactSolution:
    pixel_area = operator.spacing**2
    contact = p > 0.0
    gap = d - z + u
    message = outcome.message
    converged = outcome.converged
    if not converged:
        warnings.warn(f"bem.solve_contact: {message}", ConvergenceWarning, stacklevel=3)
    stiffness_value = None
    if stiffness:
        stiffness_value, stiffness_converged, stiffness_iterations = _stiffness(
            operator, contact, tol=_STIFFNESS_TOLERANCE, max_iter=max(1000, 10 * z.shape[0]),
            ws=ws)
        if not stiffness_converged:
            converged = False
            message += f"; stiffness solve not converged after {stiffness_iterations} iterations"
            warnings.warn(f"bem.solve_contact: stiffness solve not converged after "
                          f"{stiffness_iterations} iterations", ConvergenceWarning, stacklevel=3)
    load = float(p.sum()) * pixel_area
    return ContactSolution(
        pressure=_frozen(p),
        displacement=_frozen(u),
        gap=_frozen(gap),
        contact=_frozen(contact),
        load=load,
        mean_pressure=load / nominal_area,
        area=contact_area(contact, operator.spacing, periodic=operator.periodic),
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
