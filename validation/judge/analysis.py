"""One scene judged: its results with the comparisons against the reference, the paper's
findings and, for a scene sampled at several intervals, its sampling study, by sweep value
(D, H, L), and the findings that span the sweep (the size sweep's sealing claim, finding g)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from validation.judge.compare import COMPARED_QUANTITIES, Comparison, compare_realizations
from validation.judge.verdicts import UNDECIDED
from validation.judge.findings import Finding, check_findings
from validation.judge.headline import HeadlineCell, headline
from validation.judge.sampling import SamplingStudy, sampling_finding, sampling_study
from validation.judge.sealing import SizeCollapse, d1_measures_leakage, sealing_size
from validation.common import models
from validation.run.runner import SceneResult
from validation.run.sequential import scene_plan
from validation.surfaces.spec import SIDES_SWEEP

__all__ = ["Analysis", "analyse", "undecided_counts"]


@dataclass(frozen=True)
class Analysis:
    """One scene's results with its comparisons and findings, by sweep value (D, H, L);
    ``scene_findings`` span the sweep (finding g over the sizes of a size sweep, whose
    numbers are ``size_collapse``); ``headlines`` every model's error at the headline's
    contact-area fractions, by sweep value (:mod:`validation.judge.headline`)."""

    result: SceneResult
    comparisons: list[Comparison] = field(default_factory=list)
    findings: dict[float, list[Finding]] = field(default_factory=dict)
    sampling: dict[float, SamplingStudy] = field(default_factory=dict)  # with [sampling] factors
    scene_findings: list[Finding] = field(default_factory=list)
    size_collapse: SizeCollapse | None = None
    headlines: dict[float, list[HeadlineCell]] = field(default_factory=dict)


def analyse(result: SceneResult) -> Analysis:
    """Compare every sweep value (D, H, L) of a surface scene with the reference (the BEM),
    read every model's error at the headline's area fractions and check the paper's findings; a scene without a reference model gets no comparison. Scenes
    that ask for leakage get finding (f) per sweep value; a size sweep also finding (g)."""
    scene = result.scene
    if scene.kind == "theory" or not set(scene.models) & set(models.reference_names()):
        return Analysis(result)
    comparisons, findings, studies = [], {}, {}
    plan = scene_plan(scene)  # 95 %, or the 5 % split between the looks of a budget
    leakage = "leakage" in scene.quantities
    for value, realizations in sorted(result.realizations.items()):
        confidence = plan.confidence_for(len(realizations))
        comparison = compare_realizations(realizations, tolerances=scene.tolerances,
                                          confidence=confidence)
        comparisons.append(comparison)
        findings[value] = check_findings(realizations, comparison, scene.tolerances)
        if leakage:
            findings[value].append(d1_measures_leakage(realizations, max(scene.tolerances)))
        study = sampling_study(realizations, scene.tolerances)
        findings[value].append(sampling_finding(study))
        if study is not None:
            studies[value] = study
    scene_findings, collapse = [], None
    if leakage and scene.surface.sweep_name == SIDES_SWEEP[1]:
        finding, collapse = sealing_size(result.realizations, scene.m, max(scene.tolerances))
        scene_findings.append(finding)
    headlines = {c.value: headline(c) for c in comparisons}
    return Analysis(result, comparisons, findings, studies, scene_findings, collapse, headlines)


def undecided_counts(analysis: Analysis) -> dict[tuple[float, str], tuple[int, int]]:
    """Undecided cells of a scene and all its cells, per tolerance and reading.

    A cell is one compared model and quantity at one load point of one sweep value; the
    readings are ``"mean"`` (the verdict on the mean error) and ``"per surface"``. Returns
    ``{(tolerance, reading): (undecided, cells)}``; empty for a scene without comparisons."""
    counts: dict[tuple[float, str], tuple[int, int]] = {}
    for comparison in analysis.comparisons:
        for (_, quantity), entry in comparison.models.items():
            if quantity not in COMPARED_QUANTITIES:
                continue
            for reading, verdicts in (("mean", entry.verdicts),
                                      ("per surface", entry.surface_verdicts)):
                for tolerance, verdict in zip(entry.tolerances, verdicts):
                    open_, cells = counts.get((tolerance, reading), (0, 0))
                    counts[tolerance, reading] = (
                        open_ + int(np.count_nonzero(np.asarray(verdict) == UNDECIDED)),
                        cells + int(np.size(verdict)))
    return counts
