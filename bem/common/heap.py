"""Large arrays outside the C heap, so that freeing them gives their memory back.

glibc's ``malloc`` maps a block of its own for each request above a threshold, and gives that
memory back to the system when the block is freed; smaller requests come from its heaps ("arenas",
one per thread that allocates), which keep what was freed in them for later requests. The
threshold starts at 128 KiB and rises, each time a mapped block is freed, to that block's size, up
to 32 MiB. On a 2048^2 scan the fields of the Reynolds solves' unknowns (31 MB) and the int32 and
float32 maps of the grid (17 MB) then come from the heaps once the first of them is freed, and the
heaps of the leakage thread and of the contact path each keep the room of their largest moment:
the 2048^2 check's resident memory rose to 2.4-2.65 GB, where with every block above 1 MiB
mapped it stayed at 2.11 GB.
:func:`map_large_arrays` fixes the threshold (which also stops it rising): arrays above it are
mapped and given back when freed; below it (every field of a 1024^2 grid, 8 MB) nothing changes.
Measured on the 2048^2 benchmark check's first 170 s (three runs each): 2.38-2.64 GB ->
2.24-2.33 GB at the same progress of its solves; the whole check 2.65 -> 2.30 GB. At 1 MiB the
peak fell to 2.11 GB but the check took 25 % longer (every temporary above 1 MiB mapped and its
pages zeroed anew). Users of the library who solve large grids themselves may call it first.

Elsewhere than glibc (macOS, musl, Windows) nothing is done.
"""

from __future__ import annotations

import ctypes
import os
import sys

__all__ = ["MAPPED_THRESHOLD", "map_large_arrays"]

#: Size [bytes] above which :func:`map_large_arrays` has every block mapped (16 MiB).
MAPPED_THRESHOLD = 16 * 1024 * 1024
#: glibc's ``mallopt`` parameter for the mapping threshold (malloc.h).
_M_MMAP_THRESHOLD = -3
#: The environment variable through which glibc reads the same setting at start-up.
_VARIABLE = "MALLOC_MMAP_THRESHOLD_"

_state = {"set": False}


def _mallopt():
    """glibc's ``mallopt``, or None where the C library is not glibc."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        library = ctypes.CDLL(None)
        function = library.mallopt
    except (OSError, AttributeError):
        return None
    if not hasattr(library, "gnu_get_libc_version"):   # glibc's alone (musl's mallopt: a stub)
        return None
    function.argtypes, function.restype = (ctypes.c_int, ctypes.c_int), ctypes.c_int
    return function


def map_large_arrays(threshold: int = MAPPED_THRESHOLD) -> bool:
    """Have glibc map every block above ``threshold`` bytes (module docstring), once per
    process; a threshold the user set through ``MALLOC_MMAP_THRESHOLD_`` is left as it is.
    Returns whether the setting is in force (False off glibc)."""
    if isinstance(threshold, bool) or not isinstance(threshold, int) or not \
            0 < threshold <= 32 * 1024 * 1024:
        raise ValueError(f"threshold must be an integer number of bytes in (0, 32 MiB], got "
                         f"{threshold!r}")
    if _state["set"]:
        return True
    if _VARIABLE in os.environ:
        return bool(os.environ[_VARIABLE])
    mallopt = _mallopt()
    _state["set"] = bool(mallopt is not None and mallopt(_M_MMAP_THRESHOLD, threshold))
    return _state["set"]
