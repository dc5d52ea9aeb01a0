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
        self.bar = tqdm(total=total, file=stream, unit=f" {label}", dynamic_ncols=interactive,
                        disable=not (interactive or always), leave=True, smoothing=0.1,
                        mininterval=0.5 if interactive else 0.0)

    def advance(self, what: str = "") -> None:
        """One unit done; ``what`` (the unit just finished) is shown after the bar."""
        if what:
            self.bar.set_postfix_str(what, refresh=False)
        self.bar.update(1)
        if self.bar.total is not None and self.bar.n >= self.bar.total:
            self.close()

    def close(self) -> None:
        self.bar.close()

    def __enter__(self) -> "Progress":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
