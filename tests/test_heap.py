"""bem.common.heap: large arrays mapped, so that freeing them gives their memory back (glibc)."""

import os
import subprocess
import sys
import textwrap

import pytest

from bem.common import heap

GLIBC = heap._mallopt() is not None

#: Allocates and frees a 20 MiB array twice (the first free raises glibc's threshold when it is
#: not fixed), then prints how much of the second one the process still holds [MiB].
PROBE = textwrap.dedent("""
    import os, sys
    import numpy as np
    from bem.common import heap
    if sys.argv[1] == "map":
        assert heap.map_large_arrays()
    def resident():
        with open("/proc/self/statm") as statm:
            return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    size = 20 * 2**20 // 8
    array = np.ones(size); del array
    before = resident()
    array = np.ones(size); del array
    print((resident() - before) / 2**20)
""")


def _held(mode: str) -> float:
    environment = {k: v for k, v in os.environ.items() if k != "MALLOC_MMAP_THRESHOLD_"}
    out = subprocess.run([sys.executable, "-c", PROBE, mode], capture_output=True, text=True,
                         check=True, env=environment)
    return float(out.stdout)


@pytest.mark.skipif(not GLIBC, reason="the threshold is glibc's")
def test_a_freed_large_array_is_given_back_once_the_threshold_is_fixed():
    # glibc's own rule keeps the second array's 20 MiB in its heap; fixed at 16 MiB, every
    # block above it is mapped and unmapped when freed
    assert _held("default") > 15.0
    assert _held("map") < 2.0


def test_a_threshold_the_user_set_is_left_alone(monkeypatch):
    monkeypatch.setattr(heap, "_state", {"set": False})
    monkeypatch.setenv("MALLOC_MMAP_THRESHOLD_", "1048576")
    monkeypatch.setattr(heap, "_mallopt", lambda: pytest.fail("mallopt called"))
    assert heap.map_large_arrays() is True


@pytest.mark.parametrize("threshold", [0, -1, 2**26, 1.5, True, "16MiB", None])
def test_a_bad_threshold_is_refused(threshold):
    with pytest.raises(ValueError, match="threshold must be an integer number of bytes"):
        heap.map_large_arrays(threshold)
