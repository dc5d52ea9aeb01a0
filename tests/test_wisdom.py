"""FFTW wisdom kept in a file: a new process plans from it; a bad file only means planning again."""

import os
import subprocess
import sys

import pytest

pytest.importorskip("pyfftw")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

#: Plans one measured pair; then reports whether FFTW can make the same plans from wisdom alone
#: (FFTW_WISDOM_ONLY fails without wisdom for that transform).
SCRIPT = """
import sys
import numpy as np, pyfftw
from bem.elastic.fft import RealFFT2
from bem.elastic.wisdom import load_wisdom

load_wisdom()
a = pyfftw.empty_aligned((96, 80), dtype=np.float64)
b = pyfftw.empty_aligned((96, 41), dtype=np.complex128)
try:
    pyfftw.FFTW(a, b, axes=(0, 1), flags=("FFTW_MEASURE", "FFTW_WISDOM_ONLY"), threads=1)
    known = True
except RuntimeError:
    known = False
if sys.argv[1] == "plan":
    fft = RealFFT2((96, 80), threads=1, planner_effort="FFTW_MEASURE")
    fft.real_buffer[...] = 1.0
    fft.execute_forward()
    assert abs(fft.spectrum_buffer[0, 0] - 96 * 80) < 1e-9
print("known" if known else "unknown")
"""


def run(folder, action):
    env = dict(os.environ, PYTHONPATH=ROOT, ASPERITY_FFTW_WISDOM=str(folder))
    result = subprocess.run([sys.executable, "-c", SCRIPT, action], capture_output=True,
                            text=True, env=env, check=True)
    return result.stdout.strip()


def test_a_new_process_plans_from_the_wisdom_of_the_last(tmp_path):
    assert run(tmp_path, "check") == "unknown"
    assert run(tmp_path, "plan") == "unknown"  # plans, and writes the file
    (written,) = tmp_path.glob("fftw-wisdom-*.json")
    assert written.stat().st_size > 0
    assert run(tmp_path, "check") == "known"


def test_no_folder_keeps_no_wisdom_and_a_corrupt_file_is_planned_over(tmp_path):
    assert run("", "plan") == "unknown"
    assert run("", "check") == "unknown"
    (tmp_path / "probe").mkdir()
    run(tmp_path / "probe", "plan")
    (name,) = (p.name for p in (tmp_path / "probe").glob("fftw-wisdom-*.json"))
    (tmp_path / name).write_text("not wisdom")
    assert run(tmp_path, "plan") == "unknown"  # the corrupt file is read, ignored, replaced
    assert run(tmp_path, "check") == "known"
