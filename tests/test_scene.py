"""Scene parsing and validation."""


import numpy as np
import pytest

from validation.scenes.scene import SceneError
from validation.scenes.reader import builtin_scenes, load_scene, parse_scene


def test_every_builtin_scene_loads():
    names = builtin_scenes()
    assert {"paper-theory", "paper-wm-d205", "paper-wm-d295", "validity-map"} <= set(names)
    for name in names:
        scene = load_scene(name)
        assert scene.name == name
        quick = scene.quick_version()
        if scene.kind == "surface":
            assert quick.realizations <= scene.realizations
            assert quick.surface.n <= scene.surface.n


def test_paper_scenes_match_the_paper():
    for name, D in (("paper-wm-d205", 2.05), ("paper-wm-d295", 2.95)):
        scene = load_scene(name)
        assert scene.surface.D == (D,)
        assert (scene.surface.gamma, scene.surface.n_max, scene.surface.M) == (1.5, 8, 10)
        assert scene.realizations == 25
        assert "bem" in scene.models
    assert load_scene("validity-map").surface.D == (2.05, 2.2, 2.4, 2.6, 2.8, 2.95)
    theory = load_scene("paper-theory")
    assert theory.kind == "theory" and theory.theory.C == (5.0, 50.0) and theory.surface is None


def write(tmp_path, text, name="scene.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


GOOD = """
[surface]
D = 2.3
rms_slope = 0.1
n = 32
"""


def test_user_file_and_defaults(tmp_path):
    scene = load_scene(write(tmp_path, GOOD, "mine.toml"))
    assert scene.name == "mine"
    assert scene.surface.n == 32 and scene.surface.D == (2.3,)
    assert scene.tolerances == (0.05, 0.2)
    assert len(scene.loads.values()) == scene.loads.count


@pytest.mark.parametrize("text, key", [
    ("unknown_top = 1\n" + GOOD, "unknown_top"),
    (GOOD.replace("n = 32", "n = 32\nwhatever = 3"), "surface.whatever"),
    (GOOD.replace("D = 2.3", "D = 3.5"), "surface.D"),
    (GOOD.replace("D = 2.3", "D = [2.1, 2.0]"), "surface.D"),
    (GOOD.replace("rms_slope = 0.1", "rms_slope = 0.1\nG = 1e-3"), "surface.rms_slope"),
    (GOOD.replace("n = 32", "n = 4"), "surface.n"),
    (GOOD.replace("n = 32", "n = 32.5"), "surface.n"),
    (GOOD + "\n[models]\nuse = [\"gw\", \"magic\"]\n", "models.use"),
    (GOOD + "\n[quantities]\nuse = [\"pressure\"]\n", "quantities.use"),
    (GOOD + "sides = [1.0, 1.7]\n", "surface.sides"),          # 32 x 1.7 = 54.4 points
    (GOOD + "sides = [1.0, 2.0]\nL = 2.0\n", "surface.L"),
    (GOOD + "sides = [1.0, 1.0]\n", "surface.sides"),
    (GOOD + "sides = [1.0, -2.0]\n", "surface.sides"),
    (GOOD.replace("D = 2.3", "D = [2.1, 2.3]") + "sides = [1.0, 2.0]\n", "surface.sides"),
    (GOOD + "wavelength = 0\n", "surface.wavelength"),
    (GOOD + "\n[loads]\nmin = 1e-2\nmax = 1e-3\n", "loads.max"),
    (GOOD + "\n[loads]\nquantity = \"force\"\n", "loads.quantity"),
    (GOOD + "\n[bem]\ntol = -1\n", "bem.tol"),
    (GOOD + "\n[bem]\nperiodic = \"yes\"\n", "bem.periodic"),
    (GOOD + "\n[tolerances]\nlevels = [0.05, -0.2]\n", "tolerances.levels"),
    (GOOD + "\n[theory]\nC = [5.0]\n", "theory"),
    ("kind = \"theory\"\n[surface]\nD = 2.3\n", "surface"),
    ("kind = \"theory\"\n[theory]\nC = [-1.0]\n", "theory.C"),
    ("kind = \"sketch\"\n", "kind"),
])
def test_bad_scene_names_key_and_file(tmp_path, text, key):
    path = write(tmp_path, text, "bad-scene.toml")
    with pytest.raises(SceneError) as info:
        load_scene(path)
    message = str(info.value)
    assert f"'{key}'" in message
    assert "bad-scene.toml" in message


def test_invalid_toml_and_missing_file(tmp_path):
    with pytest.raises(SceneError, match="bad.toml.*not valid TOML"):
        load_scene(write(tmp_path, "this is = = not toml", "bad.toml"))
    with pytest.raises(SceneError, match="no such scene"):
        load_scene(tmp_path / "missing.toml")


def test_parse_scene_is_a_value_error():
    with pytest.raises(ValueError):
        parse_scene({"surface": {"D": 2.5}}, source="inline")


def test_dataclasses_validate_themselves():
    from dataclasses import replace

    from validation.scenes.scene import BemSettings, LoadPath, SurfaceSpec, TheorySpec

    scene = load_scene("paper-wm-d205")
    for changes, key in ((dict(realizations=-2), "realizations"), (dict(e_star=0.0), "e_star"),
                         (dict(models=("gw", "magic")), "models"),
                         (dict(tolerances=()), "tolerances"), (dict(surface=None), "surface")):
        with pytest.raises(SceneError, match=f"'{key}'"):
            replace(scene, **changes)
    with pytest.raises(SceneError, match="'min'"):
        LoadPath(min=0.0, spacing="log")
    with pytest.raises(SceneError, match="'max'"):
        LoadPath(min=1e-2, max=1e-3)
    with pytest.raises(SceneError, match="'n'"):
        SurfaceSpec(D=(2.3,), n=8)
    with pytest.raises(SceneError, match="'tol'"):
        BemSettings(tol=float("nan"))
    with pytest.raises(SceneError, match="'separation_max'"):
        TheorySpec(separation_min=1.0, separation_max=0.0)


def test_defaults_are_the_dataclass_defaults(tmp_path):
    from validation.scenes.scene import BemSettings, LoadPath, QuickSettings, Scene, defaults

    scene = load_scene(write(tmp_path, GOOD))
    assert scene.loads == LoadPath() and scene.bem == BemSettings()
    assert scene.quick == QuickSettings()
    base = defaults(Scene)
    for key in ("realizations", "seed", "e_star", "models", "m", "quantities", "tolerances"):
        assert getattr(scene, key) == base[key], key
    separation = LoadPath(quantity="separation")
    assert (separation.min, separation.max, separation.spacing) == (0.0, 3.0, "linear")


def test_sealing_size_scene_sweeps_nested_windows_of_one_spacing():
    from validation.run.realization import plan_scene

    scene = load_scene("sealing-size")
    assert "leakage" in scene.quantities and {"gw", "improved_gw", "bem"} <= set(scene.models)
    surface = scene.surface
    assert surface.sweep_name == "L" and surface.sweep_values == (1.0, 2.0, 4.0)
    assert surface.L == 1.0 and surface.wavelength == 1.0 and len(surface.D) == 1
    for quick in (False, True):
        tasks = plan_scene(scene.quick_version() if quick else scene)
        spacings = {t.surface.spacing for t in tasks}
        assert len(spacings) == 1                      # the same grid spacing on every size
        by_side = {t.sweep_value: t.surface for t in tasks}
        assert sorted(by_side) == [1.0, 2.0, 4.0]
        for side, spec in by_side.items():
            assert spec.L == side and spec.wavelength == 1.0 and spec.sides == (side,)
        assert [by_side[s].n for s in (1.0, 2.0, 4.0)] == (
            [64, 128, 256] if quick else [128, 256, 512])
        # the same seeds on every size: realization k is a nested window of one surface
        assert len({tuple(sorted(t.seed for t in tasks if t.sweep_value == s))
                    for s in by_side}) == 1


def test_nested_windows_are_one_surface():
    from validation.surfaces.families import surface_heights, surface_identity

    scene = load_scene("sealing-size").quick_version()
    small, large = (scene.surface.at(side) for side in (1.0, 2.0))
    a, b = surface_heights(small, 3), surface_heights(large, 3)
    assert b.shape == (2 * a.shape[0],) * 2
    # the windows are scaled to the rms slope each on its own, so the corner agrees up to a
    # constant offset and a factor near 1
    corner = b[:a.shape[0], :a.shape[1]]
    factor = np.std(corner) / np.std(a)
    np.testing.assert_allclose(corner - corner.mean(), factor * (a - a.mean()), atol=1e-12)
    assert 0.8 < factor < 1.25
    assert surface_identity(small, 3) != surface_identity(large, 3)



def test_paper_scenes_ask_for_leakage_and_the_default_report_has_the_size_scene():
    from validation.cli import DEFAULT_SCENES

    for name in ("paper-wm-d205", "paper-wm-d295"):
        assert "leakage" in load_scene(name).quantities
    assert "sealing-size" in DEFAULT_SCENES


def test_quick_mode_may_leave_out_quantities():
    scene = load_scene("paper-wm-d205")
    assert "leakage" in scene.quantities
    quick = scene.quick_version()
    assert "leakage" not in quick.quantities and "conductance" in quick.quantities
    # the sealing scene keeps its leakage in quick mode (it exists to measure it)
    assert "leakage" in load_scene("sealing-size").quick_version().quantities
    data = {"surface": {"D": 2.3, "rms_slope": 0.1, "n": 32},
            "quick": {"quantities": ["area", "flow"]}}
    with pytest.raises(SceneError, match="quick.quantities"):
        parse_scene(data)
