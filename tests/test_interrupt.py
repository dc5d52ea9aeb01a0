"""Ctrl-C stops a report at once, whatever the executor: a real SIGINT to a report running on
two worker processes ends it within seconds with exit status 130, a short message and no
traceback, no worker left behind, and a cache whose every entry reads back."""

from __future__ import annotations

import os
import pathlib
import signal
import subprocess
import sys
import time

import pytest

from validation.run.cache import Cache

ROOT = pathlib.Path(__file__).resolve().parents[1]
#: Big enough to run for a minute or more when not interrupted (so that the signal always
#: arrives while realizations are queued and running), small in memory.
SCENE = """
name = "interrupted"
[surface]
D = 2.4
rms_slope = 0.1
n = 512
[realizations]
count = 20
[loads]
min = 1e-4
max = 1e-2
count = 6
"""


def _children_of(pid: int) -> list[int]:
    """Processes whose parent is ``pid`` (read from /proc)."""
    out = []
    for entry in pathlib.Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid:
                out.append(int(entry.name))
    return out


def _running(pid: int) -> bool:
    """Whether process ``pid`` exists and is not a zombie."""
    try:
        return pathlib.Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return False


def _start(tmp_path: pathlib.Path, jobs: int, group: bool
           ) -> tuple[subprocess.Popen, pathlib.Path]:
    scene = tmp_path / "interrupted.toml"
    scene.write_text(SCENE)
    cache = tmp_path / "cache"
    env = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONWARNINGS="ignore")
    process = subprocess.Popen(
        [sys.executable, "-m", "validation", "report", str(scene), "--out", str(tmp_path / "out"),
         "--cache", str(cache), "--jobs", str(jobs), "--quiet"],
        cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        start_new_session=group)
    # computing has started once the first cache entry (the summits of a realization) is there
    deadline = time.monotonic() + 120
    while not list(cache.glob("*.npz")):
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline, "the report never started computing"
        time.sleep(0.05)
    return process, cache


@pytest.mark.skipif(not pathlib.Path("/proc").is_dir() or os.name != "posix",
                    reason="needs POSIX signals and /proc")
@pytest.mark.parametrize("jobs, group", [(2, False), (2, True), (1, False)],
                         ids=["two-workers", "two-workers-terminal", "in-process"])
def test_ctrl_c_stops_a_report_at_once_and_keeps_the_cache(tmp_path, jobs, group):
    # group: Ctrl-C in a terminal, which signals the whole process group (workers included)
    process, cache = _start(tmp_path, jobs, group)
    workers = _children_of(process.pid)
    if jobs > 1:
        assert workers, "the report runs no worker process"

    def interrupt() -> None:
        if group:
            os.killpg(process.pid, signal.SIGINT)
        else:
            process.send_signal(signal.SIGINT)

    interrupt()
    time.sleep(0.2)
    interrupt()                               # a second Ctrl-C must not hang the shutdown
    try:
        _, stderr = process.communicate(timeout=10)
    except subprocess.TimeoutExpired:
        process.kill()
        process.communicate()
        pytest.fail("the report did not stop within 10 s of Ctrl-C")
    assert process.returncode == 130, stderr
    assert "interrupted" in stderr and "Traceback" not in stderr, stderr
    assert "resumes" in stderr
    time.sleep(0.5)
    alive = [pid for pid in workers if _running(pid)]
    assert not alive, f"worker processes left running: {alive}"
    # every entry written before the signal reads back whole (entries are renamed into place)
    entries = sorted(cache.glob("*.npz"))
    assert entries
    assert all(Cache(cache).load(path.stem) is not None for path in entries)
    assert not (tmp_path / "out" / "report.md").exists()
