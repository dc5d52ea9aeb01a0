"""pyFFTW and scipy.fft give the same answers, and everything works without pyFFTW."""

import subprocess
import sys
import textwrap

import numpy as np
import pytest

from bem import HalfSpace, solve_contact
from bem.elastic.fft import PaddedRealFFT2, RealFFT2, have_pyfftw

needs_pyfftw = pytest.mark.skipif(not have_pyfftw(), reason="pyFFTW is not installed")


@pytest.mark.parametrize("backend", ["scipy", pytest.param("pyfftw", marks=needs_pyfftw)])
@pytest.mark.parametrize("shape", [(16, 16), (12, 18), (15, 9)])
def test_round_trip_and_numpy_convention(backend, shape):
    rng = np.random.default_rng(0)
    real = rng.normal(size=shape)
    fft = RealFFT2(shape, backend=backend)
    spectrum = fft.forward(real)
    np.testing.assert_allclose(spectrum, np.fft.rfft2(real), rtol=0, atol=1e-12 * np.abs(spectrum).max())
    np.testing.assert_allclose(fft.inverse(spectrum), real, rtol=0, atol=1e-13)
    # the in-place pair: unnormalised inverse between the owned buffers
    fft.real_buffer[...] = real
    fft.execute_forward()
    np.testing.assert_allclose(fft.spectrum_buffer, spectrum, rtol=0, atol=1e-13 * np.abs(spectrum).max())
    fft.execute_inverse()
    np.testing.assert_allclose(fft.output_buffer / fft.size, real, rtol=0, atol=1e-13)
    np.testing.assert_array_equal(fft.real_buffer, real)  # the forward input is never written


@pytest.mark.parametrize("backend", ["scipy", pytest.param("pyfftw", marks=needs_pyfftw)])
@pytest.mark.parametrize("shape", [(8, 8), (6, 11)])
def test_padded_pair_is_the_pruned_full_pair(backend, shape):
    rng = np.random.default_rng(5)
    block = rng.normal(size=shape)
    padded = np.zeros((2 * shape[0], 2 * shape[1]))
    padded[:shape[0], :shape[1]] = block
    fft = PaddedRealFFT2(shape, backend=backend)
    for _ in range(2):  # the padding survives a transform pair
        fft.input_block[...] = block
        fft.execute_forward()
        expected = np.fft.rfft2(padded)
        np.testing.assert_allclose(fft.spectrum_buffer, expected, rtol=0,
                                   atol=1e-13 * np.abs(expected).max())
        multiplier = rng.uniform(size=fft.spectrum_shape)
        fft.spectrum_buffer *= multiplier
        fft.execute_inverse()
        inverse = np.fft.irfft2(expected * multiplier, s=padded.shape)[:shape[0], :shape[1]]
        np.testing.assert_allclose(fft.output_block / fft.size, inverse, rtol=0,
                                   atol=1e-13 * np.abs(inverse).max())


@needs_pyfftw
@pytest.mark.parametrize("periodic", [False, True])
def test_operator_backends_agree(periodic):
    rng = np.random.default_rng(1)
    pressure = rng.uniform(size=(32, 32))
    a = HalfSpace((32, 32), 0.1, periodic=periodic, backend="pyfftw").displacement(pressure)
    b = HalfSpace((32, 32), 0.1, periodic=periodic, backend="scipy").displacement(pressure)
    assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(a))


@needs_pyfftw
@pytest.mark.parametrize("periodic", [False, True])
def test_solver_backends_agree(periodic):
    rng = np.random.default_rng(2)
    n = 32
    heights = np.cumsum(np.cumsum(rng.normal(size=(n, n)), axis=0), axis=1) * 1e-3
    heights -= heights.mean()
    solutions = [
        solve_contact(heights, 1.0 / n, load=2e-3, periodic=periodic, tol=1e-14, max_iter=2000,
                      operator=HalfSpace((n, n), 1.0 / n, periodic=periodic, backend=backend))
        for backend in ("pyfftw", "scipy")
    ]
    a, b = solutions
    assert a.converged and b.converged
    np.testing.assert_array_equal(a.contact, b.contact)
    # Both iterations run the same operations on operators equal to rounding: the converged
    # pressures agree to 1e-12 of the peak (tol = 1e-14 leaves no iteration-error difference).
    assert np.max(np.abs(a.pressure - b.pressure)) <= 1e-12 * np.max(a.pressure)
    assert a.separation == pytest.approx(b.separation, rel=1e-12, abs=1e-15)


def test_project_works_without_pyfftw():
    script = textwrap.dedent("""
        import sys
        sys.modules["pyfftw"] = None  # import pyfftw now raises ImportError
        import numpy as np
        import bem, asperity, validation
        from bem.elastic.fft import have_pyfftw, RealFFT2
        assert not have_pyfftw()
        try:
            RealFFT2((8, 8), backend="pyfftw")
        except ValueError:
            pass
        else:
            raise AssertionError("backend='pyfftw' accepted without pyFFTW")
        n = 16
        x = (np.arange(n) - n / 2 + 0.5) / n
        heights = -(x[None, :] ** 2 + x[:, None] ** 2)
        for periodic in (False, True):
            operator = bem.HalfSpace((n, n), 1.0 / n, periodic=periodic)
            assert operator.backend == "scipy"
            solution = bem.solve_contact(heights, 1.0 / n, load=1e-3, periodic=periodic,
                                         operator=operator, stiffness=True)
            assert solution.converged and solution.area > 0 and solution.stiffness > 0
        print("ok")
    """)
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip().endswith("ok")


def test_thread_count_override(monkeypatch):
    from bem.elastic.fft_threads import default_threads

    monkeypatch.setenv("ASPERITY_FFT_THREADS", "3")
    assert default_threads() == 3
    monkeypatch.setenv("ASPERITY_FFT_THREADS", "zero")
    with pytest.raises(ValueError, match="ASPERITY_FFT_THREADS"):
        default_threads()


@pytest.mark.parametrize("backend", ["auto", "scipy"])
def test_transforms_leave_their_input_untouched(backend):
    # Regression: FFTW's complex-to-real transform destroys its input array; the wrapper must
    # work on its own buffer so that a spectrum can be inverted twice.
    from bem.elastic.fft import RealFFT2

    rng = np.random.default_rng(5)
    real = rng.random((16, 16))
    fft = RealFFT2(real.shape, backend=backend)
    spectrum = fft.forward(real)
    kept = spectrum.copy()
    first = fft.inverse(spectrum)
    np.testing.assert_array_equal(spectrum, kept)
    np.testing.assert_array_equal(fft.inverse(spectrum), first)
    np.testing.assert_allclose(first, real, atol=1e-15)


def test_default_fft_threads_are_the_caller_and_the_idle_cpus(monkeypatch):
    import bem.elastic.fft_threads as fft

    monkeypatch.setenv("ASPERITY_FFT_THREADS", "4")
    assert fft.fft_threads((512, 512)) == 1                 # small grids: one thread
    for idle, expected in [(0.0, 1), (0.4, 1), (0.6, 2), (1.0, 2), (2.7, 4), (9.0, 4)]:
        monkeypatch.setattr(fft, "idle_cpus", lambda idle=idle: idle)
        assert fft.fft_threads((1024, 1024)) == expected
    # without /proc/stat: the CPUs the 1-minute load average leaves
    monkeypatch.setattr(fft, "idle_cpus", lambda: None)
    monkeypatch.setattr(fft.os, "getloadavg", lambda: (1.0, 0.0, 0.0))
    assert fft.fft_threads((1024, 1024)) == 3
    monkeypatch.setattr(fft.os, "getloadavg", lambda: (7.0, 0.0, 0.0))
    assert fft.fft_threads((1024, 1024)) == 1


def test_idle_cpus_are_read_from_the_cpu_times(monkeypatch):
    import bem.elastic.fft_threads as fft

    samples = iter([(100, 1000), (250, 1200)])     # 150 of 200 ticks idle
    monkeypatch.setattr(fft, "_cpu_times", lambda: next(samples))
    monkeypatch.setattr(fft.os, "cpu_count", lambda: 2)
    assert fft.idle_cpus(0.0) == pytest.approx(1.5)
    monkeypatch.setattr(fft, "_cpu_times", lambda: (_ for _ in ()).throw(OSError("none")))
    assert fft.idle_cpus(0.0) is None


def test_default_fft_threads_leave_a_core_to_each_running_background_call(monkeypatch):
    import threading

    import bem.elastic.fft_threads as fft
    from bem.common.background import BackgroundCall, running

    monkeypatch.setenv("ASPERITY_FFT_THREADS", "2")
    monkeypatch.setattr(fft, "idle_cpus", lambda: 1.0)
    assert running() == 0 and fft.fft_threads((1024, 1024)) == 2
    release = threading.Event()
    beside = BackgroundCall(release.wait, 10.0, name="models")
    try:
        assert running() == 1 and fft.fft_threads((1024, 1024)) == 1
    finally:
        release.set()
        assert beside.result() is True
    assert running() == 0


@pytest.mark.parametrize("interval", [-1.0, float("nan"), "0.1"])
def test_idle_cpus_refuses_a_bad_interval(interval):
    from bem.elastic.fft_threads import idle_cpus

    with pytest.raises((ValueError, TypeError), match="interval"):
        idle_cpus(interval)


@pytest.mark.parametrize("backend", ["scipy", pytest.param("pyfftw", marks=needs_pyfftw)])
def test_cosine_pair_is_the_dft_of_the_mirror_extension(backend):
    # The type-II cosine transform of a quadrant is, up to the half-pixel phase, the real DFT
    # of its even extension (the field and its mirror images about the lines half a pixel
    # beyond its edges); the inverse returns 4 N M times the input.
    from bem.elastic.fft import CosineTransform2

    rng = np.random.default_rng(7)
    block = rng.normal(size=(6, 10))
    rows, columns = block.shape
    extended = np.block([[block, block[:, ::-1]], [block[::-1], block[::-1, ::-1]]])
    phase = np.exp(-1j * np.pi * np.arange(rows) / (2 * rows))[:, None] \
        * np.exp(-1j * np.pi * np.arange(columns) / (2 * columns))[None, :]
    expected = (np.fft.fft2(extended)[:rows, :columns] * phase).real
    fft = CosineTransform2(block.shape, backend=backend)
    fft.real_buffer[...] = block
    fft.execute_forward()
    np.testing.assert_allclose(fft.spectrum_buffer, expected, rtol=0,
                               atol=1e-12 * np.abs(expected).max())
    fft.execute_inverse()
    np.testing.assert_allclose(fft.output_buffer / fft.size, block, rtol=0, atol=1e-13)


@needs_pyfftw
def test_cosine_transforms_use_fftw_on_large_grids_only():
    from bem.elastic.fft import COSINE_FFTW_LIMIT, CosineTransform2

    side = int(np.sqrt(COSINE_FFTW_LIMIT))
    assert CosineTransform2((side, side), planner_effort="FFTW_ESTIMATE").backend == "scipy"
    assert CosineTransform2((side, side + 1),
                            planner_effort="FFTW_ESTIMATE").backend == "pyfftw"
    assert CosineTransform2((8, 8), backend="pyfftw").backend == "pyfftw"
    assert CosineTransform2((side, side + 1), backend="scipy").backend == "scipy"
