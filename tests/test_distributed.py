"""The distributed path for real: realizations on a dask ``LocalCluster`` of two worker
processes give the same report tables as the in-process run (skipped without dask)."""

from __future__ import annotations

import tomllib

import pytest

distributed = pytest.importorskip("distributed")

from validation.report.write import write_report  # noqa: E402
from validation.run.runner import run_scenes  # noqa: E402
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
