"""The reference on a GPU (bem.elastic.device): the option, its errors, and the GPU code path.

Without a GPU the code path runs on :mod:`device_double`, a stand-in for CuPy whose arrays
refuse implicit host conversion as CuPy's do: the solves must equal the CPU's. Tests marked
``gpu`` run on CuPy itself and skip where there is no CUDA device.
"""

from __future__ import annotations

import sys
import types

import numpy as np
import pytest

import bem
import bem.elastic.device
import bem.elastic.halfspace
import bem.contact.preconditioner
from bem.elastic.device import array_module, check_device, to_host

import device_double


def _surface(n=64, seed=3):
    rng = np.random.default_rng(seed)
    spectrum = rng.standard_normal((n, n)) + 1j * rng.standard_normal((n, n))
    q = np.hypot(*np.meshgrid(np.fft.fftfreq(n), np.fft.fftfreq(n)))
    spectrum *= np.where(q > 0, q, np.inf) ** -1.8
    heights = np.fft.ifft2(spectrum).real
    return heights / heights.std() * 0.01


@pytest.fixture
def double(monkeypatch):
    """device="gpu" served by the CuPy stand-in."""
    def module(device, name="device"):
        return device_double if check_device(device, name) == "gpu" else np
    import asperity.discrete.interaction
    import validation.check.library
    import validation.cli

    for where in (bem.elastic.device, bem.elastic.halfspace, bem.contact.preconditioner, asperity.discrete.interaction,
                  validation.check.library, validation.cli):
        monkeypatch.setattr(where, "array_module", module)
    return device_double


def test_device_values_are_checked():
    assert array_module("cpu") is np
    with pytest.raises(ValueError, match=r"device must be one of 'cpu', 'gpu', got 'tpu'"):
        check_device("tpu")
    with pytest.raises(TypeError, match="device must be one of"):
        check_device(1)
    with pytest.raises(ValueError, match="device must be one of"):
        bem.solve_contact(_surface(), 1 / 64, load=1e-3, device="cuda")


def test_gpu_without_cupy_is_a_clear_error(monkeypatch):
    monkeypatch.setitem(sys.modules, "cupy", None)   # import cupy raises ImportError
    for call in (lambda: array_module("gpu"),
                 lambda: bem.solve_contact(_surface(), 1 / 64, load=1e-3, device="gpu"),
                 lambda: bem.HalfSpace((64, 64), 1 / 64, device="gpu"),
                 lambda: bem.BoundaryElementModel(_surface(), 1 / 64, device="gpu")):
        with pytest.raises(ValueError, match=r"device='gpu' needs CuPy, which is not installed"
                                             r".*\[gpu\].*device='cpu'"):
            call()


def test_gpu_without_a_device_is_a_clear_error(monkeypatch):
    def no_device():
        raise RuntimeError("cudaErrorNoDevice: no CUDA-capable device is detected")
    fake = types.SimpleNamespace(cuda=types.SimpleNamespace(
        runtime=types.SimpleNamespace(getDeviceCount=no_device)))
    monkeypatch.setitem(sys.modules, "cupy", fake)
    with pytest.raises(ValueError, match="CuPy is installed but finds no CUDA device "
                                         r"\(RuntimeError: cudaErrorNoDevice"):
        array_module("gpu")
    fake.cuda.runtime.getDeviceCount = lambda: 0
    with pytest.raises(ValueError, match="finds no CUDA device; use device='cpu'"):
        array_module("gpu")


def test_the_double_refuses_host_conversion():
    array = device_double.asarray(np.arange(3.0))
    with pytest.raises(TypeError, match="Implicit conversion"):
        np.asarray(array)
    with pytest.raises(TypeError, match="host array mixed"):
        np.add(array, np.ones(3))
    assert isinstance(np.multiply(array, 2.0), device_double.DeviceArray)
    np.testing.assert_array_equal(to_host(array * 2.0), [0.0, 2.0, 4.0])


def _same_solution(gpu, cpu, relative=1e-9):
    assert isinstance(gpu.pressure, np.ndarray) and isinstance(gpu.gap, np.ndarray)
    np.testing.assert_array_equal(gpu.contact, cpu.contact)
    for name in ("load", "area", "separation", "mean_gap"):
        assert getattr(gpu, name) == pytest.approx(getattr(cpu, name), rel=relative, abs=1e-15)
    if cpu.stiffness is not None:
        assert gpu.stiffness == pytest.approx(cpu.stiffness, rel=relative)
    np.testing.assert_allclose(gpu.pressure, cpu.pressure, rtol=0,
                               atol=relative * float(np.abs(cpu.pressure).max()))


def _solution(z, h, *, periodic, mirror, operator, device, problem):
    """One solve with its stiffness (the mirror quadrant's through a one-point path)."""
    if not mirror:
        return bem.solve_contact(z, h, periodic=periodic, stiffness=True, operator=operator,
                                 device=device, **problem)
    kept = []
    bem.contact_curve(z, h, periodic=True, mirror=True, operator=operator, device=device,
                      quantities=("area", "load", "separation", "stiffness"),
                      callback=lambda index, solution: kept.append(solution),
                      **{name + "s": [value] for name, value in problem.items()})
    return kept[0]


@pytest.mark.parametrize("periodic, mirror", [(False, False), (True, False), (True, True)])
def test_the_gpu_code_path_solves_as_the_cpu(double, periodic, mirror):
    z = _surface(128)
    h = 1 / 128
    for problem in ({"load": 2e-3}, {"separation": float(np.quantile(z, 0.97))}):
        cpu_operator = bem.HalfSpace(z.shape, h, periodic=periodic, mirror=mirror)
        gpu_operator = bem.HalfSpace(z.shape, h, periodic=periodic, mirror=mirror, device="gpu")
        assert isinstance(gpu_operator._fft.real_buffer, double.DeviceArray)
        cpu = _solution(z, h, periodic=periodic, mirror=mirror, operator=cpu_operator,
                        device="cpu", problem=problem)
        gpu = _solution(z, h, periodic=periodic, mirror=mirror, operator=gpu_operator,
                        device="gpu", problem=problem)
        assert cpu.converged and gpu.converged and 0 < cpu.area < 0.2 * z.size * h * h
        _same_solution(gpu, cpu)
    np.testing.assert_allclose(gpu_operator.displacement(cpu.pressure),
                               cpu_operator.displacement(cpu.pressure), rtol=1e-12, atol=1e-18)


def test_a_gpu_load_path_is_the_cpus(double):
    z = _surface(128, seed=5)
    loads = np.geomspace(1e-4, 1e-2, 4)
    options = dict(quantities=("area", "load", "separation", "conductance", "contacts",
                               "leakage"), periodic=True, mirror=True, error_estimate=True)
    cpu = bem.contact_curve(z, 1 / 128, loads=loads, **options)
    gpu = bem.contact_curve(z, 1 / 128, loads=loads, device="gpu", **options)
    for name in ("area", "separation", "conductance", "contacts", "leakage"):
        np.testing.assert_allclose(getattr(gpu, name), getattr(cpu, name), rtol=1e-9)
    np.testing.assert_allclose(gpu.extras["area_error"], cpu.extras["area_error"], rtol=1e-9)
    model = bem.BoundaryElementModel(z, 1 / 128, periodic=True, device="gpu")
    np.testing.assert_allclose(model.at_load(loads).area,
                               bem.BoundaryElementModel(z, 1 / 128, periodic=True)
                               .at_load(loads).area, rtol=1e-9)


def test_a_gpu_path_starts_from_host_coarse_pressures(double):
    """Coarse pressures kept on the host (validation.run.starts) start a device path."""
    z = _surface(128, seed=5)
    loads = np.geomspace(1e-4, 1e-2, 3)
    kept = {}
    bem.contact_curve(z[::2, ::2], 2 / 128, loads=loads, periodic=True, mirror=True,
                      callback=lambda index, solution: kept.__setitem__(index, solution.pressure))
    options = dict(periodic=True, mirror=True, coarse_pressures=kept)
    cpu = bem.contact_curve(z, 1 / 128, loads=loads, **options)
    gpu = bem.contact_curve(z, 1 / 128, loads=loads, device="gpu", **options)
    for name in ("area", "separation"):
        np.testing.assert_allclose(getattr(gpu, name), getattr(cpu, name), rtol=1e-9)


def _cupy_or_skip():
    try:
        return array_module("gpu")
    except ValueError as error:
        pytest.skip(str(error))


@pytest.mark.gpu
@pytest.mark.parametrize("periodic, mirror", [(False, False), (True, False), (True, True)])
def test_cupy_solves_as_the_cpu(periodic, mirror):
    _cupy_or_skip()
    z = _surface(256)
    for problem in ({"load": 2e-3}, {"separation": float(np.quantile(z, 0.97))}):
        cpu, gpu = (_solution(z, 1 / 256, periodic=periodic, mirror=mirror, device=device,
                              problem=problem,
                              operator=bem.HalfSpace(z.shape, 1 / 256, periodic=periodic,
                                                     mirror=mirror, device=device))
                    for device in ("cpu", "gpu"))
        _same_solution(gpu, cpu)


@pytest.mark.gpu
def test_cupy_load_path_is_the_cpus():
    _cupy_or_skip()
    z = _surface(256, seed=5)
    loads = np.geomspace(1e-4, 1e-2, 6)
    options = dict(quantities=("area", "load", "separation", "conductance", "leakage"),
                   periodic=True, error_estimate=True)
    cpu = bem.contact_curve(z, 1 / 256, loads=loads, **options)
    gpu = bem.contact_curve(z, 1 / 256, loads=loads, device="gpu", **options)
    for name in ("area", "separation", "conductance", "leakage"):
        np.testing.assert_allclose(getattr(gpu, name), getattr(cpu, name), rtol=1e-9)


def test_the_device_is_asked_for_everywhere_and_said_clearly(monkeypatch, tmp_path, capsys):
    from validation import check_scan
    from validation.cli import main
    from validation.common import models
    from validation.scenes.reader import parse_scene

    monkeypatch.setitem(sys.modules, "cupy", None)
    scene = {"name": "g", "surface": {"family": "self-affine", "hurst": 0.8, "rms_slope": 0.1,
                                      "n": 64}, "bem": {"device": "gpu"}}
    assert parse_scene(scene).bem.device == "gpu"
    with pytest.raises(ValueError, match="bem.device' must be one of cpu, gpu; got 'tpu'"):
        parse_scene({**scene, "bem": {"device": "tpu"}})
    (tmp_path / "g.toml").write_text('name = "g"\n[surface]\nfamily = "self-affine"\n'
                                     'hurst = 0.8\nrms_slope = 0.1\nn = 64\n'
                                     '[bem]\ndevice = "gpu"\n')
    assert main(["report", str(tmp_path / "g.toml"), "--out", str(tmp_path / "r")]) == 2
    assert "scene 'g': [bem] device='gpu' needs CuPy" in capsys.readouterr().err
    assert main(["report", "paper-wm-d205", "--device", "gpu", "--out",
                 str(tmp_path / "r")]) == 2
    assert "--device='gpu' needs CuPy" in capsys.readouterr().err
    heights = _surface(64)
    with pytest.raises(ValueError, match=r"^device='gpu' needs CuPy"):
        check_scan(heights * 1e-6, spacing=1e-6, device="gpu", cache=False)
    # the device is not part of a reference's cache key: a GPU result is the CPU's
    inputs = models.ModelInputs(spacing=1 / 64, nominal_area=1.0, heights=heights,
                                bem_options={"periodic": True, "tol": 1e-8, "device": "gpu"})
    for name in ("bem", "bem_interface", "bem_nominal"):
        settings = models.entry(name).settings(inputs)
        assert "device" not in settings["options"] and settings["options"]["tol"] == 1e-8


def test_the_interaction_sums_on_the_gpu_code_path(double):
    import asperity

    z = _surface(128, seed=7)
    summits = asperity.find_summits(z, 1 / 128)
    loads = np.geomspace(1e-4, 3e-3, 5)
    cpu = asperity.DiscreteAsperityModel(summits, method="fft").at_load(loads)
    model = asperity.DiscreteAsperityModel(summits, method="fft", device="gpu")
    gpu = model.at_load(loads)
    assert isinstance(model.operator._grid, double.DeviceArray)
    for name in ("area", "separation", "stiffness"):
        np.testing.assert_allclose(getattr(gpu, name), getattr(cpu, name), rtol=1e-9)


@pytest.mark.gpu
def test_cupy_interaction_sums_are_the_cpus():
    import asperity

    _cupy_or_skip()
    summits = asperity.find_summits(_surface(256, seed=7), 1 / 256)
    loads = np.geomspace(1e-4, 3e-3, 5)
    cpu = asperity.DiscreteAsperityModel(summits, method="fft").at_load(loads)
    gpu = asperity.DiscreteAsperityModel(summits, method="fft", device="gpu").at_load(loads)
    # Newton's iteration stops at its tolerance (1e-10) from iterates that cuFFT's rounding
    # moves: 2e-9 apart on an H200 at the heaviest load (FFTW against numpy's FFT: 1e-9 holds)
    for name in ("area", "separation", "stiffness"):
        np.testing.assert_allclose(getattr(gpu, name), getattr(cpu, name), rtol=1e-8)


def _same_check(gpu, cpu, n):
    # The finer reference's loads are one path on a GPU and sub-paths, one per core, on the CPU,
    # and cuFFT rounds otherwise than FFTW: their iterates differ, so the refined points agree
    # to the solver's tolerance, the contact area to a few pixels of the refined grid.
    assert [t.field for t in gpu.tables] == [t.field for t in cpu.tables]
    for g, c in zip(gpu.tables, cpu.tables):
        pixels = 4 / (2 * n) ** 2 if c.field == "area" else 0.0
        np.testing.assert_allclose(g.reference, c.reference, rtol=1e-4, atol=pixels + 1e-15)
        for name in c.verdicts:
            np.testing.assert_array_equal(g.verdicts[name], c.verdicts[name])


def _check_of(heights, device):
    from validation import check_scan

    return check_scan(heights * 1e-9, spacing="1nm", e_star="115GPa", device=device, cache=False)


def test_a_check_on_the_gpu_code_path_is_the_cpus(double):
    heights = _surface(128, seed=11) * 128
    _same_check(_check_of(heights, "gpu"), _check_of(heights, "cpu"), 128)


@pytest.mark.gpu
def test_a_cupy_check_is_the_cpus():
    _cupy_or_skip()
    heights = _surface(256, seed=11) * 256
    _same_check(_check_of(heights, "gpu"), _check_of(heights, "cpu"), 256)
