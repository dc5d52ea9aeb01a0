"""Shared test configuration: hypothesis profiles, and the tests skipped for an optional package.

``HYPOTHESIS_PROFILE=ci`` (set by .ci/run) fixes the example count and derandomises the search
so a CI run is reproducible; the default profile explores more.

The README's test command installs the ``test`` extra alone, so a test that needs an optional
package (SurfaceTopography, pandas, dask) skips, saying which. With ``ASPERITY_SKIPPED_FOR=FILE``
the node ids of the tests so skipped are written to FILE, one a line: .ci/run installs the
extras and runs exactly those again.
"""

import os
import pathlib

from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci", max_examples=40, deadline=None, derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "dev", max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "thorough", max_examples=1000, deadline=None, suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "dev"))

#: What a skip for a missing package says (pytest.importorskip's words, and this suite's).
_MISSING = ("could not import", "not installed")
_skipped_for_packages: list[str] = []


def _missing_package(report) -> bool:
    longrepr = report.longrepr
    message = longrepr[2] if isinstance(longrepr, tuple) else str(longrepr)
    return any(words in message for words in _MISSING)


def pytest_runtest_logreport(report):
    if report.skipped and _missing_package(report):
        _skipped_for_packages.append(report.nodeid)


def pytest_collectreport(report):
    if report.skipped and _missing_package(report):   # a module skipped as a whole
        _skipped_for_packages.append(report.nodeid)


def pytest_sessionfinish(session):
    target = os.environ.get("ASPERITY_SKIPPED_FOR")
    if target:
        pathlib.Path(target).write_text("".join(f"{node}\n" for node in
                                                dict.fromkeys(_skipped_for_packages)),
                                        encoding="utf-8")
