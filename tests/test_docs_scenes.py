"""docs/guide/scenes.md lists every scene key the reader accepts, with the reader's default and
an example that parses, and the built-in scenes as they are.

The key tables follow a marker line ``<!-- scene keys: TABLE [FAMILY] -->`` (``top`` for the
top level; ``surface FAMILY`` for the keys of one surface family). Each row gives the key, its
default (in code font: a TOML value the reader fills in when the key is absent, so writing it
changes nothing; in words: a default that depends on other keys) and an example (one or more
``key = value`` lines in code font, set together in a scene of that family).

Which keys the reader accepts is found by asking it: every name of a field of the scene
dataclasses, of ``read_topography``'s keywords and of the documented keys is tried in every
table of a valid scene, and a key is accepted unless the reader answers that it is unknown.
"""

from __future__ import annotations

import copy
import dataclasses
import inspect
import pathlib
import re
import shutil
import tomllib
import warnings

import numpy as np
import pytest

import validation
from validation.cli import DEFAULT_SCENES, FULL_ONLY_SCENES

ROOT = pathlib.Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "guide" / "scenes.md"
EXAMPLE_SCAN = ROOT / "examples" / "example_topography.txt"
#: Keys written up ahead of the program, in the marked pending section of another page (table,
#: family, key, page): accepted or not yet, they count as documented. When one lands, move it
#: into the key table of scenes.md and drop it here.
PENDING: set = set()

_MARKER = re.compile(r"^<!-- scene keys: (\w+)(?: ([\w-]+))? -->$")
_CELL = re.compile(r"`([^`]+)`")
#: What the reader says of a key it does not take (and of a table in the wrong kind of scene).
_UNKNOWN = re.compile(r"is not a known key|is not a key of family|is not a parameter of family|"
                      r"does not belong|belongs only|is not a keyword of read_topography")
_PROBE = "\x00probe"


@dataclasses.dataclass(frozen=True)
class Row:
    table: str          # "top", "surface", "loads", ...
    family: str | None  # a surface family, for the family's own [surface] keys
    key: str
    default: str        # the default cell as written
    example: dict       # the example's keys and values


def _rows() -> list[Row]:
    lines = PAGE.read_text(encoding="utf-8").splitlines()
    rows = []
    for number, line in enumerate(lines):
        found = _MARKER.match(line.strip())
        if not found:
            continue
        table, family = found.groups()
        body = [x for x in lines[number + 1:number + 60]]
        while body and not body[0].strip():
            body.pop(0)
        table_lines = []
        for x in body:
            if not x.startswith("|"):
                break
            table_lines.append(x)
        assert len(table_lines) > 2, f"scenes.md line {number + 1}: no key table after the marker"
        for x in table_lines[2:]:
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", x.strip())[1:-1]]
            key, default, example = cells[0].strip("`"), cells[1], cells[2]
            snippets = _CELL.findall(example)
            assert snippets, f"scenes.md: key {key!r} has no example"
            rows.append(Row(table, family, key, default,
                            tomllib.loads("\n".join(snippets))))
    return rows


ROWS = _rows()


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> pathlib.Path:
    """The scene folder of the measured-map examples: the example scan, and the same heights as
    a bare array (a file that states neither its size nor its unit)."""
    path = tmp_path_factory.mktemp("scenes")
    shutil.copy(EXAMPLE_SCAN, path / EXAMPLE_SCAN.name)
    heights = validation.read_topography(EXAMPLE_SCAN, height_unit="nm").heights
    np.save(path / "heights.npy", heights)
    return path


def _base(family: str) -> dict:
    if family == "theory":
        return {"kind": "theory"}
    surface = {"wm": {"D": 2.3, "rms_slope": 0.1},
               "self-affine": {"family": "self-affine", "hurst": 0.8, "rms_slope": 0.1},
               "file": {"family": "file", "path": EXAMPLE_SCAN.name}}[family]
    return {"surface": dict(surface)}


def _family(row: Row) -> str:
    return "theory" if row.table == "theory" else (row.family or "wm")


def _with(data: dict, table: str, values: dict) -> dict:
    data = copy.deepcopy(data)
    if table == "surface" and set(values) & {"G", "rms_height"}:
        data["surface"].pop("rms_slope", None)   # the other amplitude instead
    (data if table == "top" else data.setdefault(table, {})).update(values)
    return data


def _parse(data: dict, folder: pathlib.Path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # SceneWarning: a valid scene
        return validation.parse_scene(data, source="scenes.md", folder=folder)


def _accepts(data: dict, folder: pathlib.Path) -> bool:
    try:
        _parse(data, folder)
    except validation.SceneError as error:
        return not _UNKNOWN.search(str(error))
    except Exception:  # the key was taken and its value refused further on
        return True
    return True


def test_the_page_has_key_tables():
    tables = {(row.table, row.family) for row in ROWS}
    assert ("top", None) in tables and ("surface", "wm") in tables and ("theory", None) in tables
    seen = [(row.table, row.family, row.key) for row in ROWS]
    assert len(seen) == len(set(seen)), "a key is listed twice in one table"


@pytest.mark.parametrize("row", ROWS, ids=lambda r: f"{r.table}.{r.family or ''}.{r.key}")
def test_each_example_parses(row, folder):
    assert row.key in row.example, f"the example of {row.key!r} does not set it"
    if row.example.get("reader") == "surfacetopography":
        pytest.importorskip("SurfaceTopography", reason="the example reads its map with "
                            "SurfaceTopography, the optional extra [topography], not installed")
    _parse(_with(_base(_family(row)), row.table, row.example), folder)


@pytest.mark.parametrize("row", [r for r in ROWS if _CELL.fullmatch(r.default)],
                         ids=lambda r: f"{r.table}.{r.family or ''}.{r.key}")
def test_each_default_is_the_readers(row, folder):
    value = tomllib.loads(f"value = {_CELL.fullmatch(row.default).group(1)}")["value"]
    base = _base(_family(row))
    assert _parse(_with(base, row.table, {row.key: value}), folder) == _parse(base, folder), (
        f"writing the documented default {row.key} = {value!r} changes the scene")


def _candidates() -> set[str]:
    """Every name a scene key could have: fields of the scene dataclasses (found from parsed
    scenes, so no internal module is named), read_topography's keywords, the documented keys and
    the names the reader gives fields in other tables."""
    wm = _parse(_base("wm"), ROOT)
    theory = _parse(_base("theory"), ROOT)
    parts = [wm, wm.surface, wm.loads, wm.bem, wm.quick, theory.theory]
    names = {f.name for part in parts for f in dataclasses.fields(part)}
    names |= {p.name for p in inspect.signature(validation.read_topography).parameters.values()
              if p.kind is p.KEYWORD_ONLY}
    names |= {row.key for row in ROWS} | {row.table for row in ROWS}
    return names | {"use", "levels", "factors", "max", "count", "seed", "height_unit", "family"}


def _documented(table: str, family: str | None) -> set[str]:
    keys = {row.key for row in ROWS if row.table == table and row.family in (family, None)}
    keys |= {key for t, f, key, _ in PENDING if t == table and f == family}
    if table == "top":
        keys |= {row.table for row in ROWS if row.table != "top"}
    return keys


def test_every_accepted_key_is_documented(folder):
    candidates = _candidates()
    missing = []
    for family in ("wm", "theory"):
        base = _base(family)
        accepted = {c for c in candidates if _accepts(_with(base, "top", {c: _PROBE}), folder)}
        missing += [f"top level: {k}" for k in sorted(accepted - _documented("top", None))]
        for table in sorted(accepted - {"name", "kind", "title", "description"}):
            if table == "surface":
                continue
            accepted_keys = {c for c in candidates
                             if _accepts(_with(base, table, {c: _PROBE}), folder)}
            missing += [f"[{table}] {k}" for k in sorted(accepted_keys - _documented(table, None))]
    for family in ("wm", "self-affine", "file"):
        base = _base(family)
        accepted = {c for c in candidates
                    if _accepts(_with(base, "surface", {c: _PROBE}), folder)}
        missing += [f"[surface] of {family}: {k}"
                    for k in sorted(accepted - _documented("surface", family))]
    missing = sorted(set(missing))
    assert not missing, f"scene keys the reader accepts that docs/guide/scenes.md does not list: {missing}"


def test_every_documented_key_belongs_to_its_family(folder):
    # an example parses in its own family; a family's key must also be refused by the others,
    # or it is listed under the wrong family (or should be under the common [surface] table)
    for row in (r for r in ROWS if r.table == "surface" and r.family is not None):
        others = [f for f in ("wm", "self-affine", "file") if f != row.family]
        taken = [f for f in others if _accepts(_with(_base(f), "surface", {row.key: _PROBE}),
                                               folder)]
        listed = [f for f in taken if row.key in _documented("surface", f)]
        assert taken == listed, f"[surface] {row.key} is accepted by families {taken} too"


def test_pending_keys_are_on_their_page():
    for table, _, key, page in PENDING:
        text = (ROOT / page).read_text(encoding="utf-8")
        begin, end = text.find("<!-- BEGIN pending"), text.find("<!-- END pending")
        assert 0 <= begin < end and key in text[begin:end], (
            f"{page} must describe the pending key [{table}] {key} in its pending section")


def test_the_built_in_scenes_are_listed_as_they_run():
    lines = PAGE.read_text(encoding="utf-8").splitlines()
    start = lines.index("<!-- built-in scenes -->")
    listed = {}
    for line in lines[start + 3:]:
        if not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip().split("|")[1:-1]]
        listed[cells[0].strip("`")] = cells[-1]
    assert set(listed) == set(validation.builtin_scenes())
    for name, where in listed.items():
        expected = ("full and published only" if name in FULL_ONLY_SCENES else
                    "default" if name in DEFAULT_SCENES else "not in the default report")
        assert where == expected, (name, where)
