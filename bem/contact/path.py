"""Load paths of the boundary-element reference as a :class:`bem.ContactCurve`."""

from __future__ import annotations

from dataclasses import replace
from typing import Callable, Iterable, Mapping

import numpy as np

from bem.contact.area import AREA_ESTIMATORS, DEFAULT_AREA_ESTIMATOR, contact_area, contact_edges
from bem.common.curve import ContactCurve, check_quantities
from bem.leakage.background_flow import QUEUED_CELLS, BackgroundLeakage
from bem.elastic.halfspace import HalfSpace
from bem.contact.nested_grid import _nestable, _prolonged, checked_coarse_pressures
from bem.contact.path_errors import error_estimates
from bem.common import checks
from bem.contact.solver import (DEFAULT_MAX_ITERATIONS, DEFAULT_TOLERANCE, ContactSolution, _check_problem,
                        _check_operator, _coarse_start, _solve,
                        _Workspace)

__all__ = ["contact_curve", "count_contacts"]

#: Contact spots are 4-connected: pixels sharing an edge belong to one spot.
_FOUR_CONNECTED = np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], dtype=bool)


def count_contacts(contact: np.ndarray, *, periodic: bool = False) -> int:
    """Number of connected contact spots of a 2-D contact map (booleans, or numbers 0 and 1).

    Pixels that share an edge belong to one spot (4-connectivity, ``scipy.ndimage.label``);
    pixels touching only at a corner do not. With ``periodic`` a spot that crosses the edge of
    the grid is counted once: spots touching across opposite edges are merged.
    """
    import scipy.ndimage   # where used: a warm report imports this module, solves nothing
    import scipy.sparse.csgraph

    contact = checks.boolean_map("contact", contact)
    periodic = checks.flag("periodic", periodic)
    labels, count = scipy.ndimage.label(contact, structure=_FOUR_CONNECTED)
    if not periodic or count < 2:
        return int(count)
    pairs = [np.stack((labels[:, -1], labels[:, 0])), np.stack((labels[-1, :], labels[0, :]))]
    edges = np.concatenate(pairs, axis=1)
    edges = edges[:, (edges[0] > 0) & (edges[1] > 0)]
    if edges.shape[1] == 0:
        return int(count)
    graph = scipy.sparse.coo_matrix(
        (np.ones(edges.shape[1]), (edges[0] - 1, edges[1] - 1)), shape=(count, count))
    merged, _ = scipy.sparse.csgraph.connected_components(graph, directed=False)
    return int(merged)


def _check_path(name: str, values, *, non_negative: bool) -> np.ndarray:
    return checks.contact_path(name, values, non_negative=non_negative)


#: Largest ratio of a point's load to the previous point's for which a path without nesting
#: starts from the previous pressure: a start rescaled from a much lighter load put the load on
#: the few pixels of its contact set, and on a 64^2 periodic grid the iteration stopped after 2
#: steps at a separation 5 % off (a load 31 times the previous one); the cold start agrees with
#: the nested path to 1e-16.
_WARM_LOAD_RATIO = 4.0


class _PathStarts:
    """Start pressures along a load path.

    Nested (the preconditioned solver): each point starts from the same load or separation
    solved on every other grid point, that coarse solve warm-started from the previous point's
    coarse pressure. A start from the previous fine pressure rescaled to the new load needed
    more fine iterations (527 against 448 on a 12-point WM path at 1024 x 1024, loads 1e-3 to
    3e-2): it overshoots the approach of the plane, and the contact set then takes longer to
    settle, while the coarse solve of the new load places the spots' edges to within a coarse
    pixel. Counting the coarse solves the two cost about the same (46.0 against 49.4 s on two
    shared cores); where the coarse pressures are at hand (``coarse_pressures``, below) the
    nested start is the cheaper. Without nesting (odd or small grids, the plain iteration) the
    previous fine pressure is the start.

    ``coarse_pressures`` (index -> pressure on every other grid point) are coarse solutions
    already at hand, those of the path's error estimate, which solves the same half-grid problems
    to the path's tolerance: they replace the coarse solves.
    """

    def __init__(self, operator: HalfSpace, z: np.ndarray, *, tol: float, max_iter: int,
                 nested: bool, coarse_pressures: dict[int, np.ndarray] | None = None) -> None:
        self._operator, self._z, self._tol, self._max_iter = operator, z, tol, max_iter
        self._nested = nested
        self._coarse_pressures = coarse_pressures or {}
        self._coarse_workspace = None
        self._coarse_pressure = None  # the previous point's coarse pressure
        self._pressure = None  # the previous point's pressure
        self._load = 0.0       # and its load

    def start(self, index: int, *, load: float | None, separation: float | None
              ) -> np.ndarray | None:
        """The start pressure of point ``index`` (None: the solver's own cold start)."""
        operator = self._operator
        coarse = self._coarse_pressures.pop(index, None)
        if self._nested and _nestable(operator.shape) and coarse is not None and coarse.any():
            self._coarse_pressure = coarse   # (the next coarse solve's start, if one is due)
            return _prolonged(coarse, operator)
        if self._nested and _nestable(operator.shape):
            if self._coarse_workspace is None:
                coarse_operator = operator.coarse()
                self._coarse_workspace = _Workspace(coarse_operator.shape, coarse_operator.xp)
            start, coarse = _coarse_start(operator, self._z, load=load, separation=separation,
                                          tol=self._tol, max_iter=self._max_iter,
                                          previous=self._coarse_pressure,
                                          ws=self._coarse_workspace)
            if start is not None:
                self._coarse_pressure = coarse
                return start
        if self._pressure is None or (load is not None
                                      and load > _WARM_LOAD_RATIO * self._load):
            return None
        return np.array(self._pressure)

    def solved(self, solution: ContactSolution) -> None:
        """Record a solved point."""
        if solution.load > 0.0:
            self._pressure, self._load = solution.pressure, solution.load


def contact_curve(
    heights,
    spacing: float,
    *,
    loads: Iterable[float] | None = None,
    separations: Iterable[float] | None = None,
    quantities: Iterable[str] = ("area", "load", "separation"),
    e_star: float = 1.0,
    periodic: bool = False,
    tol: float = DEFAULT_TOLERANCE,
    max_iter: int = DEFAULT_MAX_ITERATIONS,
    operator: HalfSpace | None = None,
    callback: Callable[[int, ContactSolution], None] | None = None,
    preconditioned: bool = True,
    area_estimator: str = DEFAULT_AREA_ESTIMATOR,
    error_estimate: bool = False,
    mirror: bool = False,
    device: str = "cpu",
    coarse_pressures: Mapping[int, np.ndarray] | None = None,
    stiffness_at: Iterable[int] | None = None,
) -> ContactCurve:
    """Boundary-element contact curve of one surface along loads or separations.

    The half-space operator is built once; the points are solved in the order of increasing
    load (increasing loads, or decreasing separations) and returned in the caller's order. Each
    point starts from its own problem solved on every other grid point, that coarse solve
    warm-started from the previous point's (preconditioned solver on even grids of at least
    128 points; otherwise from the previous point's pressure). See :func:`bem.solve_contact` for the
    conventions, the solver and the stopping rule.

    Parameters
    ----------
    heights : array_like
        Heights z[j, i] [length] on an N x M grid (as in :func:`bem.solve_contact`).
    spacing : float
        Grid step h [length]; nominal area ``N M h^2``.
    loads : array_like, optional
        Total forces W >= 0 [force] (load control).
    separations : array_like, optional
        Separations d [length] (separation control). Exactly one of ``loads``/``separations``.
    quantities : iterable of str
        Among ``"separation", "load", "area", "contacts", "stiffness", "conductance",
        "mean_pressure", "leakage"``. Separation, load, area and mean pressure come with every solve and are
        always filled. ``contacts`` counts connected contact spots
        (:func:`count_contacts`: 4-connected, merged across the edges when periodic).
        ``stiffness`` S = -dW/dd [force/length] and ``conductance`` 2 S / E* [length] cost one
        extra conjugate-gradient solve per point and are computed only when asked for.
        ``leakage`` h_eff [length] is the effective hydraulic aperture of the solved gap (zero
        on the contact set), the mean leak rate of flow along x and along y
        (:func:`bem.leakage.flow.leakage_aperture`), periodic or not as the contact problem; two
        sparse Reynolds solves per point, only when asked for, run in background threads
        (:class:`bem.leakage.background_flow.BackgroundLeakage`) while the next points are solved.
    e_star, periodic, tol, max_iter, operator, preconditioned
        As in :func:`bem.solve_contact`.
    callback : callable, optional
        ``callback(index, solution)`` after each solved point (``index`` in the caller's order),
        e.g. for progress reports or to keep pressure fields.
    area_estimator : str
        How the area is read from the contact set (:func:`bem.contact.area.contact_area`):
        ``"perimeter"`` (default), ``"subpixel"`` or ``"pixels"``.
    error_estimate : bool
        Also estimate each point's discretisation error
        (:func:`~bem.contact.path_errors.error_estimates`): the same heights sampled every second
        point (``heights[::2, ::2]``, spacing 2h, same window) are solved at the same loads or
        separations, first: their solutions are then the fine points' nested starts, which the
        path would otherwise solve again to a looser tolerance (16-point path at 512^2: the fine
        iterations unchanged, 3472 FFT pairs of all sizes against 4544 when the estimate came
        after the path).
    mirror : bool
        With ``periodic``: the heights are a quadrant of the period of their even (mirror)
        extension, solved on the quadrant by cosine transforms (:class:`bem.HalfSpace`
        ``mirror``): the periodic solution of :func:`bem.interface.mirror_extension` of the
        heights, per copy, at a quarter of its points; contact edges, patches and the flow do
        not wrap around.
    device : {"cpu", "gpu"}
        Where the contact problems are solved (:func:`bem.solve_contact`); the leakage's
        Reynolds solves stay on the CPU, in the background threads, either way.
    coarse_pressures : mapping, optional
        Pressures [pressure] already solved at some of the points on every other grid point
        (point index -> array of shape ``(N/2, M/2)``, the same problem on ``heights[::2,
        ::2]``, e.g. the path one grid below): those points start from them (interpolated)
        instead of a coarse solve of their own. Any pressure is a valid start; the solution
        agrees with the path's own to the solver's tolerance.
    stiffness_at : iterable of int, optional
        With ``stiffness`` or ``conductance`` among the quantities: the points (indices into
        ``loads`` or ``separations``) where their solve runs, NaN at the others (default: every
        point). The contact solves are the same either way.

    Returns
    -------
    ContactCurve
        With extras ``converged`` (bool array), ``iterations``, ``residual``, ``mean_gap``
        [length], ``pixel_area`` [length^2] (h^2 times the number of contact pixels) and
        ``staircase_perimeter`` [length] (h times the contact/non-contact pixel edges); with
        ``error_estimate`` also ``<quantity>_error`` for ``area``, ``separation``,
        ``mean_gap`` and, when computed, ``contacts``, ``stiffness``, ``conductance`` and
        ``leakage``
        (absolute, in the quantity's units); ``converged`` then requires both grids to have
        converged (an estimate from an unconverged half-grid solve is no certificate).

    Raises
    ------
    ValueError
        For bad heights, spacing, loads or separations (as :func:`bem.solve_contact`),
        unknown quantities, and coarse pressures of another shape or grid.
    """
    z, spacing, e_star, tol, max_iter, periodic = _check_problem(
        heights, spacing, e_star, tol, max_iter, periodic)
    quantities = check_quantities(quantities)
    area_estimator = checks.choice("area_estimator", area_estimator, AREA_ESTIMATORS)
    error_estimate = checks.flag("error_estimate", error_estimate)
    preconditioned = checks.flag("preconditioned", preconditioned)
    callback = checks.optional_callable("callback", callback)
    if error_estimate and (min(z.shape) < 8 or z.shape[0] % 2 or z.shape[1] % 2):
        raise ValueError(f"error_estimate needs an even grid, at least 8 x 8 (the half grid "
                         f"covers the same window), got {z.shape}")
    if (loads is None) == (separations is None):
        raise ValueError("give exactly one of loads (forces) and separations (lengths)")
    if loads is not None:
        targets = _check_path("loads", loads, non_negative=True)
        order = np.argsort(targets, kind="stable")
    else:
        targets = _check_path("separations", separations, non_negative=False)
        if periodic and np.any(targets <= z.mean()):
            raise ValueError(
                f"separations must exceed the mean height {float(z.mean())!r} for a periodic "
                f"surface (full contact, where the load is undetermined)")
        order = np.argsort(-targets, kind="stable")
    mirror = checks.flag("mirror", mirror)
    if mirror and not periodic:
        raise ValueError("mirror needs periodic=True (the extension's period is solved)")
    operator = _check_operator(operator, z.shape, spacing, e_star, periodic, mirror, device)
    wraps = operator.wraps
    want_stiffness = "stiffness" in quantities or "conductance" in quantities
    stiff = checks.point_mask("stiffness_at", stiffness_at, targets.size) & want_stiffness
    want_contacts = "contacts" in quantities
    want_leakage = "leakage" in quantities

    size = targets.size
    separation, load, area = np.empty(size), np.empty(size), np.empty(size)
    mean_gap, residual, pixel_area = np.empty(size), np.empty(size), np.empty(size)
    perimeter = np.empty(size)
    iterations = np.empty(size, dtype=int)
    converged = np.empty(size, dtype=bool)
    contacts = np.empty(size) if want_contacts else None
    stiffness = np.empty(size) if want_stiffness else None
    leakage = np.empty(size) if want_leakage else None
    coarse_pressures = checked_coarse_pressures(coarse_pressures, z.shape, targets.size,
                                                preconditioned)
    coarse = None
    if error_estimate:
        # The half grid first: its solutions are the nested starts of the fine points, which
        # would otherwise solve the same problems again to a looser tolerance (the error
        # estimate is the same path on every other grid point, with the fine operator's own
        # coarse level as its operator).
        keep = preconditioned and _nestable(z.shape)
        coarse = contact_curve(
            z[::2, ::2], 2.0 * spacing, quantities=quantities, e_star=e_star, periodic=periodic,
            mirror=mirror, tol=tol, max_iter=max_iter, area_estimator=area_estimator,
            preconditioned=preconditioned, operator=operator.coarse() if keep else None,
            device=device, stiffness_at=stiffness_at,
            callback=(lambda i, solution: coarse_pressures.__setitem__(i, solution.pressure))
            if keep else None,
            **({"loads": targets} if loads is not None else {"separations": targets}))
    workspace = _Workspace(z.shape, operator.xp)
    z_device = operator.xp.asarray(z)   # (numpy: z itself)
    starts = _PathStarts(operator, z_device, tol=tol, max_iter=int(max_iter), nested=preconditioned,
                         coarse_pressures=coarse_pressures)
    # The Reynolds solves of each point run in a background thread while the next points' contact
    # problems are solved (bem.leakage.background_flow): the path runs ahead of them by up to
    # QUEUED_CELLS of waiting gaps.
    flow = (BackgroundLeakage(spacing, periodic=wraps, pending=max(1, QUEUED_CELLS // z.size))
            if want_leakage else None)
    for index in order:
        target = float(targets[index])
        problem = {"load": target if loads is not None else None,
                   "separation": target if separations is not None else None}
        solution = _solve(operator, z_device, **problem, tol=tol, max_iter=int(max_iter),
                          initial=starts.start(int(index), **problem), stiffness=bool(stiff[index]),
                          ws=workspace, preconditioned=preconditioned)
        starts.solved(solution)
        separation[index] = solution.separation
        load[index] = solution.load
        area[index] = (solution.area if area_estimator == DEFAULT_AREA_ESTIMATOR else contact_area(
            solution.contact, spacing, periodic=wraps, estimator=area_estimator,
            pressure=solution.pressure, gap=solution.gap, e_star=e_star))
        pixel_area[index] = solution.pixel_area
        perimeter[index] = contact_edges(solution.contact, periodic=wraps) * spacing
        mean_gap[index] = solution.mean_gap
        residual[index] = solution.residual
        iterations[index] = solution.iterations
        converged[index] = solution.converged
        if want_contacts:
            contacts[index] = count_contacts(solution.contact, periodic=wraps)
        if want_stiffness:
            stiffness[index] = solution.stiffness if stiff[index] else np.nan
        if want_leakage:
            flow.submit(int(index), solution.fluid_gap)
        if callback is not None:
            callback(int(index), solution)
        del solution   # (not held through the next solve: 68 MB at 2048^2)
    # the contact solves' memory given back before the last Reynolds solves (0.3 GB at 2048^2)
    del operator, workspace, starts, z_device
    if want_leakage:
        for index, value in flow.results().items():
            leakage[index] = value
    nominal_area = z.size * spacing**2
    extras = {"converged": converged, "iterations": iterations, "residual": residual,
              "mean_gap": mean_gap, "pixel_area": pixel_area, "staircase_perimeter": perimeter}
    curve = ContactCurve(
        separation=separation,
        load=load,
        area=area,
        mean_pressure=load / nominal_area,
        nominal_area=nominal_area,
        e_star=e_star,
        contacts=contacts,
        stiffness=stiffness if "stiffness" in quantities else None,
        conductance=2.0 * stiffness / e_star if "conductance" in quantities else None,
        leakage=leakage,
        extras=extras,
    )
    if not error_estimate:
        return curve
    extras.update(error_estimates(curve, coarse, spacing))
    extras["converged"] = converged & coarse.extras["converged"]
    return replace(curve, extras=extras)
