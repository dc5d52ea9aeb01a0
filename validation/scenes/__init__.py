"""Scenes: the frozen scene dataclasses (:mod:`~validation.scenes.scene`), their checks, the TOML
reader (:mod:`~validation.scenes.reader`) and the built-in scene files (``*.toml`` in this folder)."""
