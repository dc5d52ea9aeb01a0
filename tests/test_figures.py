"""The report's figures: fixed layouts that hold their labels, the same bytes from a process pool."""

import re
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

import validation.report.write
from validation import run_scenes
from validation.scenes.reader import parse_scene

SWEEP = {
    "name": "sweep",
    "title": "Two fractal dimensions",
    "surface": {"D": [2.2, 2.6], "rms_slope": 0.1, "n": 32},
    "realizations": {"count": 2, "seed": 5},
    "loads": {"min": 1e-4, "max": 1e-2, "count": 4},
}
THEORY = {"name": "theory", "title": "GW and improved GW", "kind": "theory"}


@pytest.fixture(scope="module")
def results():
    return run_scenes([parse_scene(SWEEP, source="test"), parse_scene(THEORY, source="test")],
                      progress=False)


def queued_figures(results, tmp_path, monkeypatch):
    jobs = []
    monkeypatch.setattr(validation.report.write._Figures, "render",
                        lambda self, executor=None, cache_dir=None: jobs.extend(self.jobs))
    validation.report.write.write_report(results, tmp_path)
    return jobs


def test_every_label_lies_on_the_canvas_and_off_the_other_panels(results, tmp_path, monkeypatch):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    jobs = queued_figures(results, tmp_path, monkeypatch)
    names = [name for name, _, _ in jobs]
    assert "sweep-validity-map.png" in names and "theory-fig3-stiffness.png" in names
    for name, draw, panels in jobs:
        fig = draw()
        assert len([ax for ax in fig.axes if ax.get_label() != "colorbar"]) == panels, name
        renderer = FigureCanvasAgg(fig).get_renderer()
        fig.draw(renderer)
        canvas = fig.bbox
        boxes = [ax.get_tightbbox(renderer) for ax in fig.axes]
        for box in boxes:
            # every tick label, axis label and title of the panel on the canvas (1 pixel slack)
            assert box.x0 >= canvas.x0 - 1 and box.y0 >= canvas.y0 - 1, (name, box)
            assert box.x1 <= canvas.x1 + 1 and box.y1 <= canvas.y1 + 1, (name, box)
        for i, box in enumerate(boxes):
            for j, other in enumerate(fig.axes):
                if i != j:  # no label of one panel reaches into another panel's plotting area
                    area = other.get_window_extent(renderer)
                    overlap = (min(box.x1, area.x1) - max(box.x0, area.x0),
                               min(box.y1, area.y1) - max(box.y0, area.y0))
                    assert min(overlap) <= 1.0, (name, i, j)
        for legend in fig.legends:  # a legend beside or above the panels: on the canvas, off them
            box = legend.get_window_extent(renderer)
            assert box.x0 >= canvas.x0 - 1 and box.y0 >= canvas.y0 - 1, (name, box)
            assert box.x1 <= canvas.x1 + 1 and box.y1 <= canvas.y1 + 1, (name, box)
            for ax in fig.axes:
                area = ax.get_tightbbox(renderer)
                overlap = (min(box.x1, area.x1) - max(box.x0, area.x0),
                           min(box.y1, area.y1) - max(box.y0, area.y0))
                assert min(overlap) <= 1.0, (name, ax.get_label())
    # eight models: the errors' legend goes beside the panels, the map's models one per row
    figures = {name: draw() for name, draw, _ in jobs}
    assert len(figures["sweep-errors-D2.2.png"].legends) == 1
    assert not figures["sweep-errors-D2.2.png"].axes[0].get_legend()
    assert figures["sweep-validity-map.png"].legends


def test_figures_drawn_on_a_pool_are_those_drawn_here(results, tmp_path):
    validation.report.write.write_report(results, tmp_path / "here")
    with ProcessPoolExecutor(max_workers=2) as pool:
        validation.report.write.write_report(results, tmp_path / "pool", executor=pool)
    here = sorted(p.name for p in (tmp_path / "here").glob("*.png"))
    assert here == sorted(p.name for p in (tmp_path / "pool").glob("*.png")) and len(here) >= 6
    for name in here:
        first, second = ((tmp_path / folder / name).read_bytes() for folder in ("here", "pool"))
        assert first == second, name
    texts = [re.sub(r"\d{4}-\d\d-\d\dT[\d:]+", "", (tmp_path / folder / "report.md").read_text(
        encoding="utf-8")) for folder in ("here", "pool")]  # the same but for the time stamp
    assert texts[0] == texts[1]


def test_verdict_margin_fits_the_longest_row_label():
    from validation.report.layout import text_width as _text_width

    short, long = _text_width(["GW: area"], 7), _text_width(["GW: area", "x" * 60], 7)
    assert 0.2 < short < long and long == pytest.approx(_text_width(["x" * 60], 7))
    assert np.isclose(_text_width([], 7), 0.0)


def test_a_figure_drawn_before_from_the_same_data_comes_from_the_cache(results, tmp_path,
                                                                     monkeypatch):
    import dataclasses

    import validation.report.figures

    cache = tmp_path / "cache"
    validation.report.write.write_report(results, tmp_path / "first", cache_dir=cache)
    drawn = []
    png = validation.report.figures.png
    monkeypatch.setattr(validation.report.figures, "png", lambda fig: drawn.append(fig) or png(fig))
    validation.report.write.write_report(results, tmp_path / "second", cache_dir=cache)
    assert not drawn  # every figure from the cache, byte for byte
    for path in (tmp_path / "first").glob("*.png"):
        assert path.read_bytes() == (tmp_path / "second" / path.name).read_bytes()
    # one realization's BEM area changed: the figures that draw it are drawn again, no other
    sweep, theory = results
    first = sweep.realizations[2.2][0]
    bem = first.curves["bem"]
    changed = dataclasses.replace(first, curves={**first.curves, "bem": dataclasses.replace(
        bem, area=bem.area * 1.01)})
    moved = dataclasses.replace(sweep, realizations={
        **sweep.realizations, 2.2: [changed] + sweep.realizations[2.2][1:]})
    validation.report.write.write_report([moved, theory], tmp_path / "third", cache_dir=cache)
    redrawn = len(drawn)
    assert 0 < redrawn < len(list((tmp_path / "first").glob("*.png")))
