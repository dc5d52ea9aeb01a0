"""The distributed path for real: realizations on a dask ``LocalCluster`` of two worker
processes give the same report tables as the in-process run, and Ctrl-C stops such a run
(skipped without dask)."""

from __future__ import annotations

import tomllib

import pytest

distributed = pytest.importorskip("distributed")

from validation.report.write import write_report  # noqa: E402
from validation import run_scenes  # noqa: E402
from validation.scenes.reader import parse_scene  # noqa: E402

SCENE = """
name = "tiny-cluster"
title = "Tiny scene on a cluster"
[surface]
D = 2.4
rms_slope = 0.1
n = 16
[realizations]
count = 3
seed = 5
[loads]
min = 1e-4
max = 1e-2
count = 3
[models]
use = ["bem", "gw", "improved_gw", "discrete"]
[bem]
tol = 1e-8
"""

TABLES = ("curves.csv", "errors.csv", "validity.csv")


@pytest.mark.slow
def test_local_cluster_report_tables_equal_the_local_run(tmp_path):
    scene = parse_scene(tomllib.loads(SCENE))
    local = write_report(run_scenes([scene], progress=False), tmp_path / "local").parent
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        results = run_scenes([scene], executor=client.get_executor(), progress=False)
        workers = client.run(lambda: __import__("os").getpid())
    remote = write_report(results, tmp_path / "cluster").parent
    assert len(set(workers.values())) == 2             # two worker processes really ran
    for name in TABLES:
        assert (remote / name).read_text() == (local / name).read_text(), name


@pytest.mark.slow
def test_ctrl_c_stops_a_report_on_a_cluster(tmp_path):
    # the same real SIGINT as tests/test_interrupt.py, with the realizations on a two-worker
    # LocalCluster: the report ends with 130, and the cluster is left with nothing to do
    import os
    import signal
    import subprocess
    import sys
    import time

    import pathlib

    root = pathlib.Path(__file__).resolve().parents[1]
    # long enough to be running when the signal comes (a minute or more uninterrupted)
    (tmp_path / "scene.toml").write_text(SCENE.replace("n = 16", "n = 512").replace(
        "count = 3\nseed = 5", "count = 20\nseed = 5"))
    cache = tmp_path / "cache"
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        env = dict(os.environ, PYTHONPATH=str(root), PYTHONWARNINGS="ignore")
        process = subprocess.Popen(
            [sys.executable, "-m", "validation", "report", str(tmp_path / "scene.toml"), "--out",
             str(tmp_path / "out"), "--cache", str(cache), "--scheduler",
             cluster.scheduler_address, "--quiet"],
            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        deadline = time.monotonic() + 120
        while not list(cache.glob("*.npz")):
            assert process.poll() is None, process.communicate()
            assert time.monotonic() < deadline, "the report never started computing"
            time.sleep(0.05)
        process.send_signal(signal.SIGINT)
        time.sleep(0.2)
        process.send_signal(signal.SIGINT)
        try:
            _, stderr = process.communicate(timeout=15)
        except subprocess.TimeoutExpired:
            process.kill()
            process.communicate()
            pytest.fail("the report did not stop within 15 s of Ctrl-C")
        assert process.returncode == 130, stderr
        assert "interrupted" in stderr and "Traceback" not in stderr
        time.sleep(1.0)
        assert not any(client.processing().values())   # cancelled on the cluster too
