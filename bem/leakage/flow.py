"""Leakage through the gap between contacting surfaces: Reynolds flow and the hydraulic aperture.

A thin film of incompressible fluid between the deformed surfaces flows, in the lubrication
(Reynolds) approximation, with the local flux ``q = -g^3 grad p / (12 mu)`` per unit width, where
g(x, y) is the gap. Mass conservation gives the steady Reynolds equation

    div(g^3 grad p) = 0                                           (docs/theory.md, eq. T41)

A pressure drop dp over the length L of the field along the flow drives a total flow Q through
its width W, and the field's effective hydraulic aperture h_eff is the uniform gap that would
carry the same flow (eq. T42):

    Q = W h_eff^3 dp / (12 mu L)

so a uniform gap h gives exactly h, and h_eff = 0 when no fluid path joins inlet and outlet
(docs/theory.md, "Reynolds leakage through the gap").

Discretisation (finite volumes on the pixel grid, eq. T43): every pixel is a cell of
conductivity k = g^3; neighbouring cells exchange the flux ``T (p_a - p_b)`` with the
harmonic-mean face conductance ``T = 2 k_a k_b / (k_a + k_b)`` (zero when either cell is in
contact, g = 0). For square pixels T does not depend on the spacing, and neither does h_eff.
The harmonic mean makes the scheme exact for a gap that varies only along the flow
(h_eff^3 = 1 / mean(1/g^3)) and, with the boundary rule below, for one that varies only across
it (h_eff^3 = mean g^3).

Boundary conditions. Non-periodic: the inlet and outlet pressures are imposed on the two edges of
the field normal to the flow, half a pixel outside the first and last cell centres, so a boundary
cell exchanges ``2 k (p_edge - p)`` with its edge; the two edges along the flow carry no flux.
Periodic: the pressure is ``p = -G x + p'`` with a mean gradient G and a fluctuation p' periodic
in both directions; the length L is the period.

Before the linear system is built, cells that cannot carry flow are removed: contact cells,
cells whose gap is at most :data:`CLOSED_GAP` of the largest (closed: their conductance is at
most 1e-18 of the widest cell's), and fluid clusters (4-connected, ``scipy.ndimage.label``)
that do not join inlet and outlet (non-periodic) or do not wind around the period along the
flow (periodic: a cluster connected to itself across the edges with a net shift of a nonzero
number of periods). What is left is a union of
spanning clusters whose matrix is symmetric positive definite (a periodic cluster's constant
null vector is removed by grounding one of its cells, which changes nothing since no flow
leaves a periodic cluster). No spanning cluster: h_eff is exactly 0.

The flow is read from the viscous dissipation ``Q dp = sum over faces T (dp_face)^2 / (12 mu)``
(boundary half-faces included), which the solution minimises, so its error is of second order
in the solver's error. The system is solved by sparse LU up to
:data:`bem.leakage.flow_solver.DIRECT_SOLVE_LIMIT` cells and by conjugate gradients preconditioned with
aggregation multigrid on the pixel grid above (:mod:`bem.leakage.flow_solver`).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from bem.common import checks
from bem.leakage.face_matrix import FaceMatrix
from bem.leakage.flow_faces import Faces
from bem.leakage.flow_solver import FlowStart, _solve_pressure, next_start
from bem.common.warnings import ConvergenceWarning

__all__ = ["CLOSED_GAP", "FLOW_DIRECTIONS", "hydraulic_aperture", "leakage_aperture", "spanning_cells"]

#: Directions of the pressure drop: along x (columns, axis 1) or y (rows, axis 0) of ``gap[j, i]``.
FLOW_DIRECTIONS = ("x", "y")
#: Gap, relative to the largest, at or below which a cell is closed (module docstring). Its
#: conductance g^3 would be at most 1e-18 of the widest cell's, so whatever flows through it is
#: beyond any measurement (and, for a largest gap of a micrometre, through less than an atom);
#: left open, such cells break the iterative solve: fifty contact-edge cells of a 2048^2 gap at
#: 22 % contact opened to 1e-12-1e-6 of the largest gap took it from 177 multigrid iterations
#: to no convergence in 2000 (an aperture 5700 times too large), as a contact solve can leave
#: them where its last iteration still moved the contact edge.
CLOSED_GAP = 1e-6

_FOUR_CONNECTED = np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], dtype=bool)


def _harmonic_mean(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``2 a b / (a + b)``, 0 where both are 0."""
    total = a + b
    return np.divide(2.0 * a * b, total, out=np.zeros_like(total), where=total > 0)


def _winding_clusters(labels: np.ndarray, count: int) -> np.ndarray:
    """Labels (1..count) of the clusters that wind around the torus along axis 1.

    ``labels`` are the clusters of the grid cut open along both edges. Crossing the axis-1 edge
    (last column to first) shifts the unwrapped position by one period, crossing the axis-0 edge
    by none along axis 1. A periodic cluster winds along axis 1 iff some closed path through it
    has a net shift, i.e. iff no "potential" phi (the period index of each open cluster) satisfies
    ``phi[b] = phi[a] + shift`` on every crossing a -> b. phi is built on a spanning forest of
    the crossings (breadth-first from a virtual root, node 0, joined to one node per periodic
    cluster; accumulated along the tree by pointer jumping) and every crossing is then checked.
    """
    import scipy.sparse.csgraph

    ends = [(labels[:, -1], labels[:, 0], 1), (labels[-1, :], labels[0, :], 0)]
    a = np.concatenate([e[0] for e in ends])
    b = np.concatenate([e[1] for e in ends])
    shift = np.concatenate([np.full(e[0].size, e[2]) for e in ends])
    keep = (a > 0) & (b > 0)
    a, b, shift = a[keep], b[keep], shift[keep]
    if a.size == 0:
        return np.empty(0, dtype=np.intp)
    nodes = count + 1
    graph = scipy.sparse.coo_array((np.ones(a.size), (a, b)), shape=(nodes, nodes)).tocsr()
    _, component = scipy.sparse.csgraph.connected_components(graph, directed=False)
    _, roots = np.unique(component[1:], return_index=True)
    roots = roots + 1
    # Forest edges in both orientations (with the shift's sign), and root edges from node 0.
    tail = np.concatenate([a, b, np.zeros(roots.size, dtype=a.dtype)])
    head = np.concatenate([b, a, roots])
    step = np.concatenate([shift, -shift, np.zeros(roots.size, dtype=shift.dtype)])
    forest = scipy.sparse.coo_array((np.ones(tail.size), (tail, head)),
                                    shape=(nodes, nodes)).tocsr()
    _, parent = scipy.sparse.csgraph.breadth_first_order(forest, 0, directed=True,
                                                         return_predecessors=True)
    parent[0] = 0   # every other node is reached: each component has an edge from node 0
    key = tail.astype(np.int64) * nodes + head
    order = np.argsort(key, kind="stable")
    tree_key = parent.astype(np.int64) * nodes + np.arange(nodes)
    position = np.minimum(np.searchsorted(key[order], tree_key), key.size - 1)
    found = key[order][position] == tree_key
    phi = np.where(found, step[order][position], 0)   # phi[i] - phi[parent[i]]
    ancestor = parent.copy()
    while np.any(ancestor != 0):
        phi = phi + phi[ancestor]
        ancestor = ancestor[ancestor]
    winding = phi[a] + shift != phi[b]
    return np.flatnonzero(np.isin(component, component[a[winding]]))


def spanning_cells(fluid, *, periodic: bool = False) -> np.ndarray:
    """Cells of the fluid clusters that carry flow along axis 1 (columns, x).

    Parameters
    ----------
    fluid : array_like of bool
        2-D map of the cells open to flow (gap > 0).
    periodic : bool
        False: the clusters (4-connected) that touch both the first and the last column.
        True: the clusters of the doubly periodic grid that wind around it along axis 1.

    Returns
    -------
    numpy.ndarray of bool
        Same shape as ``fluid``; all False when no cluster spans (no leakage).
    """
    import scipy.ndimage   # where used: a warm report imports this module, solves no flow

    fluid = np.asarray(fluid, dtype=bool)
    labels, count = scipy.ndimage.label(fluid, structure=_FOUR_CONNECTED)
    if count == 0:
        return np.zeros(fluid.shape, dtype=bool)
    if periodic:
        spanning = _winding_clusters(labels, count)
    else:
        spanning = np.intersect1d(labels[:, 0], labels[:, -1])
        spanning = spanning[spanning > 0]
    return np.isin(labels, spanning)


def _flow_system(k: np.ndarray, cells: np.ndarray, periodic: bool):
    """The finite-volume system ``A p = b`` of the spanning cells for a unit pressure drop along
    axis 1, and the faces to evaluate the dissipation on.

    Returns ``(A, b, faces, boundary)``: ``A`` held by its faces
    (:class:`bem.leakage.face_matrix.FaceMatrix`: one coefficient per face, not the compressed rows of
    its 20 million entries at 2048^2), ``faces`` the faces between cells for the dissipation
    (:class:`bem.leakage.flow_faces.Faces`: flux ``T (p_tail - p_head + drop)``, drop = the mean
    gradient's share when periodic) and ``boundary`` is ``(cell, conductance, edge_pressure)``
    for the half-faces to the inlet and outlet edges (empty when periodic).
    """
    import scipy.sparse
    import scipy.sparse.csgraph

    rows, columns = k.shape
    index = np.full(k.shape, -1, dtype=np.int32)
    unknowns = int(np.count_nonzero(cells))
    index[cells] = np.arange(unknowns, dtype=np.int32)
    drop = 1.0 / columns if periodic else 0.0   # G h: the mean-gradient drop across one face
    after = {}   # axis -> the coefficient -T of each unknown's face to the next cell
    faces = []   # (tail, head, conductance) per axis, for the diagonal, b and the grounding
    for axis in (1, 0):
        neighbour = np.roll(index, -1, axis=axis)
        t = _harmonic_mean(k, np.roll(k, -1, axis=axis))
        open_face = (index >= 0) & (neighbour >= 0) & (t > 0)
        if not periodic:   # no face across the grid's edges
            edge = [slice(None), slice(None)]
            edge[axis] = -1
            open_face[tuple(edge)] = False
        faces.append((index[open_face], neighbour[open_face], t[open_face]))
        t[~open_face] = 0.0
        after[axis] = -t[cells]
    del neighbour, t, open_face
    tail, head, t = (np.concatenate([face[part] for face in faces]) for part in range(3))
    diagonal = np.bincount(tail, t, unknowns) + np.bincount(head, t, unknowns)
    if periodic:
        # Ground one cell per cluster: the right-hand side sums to zero over a periodic cluster,
        # so the grounded cell's pressure is zero and the flow is unchanged.
        graph = scipy.sparse.coo_array((t, (tail, head)), shape=(unknowns, unknowns))
        _, cluster = scipy.sparse.csgraph.connected_components(graph, directed=False)
        _, grounded = np.unique(cluster, return_index=True)
        diagonal[grounded] *= 2.0
        del graph
    del tail, head, t
    tail, head, t = faces[0]   # (no drop along axis 0)
    rhs = np.bincount(head, t * drop, unknowns) - np.bincount(tail, t * drop, unknowns)
    del faces, tail, head, t
    if periodic:
        boundary = (np.empty(0, dtype=np.int32), np.empty(0), np.empty(0))
    else:
        inlet, outlet = index[:, 0][cells[:, 0]], index[:, -1][cells[:, -1]]
        t_in, t_out = 2.0 * k[:, 0][cells[:, 0]], 2.0 * k[:, -1][cells[:, -1]]
        diagonal += np.bincount(inlet, t_in, unknowns) + np.bincount(outlet, t_out, unknowns)
        rhs += np.bincount(inlet, t_in, unknowns)   # inlet pressure 1, outlet 0
        boundary = (np.concatenate([inlet, outlet]), np.concatenate([t_in, t_out]),
                    np.concatenate([np.ones(inlet.size), np.zeros(outlet.size)]))
    matrix = FaceMatrix(index, after[1], after[0], diagonal, periodic)
    return matrix, rhs, Faces(k, index, periodic, drop), boundary


def _dissipation(pressure: np.ndarray, faces: Faces, boundary,
                 scale: np.ndarray | None = None) -> float:
    """``sum T (dp_face)^2`` over the faces and the boundary half-faces (12 mu Q dp) for the
    unknowns' ``pressure`` (times ``scale`` when given: a Jacobi-scaled iterate's)."""
    cell, t_edge, edge_pressure = boundary
    edge_cells = pressure[cell] if scale is None else pressure[cell] * scale[cell]
    return float(faces.dissipation(pressure, scale)
                 + np.sum(t_edge * (edge_pressure - edge_cells) ** 2))



def hydraulic_aperture(gap, spacing: float, *, direction: str = "x",
                       periodic: bool = False) -> float:
    """Effective hydraulic aperture h_eff of a gap field: the exact Reynolds leakage reference.

    Solves the steady Reynolds equation div(g^3 grad p) = 0 on the pixel grid for a pressure
    drop dp along ``direction`` and returns the uniform gap that carries the same flow Q,
    ``Q = W h_eff^3 dp / (12 mu L)`` (docs/theory.md, "Reynolds leakage through the gap",
    eqs. T41-T44; discretisation and boundary conditions: module docstring). A uniform gap h
    gives exactly h; a gap varying only along the flow gives exactly
    ``(1 / mean(1/g^3))^(-1/3)``, one varying only across it ``mean(g^3)^(1/3)``.

    Parameters
    ----------
    gap : array_like
        Gap g[j, i] >= 0 [length] on a rectangular grid (row j is y, column i is x; at least
        2 x 2), 0 on contact; e.g. ``ContactSolution.gap`` with contact pixels set to 0.
    spacing : float
        Grid step h [length] (square pixels). h_eff does not depend on it; it is checked, and
        fixes the length L = (number of pixels along the flow) h and the width W likewise.
    direction : {"x", "y"}
        Direction of the pressure drop: along the columns (x, axis 1) or the rows (y, axis 0).
    periodic : bool
        False: pressures imposed on the inlet and outlet edges (half a pixel outside the
        boundary cell centres), no flux through the two edges along the flow. True: a mean
        pressure gradient with pressure fluctuations periodic in both directions (as on the
        periodic half-space of :func:`bem.solve_contact`).

    Returns
    -------
    float
        h_eff [length] >= 0; exactly 0.0 when no fluid path (4-connected cells with g > 0)
        joins inlet and outlet (non-periodic) or winds around the period along the flow
        (periodic).

    Raises
    ------
    ValueError
        ``gap`` not a 2-D array of finite numbers >= 0 of at least 2 x 2, ``spacing`` not a
        positive finite number, ``direction`` not "x" or "y", ``periodic`` not a bool.

    Notes
    -----
    Cost (one core, benchmarks/bench_leakage.py): a sparse LU factorisation up to
    :data:`bem.leakage.flow_solver.DIRECT_SOLVE_LIMIT` cells (128^2), above it the
    multigrid-preconditioned solve: about 0.2 s at 256^2, 0.3-0.9 s at 512^2, 2-12 s and under
    1 GB at 1024^2 (the longest on rough gaps at heavy contact).
    """
    return _flow_solution(gap, spacing, direction, periodic)[0]


def _flow_solution(gap, spacing: float, direction: str, periodic: bool,
                   start: FlowStart | None = None) -> tuple[float, FlowStart | None]:
    """:func:`hydraulic_aperture` and how it was solved (None where nothing was): the
    pressure, a map of the grid oriented along the flow (the transpose for ``"y"``) with NaN
    off the spanning cells, and the multigrid's iterations. ``start``, that of a neighbouring
    gap of the same grid and direction (e.g. the previous load's), is where the iterative solve
    begins and chooses the solver (:func:`bem.leakage.flow_solver._solve_pressure`)."""
    gap = checks.height_map("gap", gap, minimum=2)
    gap = checks.real_array("gap", gap, minimum=0.0)
    checks.positive("spacing", spacing)
    direction = checks.choice("direction", direction, FLOW_DIRECTIONS)
    periodic = checks.flag("periodic", periodic)
    largest = float(gap.max())
    if largest == 0.0:
        return 0.0, None
    # scaled to at most 1: no overflow for any unit; closed cells (CLOSED_GAP) carry nothing
    conductivity = np.where(gap > CLOSED_GAP * largest, (gap / largest) ** 3, 0.0)
    if direction == "y":   # (contiguous along the flow: the faces are walked row by row)
        conductivity = np.ascontiguousarray(conductivity.T)
    cells = spanning_cells(conductivity > 0.0, periodic=periodic)
    if not cells.any():
        return 0.0, None
    matrix, rhs, faces, boundary = _flow_system(conductivity, cells, periodic)
    try:
        pressure, iterations = _solve_pressure(matrix, rhs, cells, periodic,
                                               lambda p, scale=None: _dissipation(
                                                   p, faces, boundary, scale), start)
    except RuntimeError as error:   # a singular factor: cannot happen for spanning cells
        warnings.warn(f"hydraulic_aperture: the flow system could not be solved ({error})",
                      ConvergenceWarning, stacklevel=3)
        return math.nan, None
    rows, columns = conductivity.shape
    solved = np.full(cells.shape, np.nan)
    solved[cells] = pressure
    return (largest * float(np.cbrt(_dissipation(pressure, faces, boundary) * columns / rows)),
            next_start(solved, iterations, start))


def _mean_leak(apertures) -> float:
    """``((h_x^3 + h_y^3) / 2)^(1/3)``: the aperture of the mean leak rate (eq. T44)."""
    h_x, h_y = apertures
    return float(np.cbrt(0.5 * (h_x ** 3 + h_y ** 3)))


def leakage_aperture(gap, spacing: float, *, periodic: bool = False) -> float:
    """h_eff of a gap for flow along x and along y, averaged by leak rate [length].

    ``((h_x^3 + h_y^3) / 2)^(1/3)`` with h_x, h_y from :func:`hydraulic_aperture`: the aperture
    of the mean of the two leak rates (Q ~ h_eff^3), which on an isotropic surface estimates the
    same h_eff as either direction with half the variance from the surface's random layout
    (docs/theory.md, eq. T44). Zero only when neither direction leaks. This is the ``leakage``
    of a boundary-element :class:`bem.ContactCurve`.

    Parameters
    ----------
    gap, spacing, periodic
        As in :func:`hydraulic_aperture`.
    """
    return _mean_leak([hydraulic_aperture(gap, spacing, direction=direction, periodic=periodic)
                       for direction in FLOW_DIRECTIONS])
