"""Bad-input campaign: every public entry point against strings (numeric ones too), bytes,
None, NaN, +-inf, 1e+-300, complex numbers, arrays where a number, a name, an object or a
callback is expected, fractional counts, wrong-type objects, arrays of objects, arrays with one
string or None entry, empty, all-zero, constant (flat) and mis-shaped arrays, and read-only
arrays.

``python benchmarks/bad_input_campaign.py`` prints the count of each outcome class; the test
catalogue ``tests/test_bad_input.py`` draws from the same table with hypothesis. A new public
entry point is covered by adding one :class:`~validation.campaigns._bad_input_table.EntryPoint`
row to the table (:mod:`validation.campaigns._bad_input_table`); the test catalogue fails when an
exported name has none.

Outcome classes (``GOOD`` are acceptable):

* ``clear error`` (good): ``ValueError``/``TypeError`` whose message names the parameter;
* ``plausible result`` (good): a finite real result for an input that may be valid;
* ``unclear error``: ``ValueError``/``TypeError`` that does not name the parameter;
* ``other exception``: any other exception type (``AttributeError``, ``ZeroDivisionError``...);
* ``non-finite result``: NaN, inf or complex numbers in the result;
* ``accepted bad input``: a result for an input that is never valid (a string, None, NaN...);
* ``rejected valid input``: an error for a valid variant (a read-only array, a numpy scalar).
"""

from __future__ import annotations

import dataclasses
import math
import signal
import warnings
from typing import Any

import numpy as np

from validation.campaigns._bad_input_table import EntryPoint, table

__all__ = ["EntryPoint", "entry_points", "BAD_SCALARS", "NAMED_DOMAINS", "bad_arrays", "classify",
           "run_campaign", "GOOD", "OUTCOMES"]

OUTCOMES = ("clear error", "plausible result", "unclear error", "other exception",
            "non-finite result", "accepted bad input", "rejected valid input", "hang")
GOOD = ("clear error", "plausible result")


# value, label, never valid for any domain?
BAD_SCALARS: tuple[tuple[Any, str, bool], ...] = (
    ("0.5", "numeric string", True), ("abc", "string", True), (None, "None", True),
    (True, "True", True), (1 + 1j, "complex", True), (complex(0.5, 0.0), "complex real", True),
    (math.nan, "NaN", True), (math.inf, "+inf", True), (-math.inf, "-inf", True),
    ([1.0], "list", True), (np.array([1.0, 2.0]), "array", True), (b"1", "bytes", True),
    ("1e-6", "exponent string", True), (1e300, "1e300", False), (-1e300, "-1e300", False),
    (1e-300, "1e-300", False), (-1e-300, "-1e-300", False), (0.0, "0", False),
    (-1.0, "-1", False), (-1, "-1 (int)", False), (0.5, "0.5 for an integer", False),
    (2.5, "2.5 for an integer", False),
)
#: Scalar domains where no value of BAD_SCALARS is valid (None only when "optional").
NAMED_DOMAINS = ("choice", "object", "callable")


def _invalid_in_domain(value: Any, domain: str) -> bool:
    if value is None and "optional" in domain:
        return False
    if domain.startswith(NAMED_DOMAINS):
        return True
    if domain.startswith(("text", "path")):
        return not isinstance(value, str)
    if not isinstance(value, float):
        return False
    if domain.startswith("positive"):
        return value <= 0
    if domain.startswith("non_negative"):
        return value < 0
    if domain.startswith("integer"):
        return True          # a float where an integer is needed
    return False


def bad_arrays(valid: np.ndarray) -> tuple[tuple[Any, str, bool | None], ...]:
    """Bad variants of a valid array: (value, label, invalid?); None means a valid variant
    (must be accepted)."""
    valid = np.asarray(valid, dtype=float)
    with_nan = valid.copy()
    with_nan.flat[0] = math.nan
    with_inf = valid.copy()
    with_inf.flat[-1] = math.inf
    read_only = valid.copy()
    read_only.setflags(write=False)
    string_entry = valid.astype(object)
    string_entry.flat[0] = "1"
    none_entry = valid.astype(object)
    none_entry.flat[-1] = None
    constant = np.full(valid.shape, valid.flat[0] if valid.size and valid.flat[0] else 1.0)
    cases = [
        (None, "None", True), ("abc", "string", True), (with_nan, "NaN entry", True),
        (with_inf, "inf entry", True), (valid.astype(complex) + 1j, "complex", True),
        (valid.astype(str), "strings", True), (np.zeros(valid.shape, dtype=bool), "bools", True),
        (valid.astype(object), "objects", True), (string_entry.tolist(), "string entry", True),
        (none_entry.tolist(), "None entry", True),
        (np.zeros(valid.shape), "zeros", False), (constant, "constant", False),
        (valid * 1e300, "x 1e300", False), (valid * 1e-300, "x 1e-300", False),
        (np.zeros((0,) * valid.ndim), "empty", False), (valid.ravel()[:3] if valid.ndim > 1
                                                        else valid[:, None], "wrong ndim", False),
        (read_only, "read-only", None), (valid.tolist(), "nested lists", None),
    ]
    return tuple(cases)


def _flatten(result: Any, depth: int = 0):
    """Numbers of a result (arrays, dataclasses, dicts, tuples) for the finiteness check."""
    if depth > 4 or result is None or isinstance(result, (str, bytes, bool)):
        return
    if isinstance(result, (int, float, complex, np.number)):
        yield np.asarray(result)
    elif isinstance(result, np.ndarray):
        if result.dtype.kind in "fciu":
            yield result
    elif isinstance(result, dict):
        for value in result.values():
            yield from _flatten(value, depth + 1)
    elif isinstance(result, (tuple, list)):
        for value in result:
            yield from _flatten(value, depth + 1)
    elif dataclasses.is_dataclass(result):
        for item in dataclasses.fields(result):
            yield from _flatten(getattr(result, item.name), depth + 1)


def _finite_real(result: Any, allow_inf: bool = True) -> bool:
    for array in _flatten(result):
        if array.dtype.kind == "c" or np.any(np.isnan(array)):
            return False
        if not allow_inf and np.any(np.isinf(array)):
            return False
    return True


class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout


def classify(entry: EntryPoint, parameter: str, value: Any, invalid: bool | None,
             seconds: int = 30) -> tuple[str, str]:
    """Call ``entry`` with ``parameter = value``: (outcome class, detail)."""
    arguments = entry.arguments()
    arguments[parameter] = value
    use_alarm = hasattr(signal, "SIGALRM")
    if use_alarm:
        previous = signal.signal(signal.SIGALRM, _alarm)
        signal.alarm(seconds)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with np.errstate(all="ignore"):
                result = entry.call(**arguments)
    except _Timeout:
        return "hang", ""
    except (ValueError, TypeError) as error:
        if invalid is None:
            return "rejected valid input", f"{type(error).__name__}: {error}"
        detail = f"{type(error).__name__}: {error}"
        return ("clear error" if parameter in str(error) else "unclear error"), detail
    except Exception as error:  # noqa: BLE001 - classifying every exception is the point
        return "other exception", f"{type(error).__name__}: {error}"
    finally:
        if use_alarm:
            signal.alarm(0)
            signal.signal(signal.SIGALRM, previous)
    if invalid:
        return "accepted bad input", type(result).__name__
    if not _finite_real(result):
        return "non-finite result", type(result).__name__
    return "plausible result", type(result).__name__


def cases(entry: EntryPoint):
    """Every (parameter, value, label, invalid) of the campaign for one entry point."""
    valid = entry.arguments()
    for parameter, domain in entry.scalars.items():
        for value, label, never_valid in BAD_SCALARS:
            if label.endswith("for an integer") and not domain.startswith("integer"):
                continue
            if isinstance(value, str) and domain.startswith("path"):
                continue     # a valid path: writing there is no test of the checks
            invalid = _invalid_in_domain(value, domain) if value is None or domain.startswith(
                ("text", "path")) else (never_valid or _invalid_in_domain(value, domain))
            yield parameter, value, label, invalid
        # a numpy scalar of the valid value must be accepted
        if (not domain.startswith(("integer", "text", "path") + NAMED_DOMAINS)
                and isinstance(valid.get(parameter), (int, float))):
            yield parameter, np.float64(valid[parameter]), "numpy float", None
    for parameter, domain in entry.arrays.items():
        for value, label, invalid in bad_arrays(valid[parameter]):
            if value is None and "optional" in domain:
                invalid = None
            elif ((label == "inf entry" and "inf" in domain)
                  or (label == "NaN entry" and "nan" in domain)
                  or (label == "bools" and "mask" in domain)):
                invalid = None
            yield parameter, value, label, invalid


def run_campaign(entries=None) -> list[tuple[str, str, str, str, str]]:
    """(entry, parameter, label, outcome, detail) for every case of every entry point."""
    rows = []
    for entry in entry_points() if entries is None else entries:
        for parameter, value, label, invalid in cases(entry):
            outcome, detail = classify(entry, parameter, value, invalid)
            rows.append((entry.name, parameter, label, outcome, detail))
    return rows


def entry_points() -> tuple[EntryPoint, ...]:
    """The table: one row per public entry point."""
    return table()
