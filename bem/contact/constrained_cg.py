"""The constrained conjugate-gradient iteration of the contact problem (Polonsky & Keer 1999).

Load control minimises the elastic energy ``(1/2) p.Kp - p.z`` over ``p >= 0`` at fixed
``sum p`` (d is the Lagrange multiplier, ``d = mean over the contact set of (z - u)``);
separation control minimises ``(1/2) p.Kp + p.(d - z)`` over ``p >= 0`` (Rey, Anciaux &
Molinari 2017). Conventions: :mod:`bem.contact.solver`.

Preconditioning (:mod:`bem.contact.preconditioner`): the gap on the contact set C is multiplied by
``P_C M P_C`` with M the inverse symbol ``(E*/2)|q|`` of the half-space, P_C the restriction to C
(and, in load control, the projection to zero sum on C), so the conjugate gradients on C see a
nearly grid-independent spectrum. Pixels off C that overlap (negative gap) join C at zero
pressure at the start of an iteration, before the gap is preconditioned: C is then the free set
of the projected gradient, and the preconditioned direction and its line search size the
pressure the joining pixels take (the plain iteration's rule, entering after the step with the
pressure ``-tau g``, took 1.2-2.2x the iterations at 11-76 % contact with the preconditioner,
measured on 512^2 and 1024^2 scans). The direction is kept across changes of C (t is zero on
the pixels that joined) and restarts from the preconditioned gradient whenever it is not a
descent direction. On grids of at least :data:`bem.contact.coarse_correction.TWO_LEVEL_GRID` points
M gets a coarse correction once C has settled (:class:`bem.contact.coarse_correction.SettlingCorrection`).
The plain Polonsky-Keer iteration (``preconditioner=None``) enters pixels after the step and
restarts from steepest descent whenever they enter.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bem.common.vectors import _dot
from bem.contact.cg_buffers import _Scatter, _Workspace
from bem.contact.coarse_correction import TWO_LEVEL_GRID, SettlingCorrection
from bem.elastic.halfspace import HalfSpace
from bem.contact.preconditioner import InverseKernel

#: Exact recomputation of u = K p every this many iterations (bounds rounding drift).
_REFRESH_INTERVAL = 50


@dataclass
class _Outcome:
    pressure: np.ndarray
    converged: bool
    iterations: int
    residual: float
    message: str


class _ContactSet:
    """The contact set C as flat grid indices with its positions in the FFT buffers, and the
    fields that live on it (compressed: one value per contact pixel)."""

    def __init__(self, indices: np.ndarray, operator_in: _Scatter, operator_out: _Scatter,
                 preconditioner_in: _Scatter | None) -> None:
        self.operator_in, self.operator_out = operator_in, operator_out
        self.preconditioner_in = preconditioner_in
        self.set(indices)

    def set(self, indices: np.ndarray) -> None:
        self.indices = indices
        self.size = int(indices.size)
        self.at_operator_in = self.operator_in.positions(indices)
        self.at_operator_out = (self.at_operator_in if self.operator_out.row_stride
                                == self.operator_in.row_stride
                                else self.operator_out.positions(indices))
        self.at_preconditioner = (None if self.preconditioner_in is None
                                  else self.preconditioner_in.positions(indices))


def _constrained_cg(operator: HalfSpace, z: np.ndarray, p: np.ndarray, *, total: float | None,
                    separation: float | None, tol: float, max_iter: int,
                    ws: _Workspace, preconditioner: InverseKernel | None = None,
                    settle: bool = False) -> _Outcome:
    """Polonsky-Keer iteration from the start ``p >= 0`` (modified in place).

    ``total`` is the target ``sum p`` (load control; p must already sum to it), or
    ``separation`` is d (separation control). Returns with ``ws.u = K p`` exact. With a
    ``preconditioner`` the direction is built from ``P M gc`` instead of the contact gap gc,
    and overlapping pixels join C before the step (module docstring). With ``settle`` the
    solve also waits for an iteration that changes no contact pixel (the stiffness solve after
    it freezes C, and one pixel more or less moves a small patch's stiffness by more than the
    tolerance).

    Implementation notes: the pressure, the gap on C, the search direction t, its
    preconditioned version and the product r = K t on C are kept compressed, one value per
    contact pixel (C is a few per cent of the grid on most of a load path), and written into or
    read from the FFT buffers at C's positions only (:class:`_Scatter`). Full-grid passes are
    left only where the whole grid matters: the gap ``u - z`` and its sign (pixels joining C),
    and the update of u. The iteration is the same as on full arrays.
    """
    load_control = total is not None
    xp = operator.xp
    u, g, flag = ws.u, ws.g, ws.flag
    columns = z.shape[1]
    flat_g, flat_p = g.reshape(-1), p.reshape(-1)
    op_in_flat, op_out_flat, op_stride = operator._flat_direction_buffers()
    operator_in = _Scatter(op_in_flat, op_stride, columns)
    operator_out = _Scatter(op_out_flat, op_stride, columns)
    preconditioner_in = None
    if preconditioner is not None:
        preconditioner_in = _Scatter(preconditioner.input_block.reshape(-1), columns, columns)
    direct_limit = operator.direct_source_limit
    if direct_limit:
        operator.influence  # noqa: B018 - build the influence coefficients once, up front
    contact = _ContactSet(np.flatnonzero(flat_p > 0.0), operator_in, operator_out,
                          preconditioner_in)
    pressure = flat_p[contact.indices]
    ws.correction = None
    two_level = (SettlingCorrection(operator)
                 if preconditioner is not None and xp is np and z.size >= TWO_LEVEL_GRID
                 else None)
    clipped = 0

    def product(values: np.ndarray) -> np.ndarray:
        """K applied to ``values`` on C: the full-grid displacement (the operator's output)."""
        operator_in.write(contact.at_operator_in, values)
        operator._transform_direction()
        return operator._direction_buffers()[1]

    def refresh() -> None:
        """u = K p exactly."""
        u[...] = product(pressure)

    def start_from(full: np.ndarray) -> np.ndarray:
        contact.set(np.flatnonzero(full.reshape(-1) > 0.0))
        return full.reshape(-1)[contact.indices]

    refresh()
    reset = True        # next direction is the steepest descent one (beta = 0)
    g_norm_old = 1.0
    residual = math.inf
    since_refresh = 0
    tau_fallback = None
    direction = xp.zeros(0)
    t_sum = 0.0
    restarted = False   # separation control restarted after losing every contact
    for iteration in range(1, max_iter + 1):
        indices = contact.indices
        # gap at the current state: g = u - z + d, d given or the mean of z - u on the contacts;
        # g itself holds u - z, and ``shift`` is what the gap adds to it
        np.subtract(u, z, out=g)
        gc = flat_g[indices]
        shift = -float(gc.mean()) if load_control else separation
        joined = 0
        if preconditioner is not None:
            # the free set of the projected gradient: pixels off C that overlap join C at zero
            # pressure before the step, which the preconditioned direction then sizes
            joining = _overlapping(g, shift, flag, indices)
            joined = int(joining.size)
            if joined:
                indices = np.concatenate((indices, joining))
                pressure = np.concatenate((pressure, xp.zeros(joined)))
                direction = np.concatenate((direction, xp.zeros(joined)))
                contact.set(indices)
                gc = flat_g[indices]
                shift = -float(gc.mean()) if load_control else separation
        gc += shift
        if preconditioner is None:
            g_norm = _dot(gc, gc)
            descent = gc
        else:
            if two_level is not None and two_level.update(indices, joined + clipped, g_norm_old):
                operator_in.forget()   # (its product wrote the whole operator input)
                reset = True
            correction = ws.correction = None if two_level is None else two_level.correction
            projected, sums = (gc, None) if correction is None else correction.before(gc)
            preconditioner_in.write(contact.at_preconditioner, projected)
            preconditioner.execute()
            descent = preconditioner.read(contact.at_preconditioner)
            if correction is not None:
                descent = correction.after(descent, sums)
            if load_control:
                descent -= descent.mean()
            g_norm = _dot(gc, descent)
        # conjugate search direction on the contact set (t is zero on pixels that just joined
        # and was dropped on those that left)
        if reset or g_norm_old == 0.0:
            direction = descent.copy()
            t_sum = 0.0  # (the descent sums to zero in load control)
        else:
            direction *= g_norm / g_norm_old
            direction += descent
            t_sum = float(direction.sum()) if load_control else 0.0
        g_norm_old = g_norm
        slope = _dot(gc, direction)
        if slope < 0.0:  # not a descent direction (a kept direction after joining pixels)
            direction = descent.copy()
            t_sum = 0.0
            slope = g_norm
        r = product(direction)  # r = K t
        r_contact = op_out_flat[contact.at_operator_out]
        rt = _dot(r_contact, direction)
        if load_control and t_sum != 0.0:
            rt -= float(r_contact.sum()) / contact.size * t_sum
        if rt > 0.0 and math.isfinite(rt):
            tau = tau_fallback = slope / rt
        else:  # t = 0: the contact set is solved exactly; only new contacts may remain
            if tau_fallback is None:
                tau_fallback = 1.0 / operator.self_influence
            tau = tau_fallback
        step = direction * tau
        pressure -= step
        # project on p >= 0: pixels with negative pressure leave C
        negative = pressure < 0.0
        clipped = int(np.count_nonzero(negative))
        sources = []  # (flat indices, values) of p_new / scale - (p_old - tau t), if few
        left = 0.0    # sum of the pressure the pixels leaving C held (T25's change there)
        if clipped:
            left = float((pressure[negative] + step[negative]).sum())
            if clipped <= direct_limit:
                sources.append((indices[negative], -pressure[negative]))
            kept = ~negative
            indices, pressure, direction = indices[kept], pressure[kept], direction[kept]
            step = step[kept]
        # plain iteration: points outside the contact set that overlap enter it (g < 0 off C)
        # with the pressure the step gives them
        entering = None if preconditioner is not None else _overlapping(g, shift, flag, indices)
        entered = 0 if entering is None else int(entering.size)
        if entered:
            values = -tau * (flat_g[entering] + shift)
            sources.append((entering, values))
            indices = np.concatenate((indices, entering))
            pressure = np.concatenate((pressure, values))
            direction = np.concatenate((direction, xp.zeros(entered)))
        if clipped or entered:
            contact.set(indices)
        scale = 1.0
        if load_control:
            current = float(pressure.sum())
            if current <= 0.0:  # everything was clipped: restart from a uniform pressure
                p.fill(total / p.size)
                pressure = start_from(p)
                refresh()
                reset = True
                continue
            scale = total / current
            pressure *= scale
        elif contact.size == 0:
            # Separation control and the step clipped every pixel. The caller enters this loop
            # only when some point overlaps the plane (d < max z), so an empty contact set is an
            # overshoot (from a poor initial pressure, say), never the answer: restart once from
            # the interference start, and report failure if it happens again.
            if restarted:
                refresh()
                return _Outcome(_scattered(p, contact, pressure), False, iteration, math.inf,
                                "lost every contact although the plane overlaps the surface")
            restarted = True
            pressure = start_from(_separation_start(operator, z, separation, ws))
            operator_in.forget()  # (the start's product wrote the whole operator input)
            refresh()
            reset = True
            continue
        # Polonsky-Keer restart from steepest descent when pixels enter (the preconditioned
        # iteration keeps its direction, zero on the pixels that joined; a non-descent direction
        # still restarts, above)
        reset = entered > 0
        # displacement of the new pressure, u = scale (u - tau K t + K e) with e the changes
        # made by the projection and the entering points (pixels that joined at zero pressure
        # change nothing): by direct sums when they are few, otherwise (and every
        # _REFRESH_INTERVAL iterations) by a full product
        since_refresh += 1
        if (clipped > direct_limit or clipped + entered > direct_limit
                or since_refresh >= _REFRESH_INTERVAL):
            refresh()
            since_refresh = 0
        else:
            np.multiply(r, tau, out=r)
            u -= r
            for source_indices, values in sources:
                operator._add_sources(source_indices, values, u, ws.work)
            if scale != 1.0:
                u *= scale
        # stopping rule (T25): the relative pressure change over every pixel, those that joined
        # or left C included (Polonsky & Keer's rule). Where C kept a pixel its new pressure is
        # scale (p_old - tau t), so p - p_old = (1 - 1/scale) p - tau t; a pixel that left held
        # p_old (``left``), one that entered after the step (at the end of ``pressure``) holds p.
        kept = step.size
        entering_pressure = float(pressure[kept:].sum()) if entered else 0.0
        if scale != 1.0:
            change = pressure[:kept] * (1.0 - 1.0 / scale)
            change -= step
            residual = (float(np.abs(change).sum()) + left + entering_pressure) / total
        else:
            residual = ((float(np.abs(step).sum()) + left + entering_pressure)
                        / float(pressure.sum()))
        if residual <= tol and not (settle and (clipped or entered or joined)):
            if since_refresh:
                refresh()
            return _Outcome(_scattered(p, contact, pressure), True, iteration, residual,
                            "converged")
    refresh()
    change = (f"relative pressure change {residual:.3g} > tol = {tol:.3g}"
              if math.isfinite(residual) else "the contact set changed at every iteration")
    return _Outcome(_scattered(p, contact, pressure), False, max_iter, residual,
                    f"not converged after {max_iter} iterations ({change})")


def _overlapping(g: np.ndarray, shift: float, flag: np.ndarray, indices: np.ndarray) -> np.ndarray:
    """Flat indices of the pixels off the contact set (``indices``) whose gap ``g + shift`` is
    negative; ``flag`` is scratch of g's shape."""
    np.less(g, -shift, out=flag)
    flag.reshape(-1)[indices] = False
    return np.flatnonzero(flag)


def _scattered(p: np.ndarray, contact: _ContactSet, pressure: np.ndarray) -> np.ndarray:
    """``p`` (full grid) holding ``pressure`` on C and zero elsewhere."""
    p.fill(0.0)
    p.reshape(-1)[contact.indices] = pressure
    return p


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
