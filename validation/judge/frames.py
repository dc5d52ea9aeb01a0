"""Which reference each model is judged against: the frames of a comparison (docs/theory.md 8.10).

A model describes either an unbounded interface or a finite nominal contact (its registry
entry's ``frame``); the results of a realization hold the reference of each frame the scene
computes. Each model is compared with the reference of its own frame, or, where the scene left
that frame out, with the other one (its rows then say which).
"""

from __future__ import annotations

from validation.common import models

__all__ = ["judged_frame", "references_of", "source_key"]


def source_key(field_name: str, frame: str, primary_frame: str) -> str:
    """The key of ``Comparison.band_source``: the field, with its frame unless primary."""
    return field_name if frame == primary_frame else f"{field_name} ({frame})"


def judged_frame(model: str, references: dict[str, str], primary_frame: str) -> str:
    """The frame a model is judged in: its registry entry's where that frame's reference is
    among ``references`` (frame -> reference); otherwise ``primary_frame`` (a scene that
    computes one frame's reference only, ``[bem] frames``, or a model the registry does not
    know). The comparison's entry records the frame it was judged in."""
    if model in models.names() and models.frame_of(model) in references:
        return models.frame_of(model)
    return primary_frame


def references_of(curves, reference_model: str | None) -> dict[str, str]:
    """frame -> reference model among ``curves``: the one named (its frame), else each
    frame's registered reference present; ValueError when there is none."""
    if reference_model is not None:
        if reference_model not in curves:
            raise ValueError(f"the results hold no {reference_model!r} reference curve "
                             f"(reference_model must be a model of the results)")
        frame = models.frame_of(reference_model) if reference_model in models.names() \
            else "finite"
        return {frame: reference_model}
    found = {frame: models.reference_among(curves, frame) for frame in models.FRAMES}
    found = {frame: name for frame, name in found.items() if name is not None}
    if not found:
        raise ValueError(f"the results hold no registered reference curve (registered "
                         f"references: {', '.join(models.reference_names())})")
    return found
