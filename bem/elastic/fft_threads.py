"""How many threads the FFTs of :mod:`bem.elastic.fft` use: the CPUs this process may use
(:func:`default_threads`), and for one operator those idle right now (:func:`fft_threads`).
"""

from __future__ import annotations

import math
import os
import time

from bem.common import background, checks

__all__ = ["IDLE_SAMPLE", "default_threads", "fft_threads", "idle_cpus"]


def default_threads() -> int:
    """Number of threads for FFTs: the CPUs this process may use.

    The environment variable ``ASPERITY_FFT_THREADS`` (a positive integer) overrides it; process
    pools set it so that their workers share the cores instead of oversubscribing them.
    """
    override = os.environ.get("ASPERITY_FFT_THREADS", "").strip()
    if override:
        if not override.isdigit() or int(override) < 1:
            raise ValueError(f"ASPERITY_FFT_THREADS must be a positive integer, got {override!r}")
        return int(override)
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


#: Interval [s] over which :func:`idle_cpus` measures the idle time of the machine's CPUs.
IDLE_SAMPLE = 0.1


def _cpu_times() -> tuple[int, int]:
    """(idle, total) clock ticks of all CPUs since boot, from the first line of /proc/stat."""
    with open("/proc/stat", encoding="ascii") as stream:
        values = [int(value) for value in stream.readline().split()[1:9]]
    return values[3] + values[4], sum(values)    # idle + iowait; user ... steal


def idle_cpus(interval: float = IDLE_SAMPLE) -> float | None:
    """CPUs of the machine left idle over the next ``interval`` seconds (e.g. 1.0 when one of
    two cores was busy), from /proc/stat; None where it cannot be read (not Linux).

    Raises
    ------
    ValueError
        For an ``interval`` that is not a finite number >= 0 (seconds).
    """
    interval = checks.non_negative("interval", interval)
    try:
        idle, total = _cpu_times()
        time.sleep(interval)
        idle_after, total_after = _cpu_times()
    except (OSError, ValueError, IndexError):
        return None
    if total_after <= total:
        return None
    return (os.cpu_count() or 1) * (idle_after - idle) / (total_after - total)


def fft_threads(shape: tuple[int, int]) -> int:
    """Default number of FFT threads for a convolution grid of ``shape`` (see HalfSpace): one
    below 1024 x 1024 points; above, the calling thread and the CPUs found idle right now
    (:func:`idle_cpus`), at most :func:`default_threads` less the process's own
    background calls running now (:func:`bem.common.background.running`: a realization's models
    computed beside its reference get their core; measured on a 512^2 check, two FFT threads
    beside them took 242 s of process time against 145 s with one).

    Idle CPUs measured now rather than the 1-minute load average, which also counts this
    process's own work of the last minute and jobs that have just ended: a check's finer
    reference, solved after its first stage had kept both cores busy, got one FFT thread on two
    idle cores. Where /proc/stat is not readable, the load average is used.
    """
    if shape[0] * shape[1] < 1024 * 1024:
        return 1
    cpus = default_threads() - background.running()
    if cpus <= 1:   # e.g. a pool's worker (ASPERITY_FFT_THREADS=1): nothing to measure
        return 1
    idle = idle_cpus()
    if idle is None:
        try:
            idle = cpus - 1.0 - os.getloadavg()[0]
        except (AttributeError, OSError):  # pragma: no cover - no load average either
            idle = cpus - 1.0
    return max(1, min(cpus, int(math.floor(1.0 + idle + 0.5))))
