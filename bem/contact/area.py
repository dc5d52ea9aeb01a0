"""Real contact area from a pixel solution: estimators with a small discretisation error
(docs/theory.md, "8.8 Contact-area estimation and error estimates", eq. T31).

Counting contact pixels (``h^2`` times their number, what most codes report) errs by about the
contact perimeter times the pixel size: the boundary of the discrete contact set is a staircase
that lies, on average, outside the true contact edge (the edge pixel is in contact as soon as
its centre is). The error decays only as ``h`` (first order) and reaches 4-11 % at 256 x 256 on
rough surfaces. The estimators here are pure functions of the solution fields:

* ``"pixels"``: ``A = h^2 n_C`` (n_C contact pixels).
* ``"perimeter"``: ``A = h^2 (n_C - alpha n_E)`` with n_E the number of contact/non-contact
  pixel pairs sharing an edge (the staircase perimeter in units of h). Yastrebov, Anciaux &
  Molinari (2017, Tribol. Int. 114, 161; arXiv:1701.02727) derive ``alpha = (pi - 1 + ln 2)/24``
  for an idealised contact edge; the solver's own edge pixels differ, so ``alpha`` is measured
  on contacts solved by this solver (:data:`PERIMETER_COEFFICIENT`, per kernel).
* ``"subpixel"``: the contact edge located between each contact pixel c and its non-contact
  neighbour n from the continuum asymptotics of a contact edge, pressure ``p = C s^(1/2)``
  inside and gap ``g = 4 C t^(3/2) / (3 E*)`` outside (plane strain), which give the edge at the
  distance ``a = x h`` from c with ``(1 - x)^3 = r x``, ``r = (3 E* g_n / (4 p_c h))^2``. The
  area of each row of pixels is then corrected by ``h^2 (x - 1/2)`` per crossing (midpoint rule
  along the row), likewise by columns, and the two estimates are averaged. It halves the pixel
  count's error but the solver's edge pixels do not follow the continuum asymptotics closely
  enough: 2-4 % at 256 x 256 on WM surfaces, against 0.8 % for ``"perimeter"``.

docs/guide/benchmarks.md ("Accuracy of the reference") tabulates their errors against converged values.
"""

from __future__ import annotations

import math

import numpy as np

from bem.common import checks

__all__ = [
    "AREA_ESTIMATORS",
    "DEFAULT_AREA_ESTIMATOR",
    "PERIMETER_COEFFICIENT",
    "YASTREBOV_COEFFICIENT",
    "contact_area",
    "contact_edges",
]

#: Names accepted by :func:`contact_area`.
AREA_ESTIMATORS = ("perimeter", "subpixel", "pixels")
#: The estimator of :attr:`bem.ContactSolution.area` and of :func:`bem.contact_curve`.
DEFAULT_AREA_ESTIMATOR = "perimeter"
#: alpha of Yastrebov, Anciaux & Molinari (2017): (pi - 1 + ln 2) / 24.
YASTREBOV_COEFFICIENT = (math.pi - 1.0 + math.log(2.0)) / 24.0
#: alpha of the default estimator, by kernel: non-periodic (Love, False) and periodic (True).
#: Least squares on Hertz contacts of radius 8-40 pixels solved by bem.solve_contact give 0.092
#: and 0.088 (benchmarks/bench_area.py --fit); on WM surfaces the alpha that makes the estimator
#: exact against converged areas is 0.102-0.126 (D = 2.95 ... 2.05, benchmarks/bench_area.py).
#: 0.100 keeps Hertz (radius 10 pixels) within 0.5 % and WM within 0.8 % at 256 x 256; the
#: periodic value keeps the Hertz difference between the kernels (not checked on WM surfaces).
PERIMETER_COEFFICIENT = {False: 0.100, True: 0.096}


def _check_contact(contact) -> np.ndarray:
    contact = np.asarray(contact)
    if contact.ndim != 2:
        raise ValueError(f"contact must be a 2-D boolean array, got {contact.ndim} dimension(s)")
    if contact.dtype != bool:
        raise TypeError(f"contact must be a boolean array, got dtype {contact.dtype}")
    return contact


def _edge_pairs(contact: np.ndarray, axis: int, periodic: bool) -> tuple[np.ndarray, np.ndarray]:
    """Boolean maps of the pixel pairs (i, i+1) along ``axis`` with exactly one in contact:
    ``first`` where i is the contact pixel, ``second`` where i+1 is (wrapping when periodic)."""
    following = np.roll(contact, -1, axis=axis) if periodic else (
        contact[1:, :] if axis == 0 else contact[:, 1:])
    current = contact if periodic else (contact[:-1, :] if axis == 0 else contact[:, :-1])
    return current & ~following, ~current & following


def contact_edges(contact, *, periodic: bool = False) -> int:
    """Number of contact/non-contact pixel pairs sharing an edge (4-neighbours) [-].

    The staircase perimeter of the contact set in units of the spacing; with ``periodic`` the
    pairs across opposite sides of the grid count, otherwise the grid's border is no edge.
    """
    contact = _check_contact(contact)
    return int(sum(int(np.count_nonzero(first)) + int(np.count_nonzero(second))
                   for first, second in (_edge_pairs(contact, axis, periodic) for axis in (0, 1))))


def _edge_fraction(pressure: np.ndarray, gap: np.ndarray, spacing: float,
                   e_star: float) -> np.ndarray:
    """x in [0, 1] with ``(1 - x)^3 = r x``, ``r = (3 E* g / (4 p h))^2`` (bisection, vectorised).

    The edge lies at x h from the contact pixel's centre towards the non-contact one.
    """
    p = np.maximum(pressure, 0.0)
    g = np.maximum(gap, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(p > 0.0, (0.75 * e_star * g / (p * spacing)) ** 2, np.inf)
    low, high = np.zeros_like(r), np.ones_like(r)
    for _ in range(40):
        middle = 0.5 * (low + high)
        above = (1.0 - middle) ** 3 > r * middle
        low = np.where(above, middle, low)
        high = np.where(above, high, middle)
    return 0.5 * (low + high)


def _subpixel_correction(contact, pressure, gap, spacing, e_star, periodic, axis) -> float:
    """Sum over the crossings along ``axis`` of (x - 1/2) [-] (area correction / h^2)."""
    first, second = _edge_pairs(contact, axis, periodic)
    shifted = (lambda a: np.roll(a, -1, axis=axis)) if periodic else (
        lambda a: a[1:, :] if axis == 0 else a[:, 1:])
    head = (lambda a: a) if periodic else (lambda a: a[:-1, :] if axis == 0 else a[:, :-1])
    total = 0.0
    # contact pixel first, non-contact after it; then the reverse
    for mask, inside, outside in ((first, head, shifted), (second, shifted, head)):
        if mask.any():
            x = _edge_fraction(inside(pressure)[mask], outside(gap)[mask], spacing, e_star)
            total += float(np.sum(x - 0.5))
    return total


def contact_area(contact, spacing: float, *, periodic: bool = False, estimator: str = DEFAULT_AREA_ESTIMATOR,
                 pressure=None, gap=None, e_star: float = 1.0,
                 alpha: float | None = None) -> float:
    """Real contact area [length^2] of a pixel contact solution by one of :data:`AREA_ESTIMATORS`.

    Parameters
    ----------
    contact : array_like of bool
        Contact set (``pressure > 0``), shape (n, n).
    spacing : float
        Pixel side h [length].
    periodic : bool
        Whether the grid is one period (edges across opposite sides count; the kernel's
        coefficient differs).
    estimator : str
        ``"perimeter"`` (default), ``"subpixel"`` or ``"pixels"`` (module docstring).
    pressure, gap : array_like, optional
        Pixel pressures [pressure] and gaps [length]; needed by ``"subpixel"`` only.
    e_star : float
        Composite modulus E* [pressure] (``"subpixel"``).
    alpha : float, optional
        Perimeter coefficient of ``"perimeter"``; default :data:`PERIMETER_COEFFICIENT` of the
        kernel.

    Returns
    -------
    float
        The area estimate, >= 0.
    """
    contact = _check_contact(contact)
    spacing = checks.positive("spacing", spacing)
    e_star = checks.positive("e_star", e_star)
    if estimator not in AREA_ESTIMATORS:
        raise ValueError(f"estimator must be one of {AREA_ESTIMATORS}, got {estimator!r}")
    cell = spacing**2
    count = float(np.count_nonzero(contact))
    if estimator == "pixels" or count == 0.0:
        return count * cell
    if estimator == "perimeter":
        alpha = PERIMETER_COEFFICIENT[bool(periodic)] if alpha is None else float(alpha)
        return max(count - alpha * contact_edges(contact, periodic=periodic), 0.0) * cell
    if pressure is None or gap is None:
        raise ValueError("the 'subpixel' estimator needs pressure and gap")
    pressure, gap = np.asarray(pressure, dtype=float), np.asarray(gap, dtype=float)
    if pressure.shape != contact.shape or gap.shape != contact.shape:
        raise ValueError(f"pressure and gap must have the contact's shape {contact.shape}")
    corrections = [_subpixel_correction(contact, pressure, gap, spacing, e_star, periodic, axis)
                   for axis in (0, 1)]
    return max(count + 0.5 * sum(corrections), 0.0) * cell
