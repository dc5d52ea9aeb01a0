"""Path steps of the discrete asperity model: warm starts, step splitting and fallbacks.

The points of a path are visited by the shared stepper :func:`bem.common.continuation.follow_path`
(light to heavy contact, results in the caller's order); this module solves one point from the
previous one:

* warm start: the previous approaches plus the tangent ``d delta / d d`` (under load control
  the separation is predicted from the previous stiffness);
* a step that does not converge is split in two, recursively (depth <= 8);
* at the top level, the last resorts are a cold start from the mean-field estimate and a
  continuation in the interaction strength from independent Hertz contacts
  (:func:`asperity.discrete.complementarity.homotopy`): they find the other branch after a snap-through,
  e.g. one very large summit suddenly pressing its neighbours out of contact;
* a point that still fails is solved once more as if it were alone on its path (from first
  contact, with a fresh budget), so that a point on a path is never worse than the same point
  solved alone; the better of the two answers is kept.

Splitting may use 6 ``max_iter`` Newton iterations per attempt and the fallbacks 2 ``max_iter``
more, so a point far outside the model's validity costs bounded time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from asperity.discrete.complementarity import (Budget, PointSolution, first_contact, hertz_separation,
                                      homotopy, mean_field_guess, mean_field_start, newton,
                                      tangent)
from asperity.discrete.assembly import DiscreteProblem

__all__ = ["PathSolver"]

_MAX_SPLIT_DEPTH = 8
_WORK_PER_POINT = 6         # Newton iterations per attempt at a point, in units of max_iter
_WORK_RESERVE = 2           # ... plus this much for the cold-start fallbacks


def _better(first: PointSolution, second: PointSolution) -> PointSolution:
    """The converged one (else the smaller residual), charged with both attempts' work."""
    best = second if (second.converged, -second.residual) > (first.converged, -first.residual) \
        else first
    return replace(best, iterations=first.iterations + second.iterations)


@dataclass(frozen=True)
class PathSolver:
    """Solves points of a discrete-model path (the solver settings and nothing mutable)."""

    problem: DiscreteProblem
    tol: float
    max_iter: int

    def start(self) -> PointSolution:
        """The state before the lightest point: first contact, no force."""
        return first_contact(self.problem)

    def _budget(self) -> Budget:
        return Budget(_WORK_PER_POINT * self.max_iter)

    def _newton(self, delta, separation, budget, load=None, approach_rate=None):
        return newton(self.problem, delta, separation, target_load=load, tol=self.tol,
                      max_iter=self.max_iter, budget=budget, approach_rate=approach_rate)

    def _fallback(self, separation: float, load: float | None, budget: Budget):
        """Cold start from the mean-field estimate, then the interaction-strength homotopy."""
        budget.left = max(budget.left, 0) + _WORK_RESERVE * self.max_iter
        if load is None:
            cold, state = self._newton(mean_field_guess(self.problem, separation), separation,
                                       budget)
        else:
            cold, state = self._newton(*mean_field_start(self.problem, load), budget, load)
        if cold.converged:
            return cold, state, cold.iterations
        spent = cold.iterations
        start = separation if load is None else hertz_separation(self.problem, load)
        cold, state = homotopy(self.problem, start, load, tol=self.tol,
                               max_iter=self.max_iter, budget=budget)
        return cold, state, spent + cold.iterations

    # ---------------------------------------------------------------- separation control
    def separation_step(self, previous: PointSolution, separation: float, *,
                        want_tangent: bool) -> PointSolution:
        """Solve at ``separation`` [length] from ``previous``, the last point of the path."""
        solution = self._at_separation(previous, separation, 0, want_tangent, self._budget())
        if solution.converged or previous.load_carried() == 0:
            return solution
        alone = self._at_separation(self.start(), separation, 0, want_tangent, self._budget())
        return _better(solution, alone)

    def _at_separation(self, previous, separation, depth, want_tangent, budget):
        problem = self.problem
        if separation >= problem.first_contact:
            return first_contact(problem, separation)
        if previous.load_carried() > 0:
            guess = previous.delta
            if previous.tangent is not None:
                guess = previous.delta + previous.tangent * (previous.separation - separation)
        else:
            guess = mean_field_guess(problem, separation)
        solution, state = self._newton(guess, separation, budget)
        spent = solution.iterations
        if not solution.converged and depth < _MAX_SPLIT_DEPTH and budget:
            middle = 0.5 * (previous.separation + separation)
            half = self._at_separation(previous, middle, depth + 1, True, budget)
            spent += half.iterations
            if half.converged:
                retry = self._at_separation(half, separation, depth + 1, want_tangent, budget)
                spent += retry.iterations
                if retry.converged:
                    return replace(retry, iterations=spent)
        if not solution.converged and depth == 0:
            cold, cold_state, cost = self._fallback(separation, None, budget)
            spent += cost
            if cold.converged:
                solution, state = cold, cold_state
        solution = replace(solution, iterations=spent)
        if want_tangent or depth > 0:
            solution = tangent(problem, solution, state)
        return solution

    # ---------------------------------------------------------------- load control
    def load_step(self, previous: tuple[PointSolution, float], load: float
                  ) -> tuple[PointSolution, float]:
        """Solve at total load ``load`` [force] from ``previous = (solution, its load)``;
        returns ``(solution, load)`` (the state :func:`bem.common.continuation.follow_path` carries)."""
        solution_before, load_before = previous
        solution = self._at_load(solution_before, load_before, load, 0, self._budget())
        if not solution.converged and load_before > 0:
            alone = self._at_load(self.start(), 0.0, load, 0, self._budget())
            solution = _better(solution, alone)
        return solution, load

    def _at_load(self, previous, previous_load, load, depth, budget):
        problem = self.problem
        if load == 0.0:
            return first_contact(problem)
        if previous_load > 0 and previous.stiffness:
            # Tangent predictor: d(W) ~ d_prev - (W - W_prev) / S, delta along -d delta/dd.
            separation = previous.separation - (load - previous_load) / previous.stiffness
            delta = np.maximum(previous.delta + previous.tangent
                               * (previous.separation - separation), 0.0)
        else:
            delta, separation = mean_field_start(problem, load)
        solution, state = self._newton(delta, separation, budget, load, previous.tangent)
        spent = solution.iterations
        if not solution.converged and depth < _MAX_SPLIT_DEPTH and budget:
            middle = math.sqrt(previous_load * load) if previous_load > 0 else 0.25 * load
            half = self._at_load(previous, previous_load, middle, depth + 1, budget)
            spent += half.iterations
            if half.converged:
                retry = self._at_load(half, middle, load, depth + 1, budget)
                spent += retry.iterations
                if retry.converged:
                    return replace(retry, iterations=spent)
        if not solution.converged and depth == 0:
            cold, cold_state, cost = self._fallback(separation, load, budget)
            spent += cost
            if cold.converged:
                solution, state = cold, cold_state
        return tangent(problem, replace(solution, iterations=spent), state)
