"""Progress of a long run: a ``tqdm`` bar with counts, rate and ETA on a terminal, silence
elsewhere (log files, CI, pipes), so that redirected output holds no control characters."""

from __future__ import annotations

import sys
from typing import IO

from tqdm import tqdm

__all__ = ["Progress"]


class Progress:
    """A progress bar over ``total`` units of work.

    Parameters
    ----------
    total : int
        Number of units (realizations).
    stream : file-like, optional
        Where to draw (stderr by default).
    label : str
        Unit name shown after the counts.
    always : bool
        Draw even when ``stream`` is not a terminal (default: only on a terminal).
    """

    def __init__(self, total: int, *, stream: IO[str] | None = None,
                 label: str = "realizations", always: bool = False) -> None:
        stream = sys.stderr if stream is None else stream
        interactive = bool(getattr(stream, "isatty", lambda: False)())
        # tqdm's own ETA assumes units of equal cost; the caller's learnt estimate (``eta`` of
        # :meth:`advance`) is shown instead when it has one
        # a pseudo-terminal without a size (a recorded session, some CI consoles) reports a
        # width of 0, which would draw an empty bar: use a fixed width there
        sized = interactive and _width(stream) > 0
        self.bar = tqdm(total=total, file=stream, unit=f" {label}", dynamic_ncols=sized,
                        ncols=None if sized or not interactive else 100,
                        nrows=None if sized or not interactive else 40,
                        disable=not (interactive or always), leave=True, smoothing=0.1,
                        mininterval=0.5 if interactive else 0.0,
                        bar_format="{l_bar}{bar}| {n_fmt}/{total_fmt}{unit} [{elapsed}{postfix}]")

    def advance(self, what: str = "", *, eta: float | None = None) -> None:
        """One unit done; ``what`` (the unit just finished) and ``eta``, the expected seconds
        still to run, are shown after the bar."""
        left = "" if eta is None else f"ETA {_clock(eta)}"
        postfix = ", ".join(part for part in (left, what) if part)
        if postfix:
            self.bar.set_postfix_str(postfix, refresh=False)
        self.bar.update(1)
        if self.bar.total is not None and self.bar.n >= self.bar.total:
            self.close()

    def close(self) -> None:
        """Finish the bar (idempotent)."""
        self.bar.close()

    def __enter__(self) -> "Progress":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _clock(seconds: float) -> str:
    """``h:mm:ss`` or ``m:ss`` of a duration in seconds."""
    minutes, secs = divmod(int(round(max(0.0, seconds))), 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours}:{minutes:02d}:{secs:02d}" if hours else f"{minutes}:{secs:02d}"


def _width(stream) -> int:
    """Columns of the terminal behind ``stream`` (0 when unknown)."""
    import os

    try:
        return os.get_terminal_size(stream.fileno()).columns
    except (AttributeError, OSError, ValueError):
        return 0
