"""Write the user guide's results page (``docs/guide/results.md``) from the published report.

Every number on the page comes from the report's CSV tables: the headline at 10 % contact per
model and frame (``headline.csv``), the paper's claims per surface family (``findings.csv``),
finding (h) and the undecided share per scene (``verdicts.csv``); the run time from the top of
``report.md`` unless ``--run-time`` says more (for instance that the run was resumed from a
cache). The words around them are :data:`PAGE`.

Usage: ``python docs/results_page.py [--run-time TEXT] [RESULTS_DIR]`` (default
``docs/results``), after ``python -m validation report --publish``;
``tests/test_doc_examples.py`` checks that the page holds exactly what this writes.
"""

from __future__ import annotations

import argparse
import collections
import csv
import math
import pathlib
import re
import sys

from readme_results import _cell

from validation.common.labels import model_label, model_rank

ROOT = pathlib.Path(__file__).resolve().parents[1]
PAGE_PATH = ROOT / "docs" / "guide" / "results.md"

#: The headline columns: (title, scene, quantity, surface parameter or None).
KEY_COLUMNS = (("conductance, D = 2.05", "paper-wm-d205", "conductance", None),
               ("conductance, D = 2.95", "paper-wm-d295", "conductance", None),
               ("separation, D = 2.05", "paper-wm-d205", "separation", None),
               ("separation, D = 2.95", "paper-wm-d295", "separation", None))
SELF_AFFINE_H = (0.3, 0.5, 0.8)
KEY_FRACTION = 0.1
#: How the page names a surface family of ``findings.csv``.
FAMILIES = {"paper-wm-d205": "paper, D = 2.05", "paper-wm-d295": "paper, D = 2.95",
            "validity-map": "validity map", "self-affine": "self-affine",
            "sealing-size": "sealing size"}

PAGE = """\
# The published results

The published paper-scale result is [the published report](../results/report.md)
(`docs/results/report.md`, with its figures and CSV tables): the command, the version and the
run time are at its top. It is regenerated, never edited, by one command (full mode, the
default scenes, the previous report's Markdown, figures and CSVs replaced; {run_time}):

<!-- not run: minutes -->
```bash
python -m validation report --publish            # writes docs/results/
python docs/readme_results.py && python docs/results_page.py   # the README's table, this page
```

## Each theory in its own frame

Every model is judged against the reference of the problem it describes ([theory
8.10](../theory.md#810-two-frames-the-interface-and-the-finite-nominal-contact)): original GW,
GW and Bush-Gibson-Thomas from the spectrum, the discrete model without interaction and
Persson's theory against the surface solved as an unbounded interface (`bem_interface`: a
periodic surface as it is, a window of a larger one through its mirror image), per unit
nominal area and without bulk deformation; improved GW (counted summits and from the spectrum)
and the discrete model with interaction against the finite window pressed as a whole (`bem`),
whose uniform bulk deformation is improved GW's interaction term. The headline tables, the
atlas rows, `headline.csv`, `errors.csv`, `verdicts.csv` and `validity.csv` name each model's
frame; the front page gives each frame's headline at its own reference's contact-area
fractions. Every synthetic surface of the default scenes is periodic, so its interface
reference is the periodic solution of the surface itself, exact up to the discretisation band;
only the sealing scene's nested windows go through their mirror image, whose method error is a
bias on the mean and a bound on one surface
([Benchmarks](benchmarks.md#the-interface-reference-python-benchmarksbench_interfacepy)).

{key_numbers}

## Where each theory holds

Every scene's page lists, per model, quantity and tolerance, the longest run of load points
whose verdict is "holds" (on the mean over realizations and per surface), with the reference's
contact-area fraction over it (`validity.csv`), and the paper's findings with the numbers that
decide them. The README's table gives the paper scenes' headline at 1 % and 10 % contact,
generated from `headline.csv` by `python docs/readme_results.py`.

Persson's theory predicts the mean gap ū (rigid plane to the deformed surface), so its row is
compared with the reference's mean gap, while the asperity models' separation d (rigid plane to
the undeformed mean plane) is compared with the reference's d; in the interface frame the two
are the same (the interface has no bulk deformation).

The paper's claims in the published run (`findings.csv`; a family of several surfaces, such as
the validity map's dimensions D, counts its verdicts):

{findings}

## Which sampling

The summit-fitted models (original and improved GW, the discrete models) count their summits on
the height map as sampled, so their answers could move with the sampling interval. By default
they use the scene's own grid, h = L/n, the grid the BEM solves: the models and the reference
then see one and the same surface, and on the WM surfaces (shortest wavelength L/γ⁸ = L/25.6,
20 grid steps at n = 512) that sampling resolves every summit the surface has. The paper scenes
check this (`[sampling] factors = [1, 2, 4]`, finding (h) and the report's section "The
sampling interval"; [theory 2.7](../theory.md#27-sampling-interval)): the same realizations
sampled at 2h and 4h (every 2nd and 4th point, mean plane kept) against the same BEM solution.
*Measured on a 512 × 512 run of the two paper scenes with 8 realizations and 12 loads (not the
published run):* at 2h the summit density falls to 0.96 (D = 2.05) and 0.98 (D = 2.95) of that
at h and every model's answer moves by at most 1.1 % in area, 0.7 % in conductance and 0.02 σ in
separation (medians over the load path); at 4h (5 steps per shortest wavelength) the density is
0.83 and 0.90, the area moves by up to +4.6 %, the separation by up to −0.08 σ and the
conductance of the discrete model without interaction by −7 %, so finding (h) is undecided (no
answer moves beyond ±5 % at most loads). *Quick run (`python -m validation report paper-wm-d205
paper-wm-d295 --quick`, 256 × 256, 8 realizations):* there 4h is 2.5 steps per shortest
wavelength, the density falls to 0.54 and 0.67, every summit-fitted model's area moves by
+20–21 % at all 12 loads at D = 2.95 and finding (h) is reproduced there (from 4h on),
undecided at D = 2.05. The samplings cost no BEM solve: 0.2–0.3 s per realization for the four
models at 2h and 4h, against 5–6 s (n = 256) and 27–31 s (n = 512) for the BEM path.

{sampling}

## How decided each scene is

Each built-in scene spends its extra effort where its undecided cells are held: the validity
map (10 → 20 realizations per D) and the self-affine map (8 → 16 per H) get budgets of
realizations and a finer reference; the paper scenes keep their 25 realizations and solve the
reference again on 1024² where its band holds a cell. Undecided cells, all models and
quantities of each scene, in the published run (`verdicts.csv`; per surface: the verdict for
single surfaces):

{decided}

An undecided cell says why in the scene's tables: the reference's band, too few realizations
(a mean error within a confidence half-width of the tolerance, which only several times the
realizations narrow enough) or the scatter between surfaces.
"""


def _rows(folder: pathlib.Path, name: str) -> list[dict]:
    path = folder / name
    if not path.is_file():
        raise ValueError(f"{path} is missing: run python -m validation report --publish first")
    with path.open(newline="", encoding="utf-8") as stream:
        return list(csv.DictReader(stream))


def _same(text: str, value: float | None) -> bool:
    return value is None or (text != "" and math.isclose(float(text), value))


def key_numbers(headline: list[dict]) -> str:
    """The headline at 10 % contact per model (with its frame), at the largest tolerance."""
    tolerance = max(float(r["tolerance"]) for r in headline)
    cells = [r for r in headline if math.isclose(float(r["tolerance"]), tolerance)
             and math.isclose(float(r["area_fraction"]), KEY_FRACTION)]

    def cell(model: str, scene: str, quantity: str, H: float | None) -> str:
        return _cell(next((r for r in cells if r["model"] == model and r["scene"] == scene
                           and r["quantity"] == quantity and _same(r.get("H", ""), H)), None))

    header = [title for title, *_ in KEY_COLUMNS] + [
        "conductance, self-affine H = " + " / ".join(f"{h:g}" for h in SELF_AFFINE_H)]
    lines = [f"Mean error at {100 * KEY_FRACTION:g} % contact (95 % interval over realizations; "
             f"✔ holds, ✘ fails, ? undecided within {tolerance:g}), against the reference of "
             f"each model's frame (`headline.csv`; conductance in %, separation in σ):", "",
             "| model (frame) | " + " | ".join(header) + " |", "|---" * (len(header) + 1) + "|"]
    for model in sorted({r["model"] for r in cells}, key=model_rank):
        frame = next((r.get("frame", "") for r in cells if r["model"] == model), "")
        row = [cell(model, scene, quantity, H) for _, scene, quantity, H in KEY_COLUMNS]
        row.append(" / ".join(cell(model, "self-affine", "conductance", h) for h in SELF_AFFINE_H))
        if all(value.strip("– /") == "" for value in row):
            continue
        lines.append(f"| {model_label(model)}{f' ({frame})' if frame else ''} | "
                     + " | ".join(row) + " |")
    lines += ["", "Separation in units of σ (Persson: its mean gap ū)."]
    return "\n".join(lines)


def _verdict_of(row: dict) -> str:
    return "not tested" if row.get("evidence", "").startswith("not tested") else row["verdict"]


def findings_table(findings: list[dict]) -> str:
    """Per claim of the paper, its verdict on each surface family (counts for a family of
    several surfaces)."""
    families = list(dict.fromkeys(r["scene"] for r in findings))
    claims = dict(sorted({r["finding"]: r["claim"] for r in findings}.items()))
    lines = ["| claim | " + " | ".join(FAMILIES.get(s, f"`{s}`") for s in families) + " |",
             "|---" * (len(families) + 1) + "|"]
    for key, claim in claims.items():
        if all(r["verdict"] == "not in the paper" for r in findings if r["finding"] == key):
            continue   # an overview the paper does not claim (finding (e)): the tables hold it
        row = []
        for scene in families:
            verdicts = [_verdict_of(r) for r in findings
                        if r["scene"] == scene and r["finding"] == key]
            counts = collections.Counter(verdicts)
            row.append("–" if not verdicts else verdicts[0] if len(verdicts) == 1 else
                       ", ".join(f"{n} {v}" for v, n in sorted(counts.items(),
                                                                key=lambda i: (-i[1], i[0]))))
        lines.append(f"| ({key}) {claim} | " + " | ".join(row) + " |")
    return "\n".join(lines)


def sampling_sentence(findings: list[dict]) -> str:
    """Finding (h) of the published run, per scene that tested it."""
    tested = [r for r in findings if r["finding"] == "h" and _verdict_of(r) != "not tested"]
    if not tested:
        return "*Published run:* finding (h) not tested."
    parts = []
    for scene in dict.fromkeys(r["scene"] for r in tested):
        where = ", ".join(f"{r['verdict']} at " + (f"D = {r['D']}" if r["D"] else f"H = {r['H']}")
                          for r in tested if r["scene"] == scene)
        parts.append(f"`{scene}`: {where}")
    return ("*Published run:* finding (h), " + "; ".join(parts)
            + " (the median shifts behind each verdict are on the scene pages).")


def decided_table(verdicts: list[dict]) -> str:
    """The undecided share on the mean (every tolerance) and per surface, per scene."""
    tolerances = sorted({float(r["tolerance"]) for r in verdicts}, reverse=True)
    by = collections.defaultdict(collections.Counter)
    for r in verdicts:
        count = by[(r["scene"], float(r["tolerance"]))]
        count["cells"] += 1
        count["undecided"] += r["verdict"] == "undecided"
        count["surface"] += r.get("verdict_per_surface", "") != ""
        count["surface undecided"] += r.get("verdict_per_surface", "") == "undecided"
    lines = [f"| scene | undecided on the mean at {' / '.join(f'{t:g}' for t in tolerances)} "
             f"| per surface at {tolerances[0]:g} |", "|---|---|---|"]
    for scene in sorted({r["scene"] for r in verdicts}):
        mean = " / ".join(f"{100 * by[(scene, t)]['undecided'] / by[(scene, t)]['cells']:.0f} %"
                          for t in tolerances)
        first = by[(scene, tolerances[0])]
        surface = (f"{100 * first['surface undecided'] / first['surface']:.0f} %"
                   if first["surface"] else "–")
        lines.append(f"| `{scene}` | {mean} | {surface} |")
    return "\n".join(lines)


def report_run_time(folder: pathlib.Path) -> str:
    """The run time the report states at its top, e.g. ``116.8 min``."""
    text = (folder / "report.md").read_text(encoding="utf-8")
    match = re.search(r"run time ([^;(]+?)\s*[;(]", text)
    if not match:
        raise ValueError(f"{folder / 'report.md'} states no run time")
    return match.group(1)


def page(folder: str | pathlib.Path, run_time: str | None = None) -> str:
    """The results page from the published report in ``folder``."""
    folder = pathlib.Path(folder)
    findings = _rows(folder, "findings.csv")
    run_time = run_time or f"{report_run_time(folder)} on two cores, from an empty cache"
    return PAGE.format(run_time=run_time, key_numbers=key_numbers(_rows(folder, "headline.csv")),
                       findings=findings_table(findings), sampling=sampling_sentence(findings),
                       decided=decided_table(_rows(folder, "verdicts.csv")))


def written_run_time(path: pathlib.Path = PAGE_PATH) -> str | None:
    """The run-time text the page was last written with (the test regenerates it alike)."""
    if not path.is_file():
        return None
    match = re.search(r"regenerated, never edited.*?replaced; (.*?)\):\n", path.read_text(
        encoding="utf-8"), re.S)
    return None if match is None else " ".join(match.group(1).split())


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder", nargs="?", default=str(ROOT / "docs" / "results"))
    parser.add_argument("--run-time", default=None,
                        help="what the page says of the run's time (default: the report's own "
                             "run time, on two cores from an empty cache)")
    args = parser.parse_args(argv)
    PAGE_PATH.write_text(page(args.folder, args.run_time), encoding="utf-8")
    print(f"{PAGE_PATH.relative_to(ROOT)} written from {args.folder}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
