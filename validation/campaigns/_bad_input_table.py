"""The entry-point table of the bad-input campaign (:mod:`validation.campaigns.bad_input`).

One :class:`~validation.campaigns._bad_input_fixtures.EntryPoint` row per name that
``asperity``, ``bem`` and ``validation`` export (``__all__``), and per public method of an
exported class that takes arguments (``"GreenwoodWilliamson.at_load"``); a few names have more
than one row (``"bem.solve_contact(separation)"``). ``tests/test_bad_input.py`` fails when an
exported name has no row, apart from the names in :data:`NO_ROW`.
"""

from __future__ import annotations

from validation.campaigns._bad_input_fixtures import EntryPoint

__all__ = ["EntryPoint", "NO_ROW", "table"]

#: Exported names with no arguments to check, and why.
NO_ROW = {
    "asperity.GW_ORDERS": "a constant",
    "asperity.DISTRIBUTIONS": "a constant",
    "asperity.DISCRETE_QUANTITIES": "a constant",
    "asperity.PERSSON_QUANTITIES": "a constant",
    "bem.CURVE_QUANTITIES": "a constant",
    "validation.__version__": "a constant",
    "asperity.ValidityWarning": "a warning: built by warnings.warn from the project's message",
    "bem.ConvergenceWarning": "a warning: built by warnings.warn from the project's message",
    "validation.SceneError": "an exception the project raises, with its own message",
    "bem.ContactModel": "a typing.Protocol (the contract); each model that follows it has rows",
    "validation.check_scan": "its arguments are the check command's options, checked by their "
                             "own campaign (tests/test_bad_options.py, "
                             "tests/test_check_library.py); a valid extreme runs a whole check",
    "validation.CheckResult": "a result check_scan builds, not built by users",
    "validation.predict_errors": "its arguments are the check's (validation.check.library."
                                 "make_request, the same campaign as check_scan's; "
                                 "tests/test_atlas.py)",
    "validation.Prediction": "a result predict_errors builds, not built by users",
    "validation.SurfaceDescriptors": "a result surface_descriptors builds, not built by users",
}


def table() -> tuple[EntryPoint, ...]:
    """Every row: the bem, asperity and validation entry points."""
    from validation.campaigns import _bad_input_asperity, _bad_input_bem, _bad_input_validation

    return _bad_input_bem.rows() + _bad_input_asperity.rows() + _bad_input_validation.rows()
