"""The benchmark and the stress campaign run in quick mode and produce their tables."""

import csv

import numpy as np
import pytest

from validation.campaigns.bench import machine_description, observed_order, pareto_front
from validation.cli import main


def test_pareto_front_and_observed_order():
    times = np.array([1.0, 2.0, 3.0, 0.5, 2.5])
    errors = np.array([0.1, 0.05, 0.2, 0.3, 0.05])
    np.testing.assert_array_equal(pareto_front(times, errors), [True, True, False, True, False])
    np.testing.assert_allclose(observed_order([64, 128, 256], [0.4, 0.1, 0.025]), [2.0, 2.0])
    assert np.isnan(observed_order([64, 128], [0.0, 0.1])[0])


def test_the_machine_is_described_with_its_cpu_model_and_versions(monkeypatch, tmp_path):
    import os
    import platform

    import validation.campaigns.bench as bench

    described = machine_description()
    assert f"{os.cpu_count()} cores" in described
    assert f"Python {platform.python_version()}" in described and f"numpy {np.__version__}" in described
    # where the platform does not name the CPU, its model comes from /proc/cpuinfo
    cpuinfo = tmp_path / "cpuinfo"
    cpuinfo.write_text("processor\t: 0\nmodel name\t: Some CPU 9000 @ 3.0GHz\nflags\t: x\n")
    real_open = open
    monkeypatch.setattr(platform, "processor", lambda: "")
    monkeypatch.setattr("builtins.open", lambda path, *args, **kwargs: real_open(
        cpuinfo if path == "/proc/cpuinfo" else path, *args, **kwargs))
    assert bench._processor() == "Some CPU 9000 @ 3.0GHz"
    assert "Some CPU 9000 @ 3.0GHz" in machine_description()
    monkeypatch.setattr("builtins.open", lambda *args, **kwargs: (_ for _ in ()).throw(OSError))
    assert bench._processor() == ""


@pytest.mark.slow      # 3-8 s: every method on two surfaces, with the figure
def test_bench_quick_writes_table_and_figure(tmp_path, capsys):
    assert main(["bench", "--quick", "--out", str(tmp_path)]) == 0
    text = (tmp_path / "bench.md").read_text()
    for method in ("bem", "gw", "improved_gw", "discrete", "discrete_no_interaction"):
        assert f"| {method} |" in text
    assert "observed order p" in text and "Peak memory" in text and "Python" in text
    assert (tmp_path / "bench.png").stat().st_size > 10_000
    with open(tmp_path / "bench.csv") as stream:
        rows = list(csv.DictReader(stream))
    assert {r["D"] for r in rows} == {"2.05", "2.95"}
    reference_rows = [r for r in rows if r["method"] == "bem" and r["n"] == "64"]
    # the reference grid at a loose tolerance differs from the reference by the tolerance only
    assert all(float(r["area_error"]) < 1e-3 for r in reference_rows)
    assert all(float(r["seconds"]) > 0 for r in rows)


def test_stress_quick_is_all_green(tmp_path, capsys):
    assert main(["stress", "--quick", "--out", str(tmp_path)]) == 0
    text = (tmp_path / "stress.md").read_text()
    groups = ("WM surface", "BEM load path", "BEM grid", "BEM separation", "special surface",
              "discrete model", "improved GW")
    for group in groups:
        assert f"| {group} |" in text
    assert "0 failures" in text
    with open(tmp_path / "stress.csv") as stream:
        rows = list(csv.DictReader(stream))
    assert rows and all(r["status"] in ("ok", "clear error") for r in rows)
    assert all(r["finite"] == "True" for r in rows)
