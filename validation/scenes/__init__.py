"""Scenes: the frozen scene dataclasses (:mod:`~validation.scenes.scene`, their field checks in
:mod:`validation.common.checks`), the TOML reader (:mod:`~validation.scenes.reader`) and the
built-in scene files (``*.toml`` in this folder)."""
