"""The constrained conjugate-gradient iteration of the contact problem (Polonsky & Keer 1999).

Load control minimises the elastic energy ``(1/2) p.Kp - p.z`` over ``p >= 0`` at fixed
``sum p`` (d is the Lagrange multiplier, ``d = mean over the contact set of (z - u)``);
separation control minimises ``(1/2) p.Kp + p.(d - z)`` over ``p >= 0`` (Rey, Anciaux &
Molinari 2017). Conventions: :mod:`bem.solver`.

Preconditioning (:mod:`bem.preconditioner`): the gap on the contact set C is multiplied by
``P_C M P_C`` with M the inverse symbol ``(E*/2)|q|`` of the half-space, P_C the restriction to C
(and, in load control, the projection to zero sum on C), so the conjugate gradients on C see a
nearly grid-independent spectrum; when pixels enter C the direction is kept (t is zero on them)
rather than restarted, and it restarts from the preconditioned gradient whenever it is not a
descent direction. The plain Polonsky-Keer iteration (``preconditioner=None``) restarts from
steepest descent whenever pixels enter.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bem.halfspace import HalfSpace
from bem.preconditioner import InverseKernel

#: Exact recomputation of u = K p every this many iterations (bounds rounding drift).
_REFRESH_INTERVAL = 50



class _Workspace:
    """Preallocated arrays of one grid, reused by every iteration (and along a load path)."""

    def __init__(self, shape: tuple[int, int]) -> None:
        self.shape = shape
        self._u: np.ndarray | None = None
        self.g = np.empty(shape)
        self._g_contact: np.ndarray | None = None  # plain iteration only
        self._t: np.ndarray | None = None  # plain iteration only
        self.work = np.empty(shape)
        self.contact_weight = np.empty(shape)
        self.contact = np.empty(shape, dtype=bool)
        self.flag = np.empty(shape, dtype=bool)
        self._inverse_kernel: InverseKernel | None = None
        self.preconditioned = True  # whether the last solve used the preconditioner

    @property
    def u(self) -> np.ndarray:
        """The displacement of the iterate (allocated when the last one was handed out)."""
        if self._u is None:
            self._u = np.empty(self.shape)
        return self._u

    def take_displacement(self) -> np.ndarray:
        """The displacement array, now the caller's: the next solve allocates a new one."""
        u, self._u = self.u, None
        return u

    @property
    def g_contact(self) -> np.ndarray:
        """The gap on the contact set (the preconditioned iteration keeps it in the
        preconditioner's input instead)."""
        if self._g_contact is None:
            self._g_contact = np.empty(self.shape)
        return self._g_contact

    @property
    def t(self) -> np.ndarray:
        """The search direction saved around a full product (the preconditioned iteration
        saves it in the preconditioner's output instead)."""
        if self._t is None:
            self._t = np.empty(self.shape)
        return self._t

    def inverse_kernel(self, operator: HalfSpace) -> InverseKernel:
        """The preconditioner of ``operator``'s grid, built on first use."""
        if self._inverse_kernel is None:
            self._inverse_kernel = InverseKernel(operator.shape, operator.spacing,
                                                 e_star=operator.e_star, threads=operator.threads)
        return self._inverse_kernel


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
                    ws: _Workspace, preconditioner: InverseKernel | None = None) -> _Outcome:
    """Polonsky-Keer iteration from the start ``p >= 0`` (modified in place).

    ``total`` is the target ``sum p`` (load control; p must already sum to it), or
    ``separation`` is d (separation control). Returns with ``ws.u = K p`` exact. With a
    ``preconditioner`` the direction is built from ``P M gc`` instead of the contact gap gc
    (module docstring); entering pixels then get the pressure ``-tau_e g`` with
    ``tau_e = tau (gc . P M gc) / (gc . gc)``, the step length expressed per unit gap as in the
    plain iteration, where ``tau_e = tau``.

    Implementation notes (each full-grid pass costs about a tenth of an FFT pair, so they are
    counted): the search direction t and its displacement r = K t live in the operator's FFT
    buffers (no copies around the product); t is saved around the occasional full product of p
    only when the next iteration needs it. In load control the sum of t follows the recurrence
    t <- beta t + gc (gc, or its preconditioned version, sums to zero) and is summed afresh only after a step that clipped
    pixels (t is then masked); sum p after the step follows from it and the few changed pixels
    when they are known.
    """
    load_control = total is not None
    u, g, work = ws.u, ws.g, ws.work
    if preconditioner is None:
        gc, saved_t = ws.g_contact, ws.t
    else:  # the preconditioner's output is free once the direction is made
        gc, s_pre = preconditioner.input_block, preconditioner.output_block
        saved_t = s_pre
    weight, contact, flag = ws.contact_weight, ws.contact, ws.flag
    t, r = operator._direction_buffers()
    flat_p, flat_g = p.reshape(-1), g.reshape(-1)
    direct_limit = operator.direct_source_limit
    if direct_limit:
        operator.influence  # noqa: B018 - build the influence coefficients once, up front
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
        if preconditioner is None:
            g_norm = _dot(gc, gc)
            descent = gc
        else:
            g_square = _dot(gc, gc)
            preconditioner.execute()
            descent = s_pre
            descent *= weight
            if load_control:
                np.multiply(weight, float(descent.sum()) / n_contact, out=work)
                descent -= work
            g_norm = _dot(gc, descent)
        # conjugate search direction on the contact set
        # t_sum = sum of t (zero outside the contact set); gc sums to zero in load control
        if reset or g_norm_old == 0.0:
            np.copyto(t, descent)
            t_sum = 0.0
        else:
            beta = g_norm / g_norm_old
            if shrunk:
                np.multiply(t, weight, out=t)
            t *= beta
            t += descent
            if load_control:
                t_sum = float(t.sum()) if shrunk else beta * t_sum
        g_norm_old = g_norm
        slope = _dot(gc, t)
        if slope < 0.0:  # not a descent direction (a kept direction after entering pixels)
            np.copyto(t, descent)
            t_sum = 0.0
            slope = g_norm
        operator._transform_direction()  # r = K t
        rt = _dot(r, t)
        if t_sum != 0.0:
            rt -= _dot(r, weight) / n_contact * t_sum
        if rt > 0.0 and math.isfinite(rt):
            tau = slope / rt
            # pressure per unit overlap for entering pixels: tau itself without preconditioner
            tau_fallback = (tau if preconditioner is None or g_square == 0.0
                            else tau * g_norm / g_square)
            tau_enter = tau_fallback
        else:  # t = 0: the contact set is solved exactly; only new contacts may remain
            if tau_fallback is None:
                tau_fallback = 1.0 / operator.self_influence
            tau = tau_enter = tau_fallback
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
            values = -tau_enter * flat_g[entering]
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
        # Polonsky-Keer restart from steepest descent when pixels enter; the preconditioned
        # iteration keeps its direction (t is zero on the entering pixels): restarting made it
        # fix the boundary of the contact set one oscillating pixel per iteration, in a number of
        # iterations growing with n (measured; a non-descent direction still restarts, above)
        reset, shrunk = entered > 0 and preconditioner is None, clipped > 0
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
    change = (f"relative pressure change {residual:.3g} > tol = {tol:.3g}"
              if math.isfinite(residual) else "the contact set changed at every iteration")
    return _Outcome(p, False, max_iter, residual,
                    f"not converged after {max_iter} iterations ({change})")


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
