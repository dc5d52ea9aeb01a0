"""The leakage of a sequence of gaps (:func:`bem.leakage.flow.leakage_aperture`), solved in a background
thread while the caller goes on, e.g. solves the next contact problem of a load path.

The gaps wait in a queue and one worker thread solves them in the order submitted, each
direction's iterative solve starting from the pressure of the same direction's previous solve
(the previous load's, along a path): the same stopping rule, in fewer iterations (a 1024^2
scan's gaps 16 % less time, those of a 512^2 path 15 %). So the caller is held back only when
more gaps wait than it allowed (``pending``), and on a path whose Reynolds solves take longer
than its contact solves (a 1024^2 scan: 68 s of solves beside a 29 s path) the path finishes
first; the gaps still waiting when the caller asks for the results then have their two
directions solved at once, on the cores the caller has freed.
"""

from __future__ import annotations

import threading
from collections import deque

import numpy as np

from bem.common import checks
from bem.common.background import BackgroundCall
from bem.elastic.fft_threads import default_threads
from bem.leakage.flow import FLOW_DIRECTIONS, FlowStart, _flow_solution, _mean_leak
from bem.leakage.flow_solver import solved_directly

__all__ = ["FINAL_PARALLEL_LIMIT", "PARALLEL_DIRECTIONS_LIMIT", "PARALLEL_FACTOR_LIMIT",
           "QUEUED_CELLS", "BackgroundLeakage"]

#: Gaps of more cells than this have their two directions solved one after the other, not
#: at once, while the caller works beside them: the multigrid solve of a 1024^2 gap peaks at
#: 0.6-0.9 GB, of a 2048^2 gap at 0.8-0.85 GB (a process solving one gap at 1-9 % contact).
PARALLEL_DIRECTIONS_LIMIT = 768 * 768
#: Once the caller waits for the results (:meth:`BackgroundLeakage.results`), gaps of up to
#: this many cells still waiting have their two directions solved at once where the process
#: may use two CPUs: the caller's contact solves are over and their memory given back
#: (:func:`bem.contact_curve`), and after a 2048^2 check's path its process held 0.79 GB
#: between solves and 1.11-1.13 GB with one 2048^2 solve, against 1.86 GB on the path with one
#: beside it.
FINAL_PARALLEL_LIMIT = 2048 * 2048
#: Gaps of more cells than this whose two directions are both to be solved by sparse LU
#: (:func:`bem.leakage.flow_solver.solved_directly`: near percolation) have them solved one after the
#: other whatever the limits above: the LU of a 1024^2 gap holds 1.2-2.0 GB of a process (40-76
#: million entries in its factors; SuperLU allocates up to 3.4 GB for it), and two at once, as
#: at the end of a 1024^2 path, would double that.
PARALLEL_FACTOR_LIMIT = 512 * 512
#: Gaps waiting for their solves hold at most about this many cells (128 MB): a load path
#: allows ``QUEUED_CELLS // cells`` gaps in its queue (16 of 1024^2, 4 of 2048^2).
QUEUED_CELLS = 16 * 1024 * 1024


def _apertures(gap, spacing: float, directions: tuple[str, ...], periodic: bool,
               starts: dict) -> list[tuple[str, float, FlowStart | None]]:
    """``(direction, aperture, solved)`` of ``gap`` along each of ``directions``, one after
    the other, each solve started from ``starts[direction]`` (:func:`bem.leakage.flow._flow_solution`)."""
    return [(direction, *_flow_solution(gap, spacing, direction, periodic, starts.get(direction)))
            for direction in directions]


class BackgroundLeakage:
    """:func:`bem.leakage.flow.leakage_aperture` of a sequence of gaps, solved in a background thread
    in the order submitted (module docstring).

    A gap's two directions are solved at once (two threads) up to
    :data:`PARALLEL_DIRECTIONS_LIMIT` cells, one after the other above it (one solve's memory at
    a time), and at once up to :data:`FINAL_PARALLEL_LIMIT` once :meth:`results` is waiting;
    but one after the other above :data:`PARALLEL_FACTOR_LIMIT` cells when both are to be
    solved by sparse LU. The sparse LU and the multigrid's compiled sweeps release the GIL.
    Once a direction's multigrid took many iterations (near percolation) it goes on by sparse
    LU (:data:`bem.leakage.flow_solver.DIRECT_SWITCH_ITERATIONS`).
    The threads are daemons (:class:`bem.common.background.BackgroundCall`): a caller interrupted by
    Ctrl-C does not wait.

    Parameters
    ----------
    spacing : float
        Grid step h [length] of every gap.
    periodic : bool
        As in :func:`bem.leakage.flow.hydraulic_aperture`.
    pending : int
        Gaps submitted and not yet solved, at most (>= 1): :meth:`submit` waits beyond that,
        which bounds the memory the waiting gaps hold.
    parallel : bool, optional
        A gap's two directions in two threads: by default as above; True at any size (the
        caller has cores and memory for two solves at once), False never.
    """

    def __init__(self, spacing: float, *, periodic: bool = False, pending: int = 1,
                 parallel: bool | None = None):
        self.spacing = checks.positive("spacing", spacing)
        self.periodic = checks.flag("periodic", periodic)
        self.pending = checks.integer("pending", pending, minimum=1)
        self.parallel = None if parallel is None else checks.flag("parallel", parallel)
        self._waiting: deque = deque()   # (key, gap) submitted, not yet taken by the worker
        self._unsolved = 0               # submitted and not yet solved
        self._solved: dict = {}          # key -> [aperture per direction] or the error
        self._results: dict = {}
        self._starts: dict[str, FlowStart] = {}   # direction -> the last solve's pressure
        self._finishing = False          # results() is waiting: the caller's cores are free
        self._worker: BackgroundCall | None = None
        self._condition = threading.Condition()

    def submit(self, key, gap) -> None:
        """Queue the leakage of ``gap`` (both directions), to be read as ``results()[key]``."""
        with self._condition:
            while self._unsolved >= self.pending:
                self._condition.wait()
            self._waiting.append((key, gap))
            self._unsolved += 1
            self._condition.notify_all()
            if self._worker is None or not self._worker.is_alive():
                self._worker = BackgroundCall(self._work, name="leakage")

    def _together(self, gap, starts: dict) -> bool:
        """Whether one thread solves both directions of ``gap`` (class docstring), the next
        solve of each direction starting from ``starts`` (direction -> :class:`FlowStart`)."""
        if self.parallel is not None:
            return not self.parallel
        cells = np.size(gap)
        if cells > PARALLEL_FACTOR_LIMIT and all(
                solved_directly(cells, starts.get(direction))
                for direction in FLOW_DIRECTIONS):
            return True
        if cells <= PARALLEL_DIRECTIONS_LIMIT:
            return False
        return not (self._finishing and cells <= FINAL_PARALLEL_LIMIT and default_threads() > 1)

    def _work(self) -> None:
        """The worker: solve the waiting gaps in turn; return when none is left."""
        while True:
            with self._condition:
                if not self._waiting:
                    self._worker = None
                    return
                key, gap = self._waiting.popleft()
                starts = dict(self._starts)
            try:
                if self._together(gap, starts):
                    outcome = _apertures(gap, self.spacing, FLOW_DIRECTIONS, self.periodic,
                                         starts)
                else:
                    first, second = ((direction,) for direction in FLOW_DIRECTIONS)
                    beside = BackgroundCall(_apertures, gap, self.spacing, second, self.periodic,
                                            starts, name="leakage-" + second[0])
                    outcome = _apertures(gap, self.spacing, first, self.periodic, starts)
                    outcome += beside.result()
            except BaseException as error:   # re-raised where the result is read
                outcome = error
            with self._condition:
                if not isinstance(outcome, BaseException):
                    self._starts.update({direction: start for direction, _, start in outcome
                                         if start is not None})
                    # the apertures only: a solve's pressure field (32 MB at 2048^2) is kept
                    # as the next start of its direction alone, not for every gap of a path
                    outcome = [aperture for _, aperture, _ in outcome]
                self._solved[key] = outcome
                self._unsolved -= 1
                self._condition.notify_all()

    def results(self) -> dict:
        """Every submitted gap's h_eff [length] by key (waits for the solves still to come);
        a gap whose solve raised re-raises its error here."""
        with self._condition:
            self._finishing = True
            while self._unsolved:
                self._condition.wait()
            self._finishing = False
            solved, self._solved = self._solved, {}
        for key, outcome in solved.items():
            if isinstance(outcome, BaseException):
                raise outcome
            self._results[key] = _mean_leak(outcome)
        return dict(self._results)
