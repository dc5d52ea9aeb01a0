"""Summits of a height map: the asperities of the GW and discrete asperity models.

docs/theory.md, "The discrete asperity model", step 1: asperities are the summits of the sampled
surface (grid points higher than their 8 neighbours), each with its position, height and radius
R = geometric mean of the principal radii of curvature (Greenwood's suggestion, the paper's
choice) from the local second derivatives.

Conventions: ``heights[j, i]`` is the height [length] at ``x = i * spacing``,
``y = j * spacing`` (row j is y, as :func:`validation.wm_surface` returns). Heights are measured
from the reference plane of the separation (the mean plane: subtract the mean first if needed);
summit heights are reported as given, never shifted.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from bem.common import checks
from bem.common.checks import frozen_array
from bem.common.checks import positive as _finite_positive

__all__ = ["Summits", "find_summits"]

_CURVATURES = ("geometric", "mean")





def _frozen(array, dtype) -> np.ndarray:
    return frozen_array(array, dtype).ravel()  # a view of a read-only array stays read-only


@dataclass(frozen=True, eq=False)
class Summits:
    """A set of asperity summits (one entry per summit in every array).

    Parameters
    ----------
    x, y : numpy.ndarray
        Positions [length]; distinct.
    height : numpy.ndarray
        Summit heights [length] above the reference (mean) plane.
    radius : numpy.ndarray
        Summit radii of curvature [length], > 0.
    area : float
        Nominal area A [length^2] the summits belong to (for a height map of ``shape`` rows x
        columns: ``rows * columns * spacing^2``, edges included).
    spacing : float or None
        Lattice spacing [length] when the summits lie on a lattice (grid points of a height map).
    shape : tuple of int or None
        Shape (rows, columns) of that lattice.
    row, column : numpy.ndarray of int or None
        Lattice indices (y and x) of the summits: ``x = column * spacing``,
        ``y = row * spacing``. They let interaction sums use an exact lattice FFT.
    periodic : bool
        The height map was periodic (summits found with wrap-around neighbours).
    curvature : {"geometric", "mean", "given"}
        How ``radius`` was obtained.
    neighbours : int or None
        4 or 8: the neighbourhood of the summit test (None for a user-supplied set).
    rejected_row, rejected_column : numpy.ndarray of int
        Lattice indices of local maxima that were *not* kept because their curvature is not
        convex (a principal curvature <= 0, e.g. a saddle-shaped or flat top on the grid).

    Notes
    -----
    Build it with :func:`find_summits` or :meth:`from_points`; both validate the input.
    """

    x: np.ndarray
    y: np.ndarray
    height: np.ndarray
    radius: np.ndarray
    area: float
    spacing: float | None = None
    shape: tuple[int, int] | None = None
    row: np.ndarray | None = None
    column: np.ndarray | None = None
    periodic: bool = False
    curvature: str = "given"
    neighbours: int | None = None
    rejected_row: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.intp))
    rejected_column: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.intp))

    def __post_init__(self) -> None:
        set_ = lambda name, value: object.__setattr__(self, name, value)  # noqa: E731
        for name in ("x", "y", "height", "radius"):
            set_(name, _frozen(checks.real_array(name, getattr(self, name), finite=False),
                               float))
        n = self.x.size
        for name in ("y", "height", "radius"):
            if getattr(self, name).size != n:
                raise ValueError(f"Summits {name} must have one entry per summit (the {n} "
                                 f"of x), got {getattr(self, name).size}")
        for name in ("x", "y", "height", "radius"):
            if not np.all(np.isfinite(getattr(self, name))):
                raise ValueError(f"Summits {name} must be finite (no NaN or inf)")
        if np.any(self.radius <= 0):
            raise ValueError("Summits radius must be > 0 for every summit")
        set_("area", _finite_positive("area", self.area))
        set_("curvature", checks.choice("curvature", self.curvature, _CURVATURES + ("given",)))
        set_("periodic", checks.flag("periodic", self.periodic))
        if n > 1:
            positions = np.column_stack((self.x, self.y))
            if np.unique(positions, axis=0).shape[0] != n:
                raise ValueError("Summits positions (x, y) must be distinct: found duplicates")
        if self.spacing is not None:
            set_("spacing", _finite_positive("spacing", self.spacing))
            if self.row is None or self.column is None:
                raise ValueError("Summits on a lattice (a spacing given) need row and column "
                                 "indices")
            set_("row", _frozen(self.row, np.intp))
            set_("column", _frozen(self.column, np.intp))
            if self.row.size != n or self.column.size != n:
                raise ValueError("Summits row and column must have one entry per summit")
            if self.shape is not None:
                set_("shape", (int(self.shape[0]), int(self.shape[1])))
        elif self.row is not None or self.column is not None:
            raise ValueError("Summits row/column indices need a lattice spacing")
        if self.periodic and (self.spacing is None or self.shape is None):
            raise ValueError("periodic summits need a lattice spacing and shape")
        set_("rejected_row", _frozen(self.rejected_row, np.intp))
        set_("rejected_column", _frozen(self.rejected_column, np.intp))

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_points(cls, x, y, height, radius, *, area: float,
                    spacing: float | None = None) -> "Summits":
        """A user-supplied summit set.

        Parameters
        ----------
        x, y, height, radius : array_like
            Positions [length], heights above the mean plane [length], radii [length] > 0.
        area : float
            Nominal area [length^2] (for the GW fit and the uniform interaction term).
        spacing : float, optional
            If given, every position must be an integer multiple of it (to 1e-9 relative):
            the summits are then put on that lattice, which makes interaction sums an exact FFT
            convolution (fast for 10^5 summits). Positions must then be >= 0.

        Raises
        ------
        ValueError
            Arrays of different lengths, non-finite values, radius <= 0, area <= 0, duplicate
            positions, or positions off the lattice.
        """
        if spacing is None:
            return cls(x, y, height, radius, area=area)
        spacing = _finite_positive("spacing", spacing)
        x = checks.real_array("x", x).ravel()
        y = checks.real_array("y", y).ravel()
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
            raise ValueError("Summits x and y must be finite (no NaN or inf)")
        column = np.rint(x / spacing)
        row = np.rint(y / spacing)
        if x.size and (np.max(np.abs(x - column * spacing)) > 1e-9 * max(spacing, np.abs(x).max())
                       or np.max(np.abs(y - row * spacing)) > 1e-9 * max(spacing,
                                                                        np.abs(y).max())):
            raise ValueError("with spacing, every position must be an integer multiple of it")
        if x.size and (row.min() < 0 or column.min() < 0):
            raise ValueError("with spacing, positions must be >= 0")
        row, column = row.astype(np.intp), column.astype(np.intp)
        shape = (int(row.max(initial=0)) + 1, int(column.max(initial=0)) + 1)
        return cls(column * spacing, row * spacing, height, radius, area=area, spacing=spacing,
                   shape=shape, row=row, column=column)

    # ------------------------------------------------------------------ storage
    def to_arrays(self) -> dict[str, np.ndarray]:
        """Plain arrays (no pickling needed, e.g. for ``np.savez``); inverse of
        :meth:`from_arrays`."""
        lattice = self.spacing is not None
        return {
            "x": np.array(self.x), "y": np.array(self.y), "height": np.array(self.height),
            "radius": np.array(self.radius), "area": np.array(self.area),
            "spacing": np.array(self.spacing if lattice else np.nan),
            "shape": np.array(self.shape if self.shape is not None else (-1, -1)),
            "row": np.array(self.row if lattice else np.zeros(0, dtype=np.intp)),
            "column": np.array(self.column if lattice else np.zeros(0, dtype=np.intp)),
            "periodic": np.array(self.periodic), "curvature": np.array(self.curvature),
            "neighbours": np.array(-1 if self.neighbours is None else self.neighbours),
            "rejected_row": np.array(self.rejected_row),
            "rejected_column": np.array(self.rejected_column),
        }

    @classmethod
    def from_arrays(cls, arrays) -> "Summits":
        """Rebuild a record written by :meth:`to_arrays` (validated like any other).

        ``arrays`` is a mapping (a dict, an ``np.load`` archive) with the entries of
        :meth:`to_arrays`; anything else is a :class:`TypeError`, a missing or malformed entry a
        :class:`ValueError`, naming ``arrays``.
        """
        if not isinstance(arrays, Mapping):
            raise checks.InputTypeError(f"arrays must be a mapping of the summit arrays (as "
                                        f"written by Summits.to_arrays), got "
                                        f"{type(arrays).__name__}")
        try:
            spacing = float(checks.real_array("arrays['spacing']", arrays["spacing"],
                                              finite=False))
            lattice = math.isfinite(spacing)
            shape = tuple(checks.integer_array("arrays['shape']", arrays["shape"]).tolist())
            neighbours = checks.integer("arrays['neighbours']", np.asarray(arrays["neighbours"]))
        except KeyError as missing:
            raise ValueError(f"summit arrays lack the entry {missing}") from None
        except (TypeError, ValueError) as error:
            raise ValueError(f"arrays holds a malformed entry: {error}") from None
        try:
            return cls(arrays["x"], arrays["y"], arrays["height"], arrays["radius"],
                       area=np.asarray(arrays["area"])[()], spacing=spacing if lattice else None,
                       shape=shape if shape[0] >= 0 else None,
                       row=arrays["row"] if lattice else None,
                       column=arrays["column"] if lattice else None,
                       periodic=np.asarray(arrays["periodic"])[()],
                       curvature=str(arrays["curvature"]),
                       neighbours=None if neighbours < 0 else neighbours,
                       rejected_row=arrays["rejected_row"],
                       rejected_column=arrays["rejected_column"])
        except KeyError as missing:
            raise ValueError(f"summit arrays lack the entry {missing}") from None

    # ------------------------------------------------------------------ statistics
    def __len__(self) -> int:
        return int(self.x.size)

    @property
    def count(self) -> int:
        """Number of summits N."""
        return int(self.x.size)

    @property
    def rejected(self) -> int:
        """Number of local maxima left out because their curvature is not convex."""
        return int(self.rejected_row.size)

    @property
    def density(self) -> float:
        """Summit density eta = N / A [1/length^2]."""
        return self.count / self.area

    def _fit(self, area):
        area = (self.area if area is None
                else checks.supported_magnitude("area", _finite_positive("area", area)))
        if self.count < 2:
            raise ValueError(f"a GW fit needs at least 2 summits, got {self.count}")
        sigma = float(np.std(self.height))
        if not sigma > 0:
            raise ValueError("a GW fit needs summit heights that are not all equal")
        return dict(density=self.count / area, radius=float(np.mean(self.radius)), sigma=sigma,
                    mean=float(np.mean(self.height)), area=area)

    def greenwood_williamson(self, area: float | None = None, *, e_star: float = 1.0):
        """The "original GW" fit of the paper (docs/theory.md, end of "Summits and their radii").

        eta = N / area, summit heights fitted by a Gaussian of mean mu_s and standard deviation
        sigma (the maximum-likelihood values: ``np.mean`` and ``np.std`` with ddof = 0), R the
        mean summit radius.

        Parameters
        ----------
        area : float, optional
            Nominal area [length^2]; default :attr:`area`.
        e_star : float
            Composite modulus E* [pressure].

        Returns
        -------
        asperity.GreenwoodWilliamson
        """
        from asperity.gw.greenwood_williamson import GreenwoodWilliamson
        return GreenwoodWilliamson(**self._fit(area), e_star=e_star)

    def improved_greenwood_williamson(self, area: float | None = None, m: float = 1.0, *,
                                      e_star: float = 1.0):
        """The same fit for the improved GW theory with uniform interaction (eq. 2), factor m."""
        from asperity.gw.greenwood_williamson import ImprovedGreenwoodWilliamson
        return ImprovedGreenwoodWilliamson(**self._fit(area), e_star=e_star, m=m)


def find_summits(heights, spacing: float, *, neighbours: int = 8, periodic: bool = False,
                 curvature: str = "geometric") -> Summits:
    """Find the summits of a height map and their radii of curvature.

    Parameters
    ----------
    heights : array_like
        Height map [length], 2-D, at least 3 x 3, finite; ``heights[j, i]`` at
        ``x = i * spacing``, ``y = j * spacing``.
    spacing : float
        Grid spacing [length], > 0.
    neighbours : {8, 4}
        A summit is higher than its 8 neighbours (the paper's definition) or its 4 edge
        neighbours.
    periodic : bool
        Wrap-around neighbours (every grid point is a candidate). Otherwise the edge rows and
        columns are never summits (their neighbourhood is incomplete).
    curvature : {"geometric", "mean"}
        ``"geometric"`` (default, the paper's choice, Greenwood's suggestion):
        ``R = sqrt(R1 R2) = 1 / sqrt(k1 k2)``; ``"mean"``: from the mean curvature,
        ``R = 2 / (k1 + k2)``.

    Returns
    -------
    Summits
        In row-major order of the grid.

    Notes
    -----
    *Summit test and ties.* A grid point is a summit when, for every neighbour, it is higher, or
    equally high and earlier in row-major order (smaller row j, then smaller column i; flat
    index ``j * columns + i``, wrapped indices when periodic). This strict total order makes the
    rule deterministic: of two equal neighbouring maxima exactly the first is a summit, and a flat
    plateau never yields two adjacent summits.

    *Curvature.* Second derivatives by central differences at the summit::

        z_xx = (z[j, i+1] - 2 z[j, i] + z[j, i-1]) / h^2       (likewise z_yy)
        z_xy = (z[j+1, i+1] - z[j+1, i-1] - z[j-1, i+1] + z[j-1, i-1]) / (4 h^2)

    (exact for any quadratic, so a sampled paraboloid gives its radius exactly, including a
    rotated elliptic one). The principal curvatures k1 >= k2 are the eigenvalues of minus the
    Hessian: ``k1 k2 = z_xx z_yy - z_xy^2`` and ``k1 + k2 = -(z_xx + z_yy)``.

    *Non-convex summits.* A summit of the grid test whose smaller principal curvature is <= 0
    (``k1 k2 <= 0`` or ``k1 + k2 <= 0``: a saddle-like or flat top, which has no Hertzian
    radius) is not kept in the arrays; its lattice indices are in ``rejected_row`` and
    ``rejected_column`` (count :attr:`Summits.rejected`). The same rule applies to both
    ``curvature`` choices, so the summit set does not depend on it.

    Raises
    ------
    ValueError
        Non-2-D or smaller than 3 x 3 heights, non-finite heights, spacing not finite and > 0,
        ``neighbours`` not 4 or 8, unknown ``curvature``.
    """
    z = checks.height_map("heights", heights)
    spacing = checks.supported_magnitude("spacing", _finite_positive("spacing", spacing))
    neighbours = checks.choice("neighbours", neighbours, (4, 8))
    curvature = checks.choice("curvature", curvature, _CURVATURES)
    periodic = checks.flag("periodic", periodic)
    rows, columns = z.shape

    # Candidate points and their flat indices.
    if periodic:
        j0, j1, i0, i1 = 0, rows, 0, columns
    else:
        j0, j1, i0, i1 = 1, rows - 1, 1, columns - 1
    J = np.arange(j0, j1)[:, None]
    I = np.arange(i0, i1)[None, :]
    centre = z[j0:j1, i0:i1]
    own = J * columns + I
    offsets = [(-1, 0), (1, 0), (0, -1), (0, 1)]
    if neighbours == 8:
        offsets += [(-1, -1), (-1, 1), (1, -1), (1, 1)]
    summit = np.ones(centre.shape, dtype=bool)
    for dj, di in offsets:
        nj = (J + dj) % rows
        ni = (I + di) % columns
        other = z[nj, ni]
        summit &= (centre > other) | ((centre == other) & (own < nj * columns + ni))
    jj, ii = np.nonzero(summit)
    jj = jj + j0
    ii = ii + i0

    # Differences of heights divided by their largest magnitude: curvatures in units of
    # scale / h^2, so that neither squaring them nor dividing by h^2 over- or underflows.
    scale = float(np.max(np.abs(z))) or 1.0

    def at(dj, di):
        return z[(jj + dj) % rows, (ii + di) % columns] / scale

    h2 = spacing * spacing
    centre_values = z[jj, ii]
    centre_scaled = centre_values / scale
    z_xx = at(0, 1) - 2.0 * centre_scaled + at(0, -1)
    z_yy = at(1, 0) - 2.0 * centre_scaled + at(-1, 0)
    z_xy = (at(1, 1) - at(1, -1) - at(-1, 1) + at(-1, -1)) / 4.0
    gaussian = z_xx * z_yy - z_xy * z_xy          # k1 k2 (h^2 / scale)^2
    curvature_sum = -(z_xx + z_yy)                # (k1 + k2) h^2 / scale
    convex = (gaussian > 0) & (curvature_sum > 0)
    if curvature == "geometric":
        radius = (h2 / scale) / np.sqrt(gaussian[convex])
    else:
        radius = 2.0 * (h2 / scale) / curvature_sum[convex]
    keep_j, keep_i = jj[convex], ii[convex]
    return Summits(
        x=keep_i * spacing, y=keep_j * spacing, height=centre_values[convex], radius=radius,
        area=rows * columns * h2, spacing=spacing, shape=(rows, columns), row=keep_j,
        column=keep_i, periodic=bool(periodic), curvature=curvature, neighbours=neighbours,
        rejected_row=jj[~convex], rejected_column=ii[~convex],
    )
