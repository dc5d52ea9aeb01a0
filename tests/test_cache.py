"""The on-disk result cache."""

import gc
import sys
import threading

import numpy as np

from validation.run.cache import Cache, cache_key


def test_key_hashes_exactly_the_inputs():
    a = cache_key("bem", "1.0", surface={"D": 2.05, "n": 64}, loads=np.array([1.0, 2.0]))
    assert a == cache_key("bem", "1.0", loads=np.array([1.0, 2.0]), surface={"n": 64, "D": 2.05})
    assert a != cache_key("bem", "1.0", surface={"D": 2.05000001, "n": 64}, loads=np.array([1.0, 2.0]))
    assert a != cache_key("bem", "1.1", surface={"D": 2.05, "n": 64}, loads=np.array([1.0, 2.0]))
    assert a != cache_key("discrete", "1.0", surface={"D": 2.05, "n": 64}, loads=np.array([1.0, 2.0]))
    assert a != cache_key("bem", "1.0", surface={"D": 2.05, "n": 64}, loads=np.array([1.0, 2.5]))


def test_round_trip_and_disabled(tmp_path):
    cache = Cache(tmp_path / "c")
    key = cache_key("x", "1", a=1)
    assert cache.load(key) is None
    cache.store(key, {"load": np.arange(4.0), "count": np.array(3)})
    got = cache.load(key)
    np.testing.assert_array_equal(got["load"], np.arange(4.0))
    assert int(got["count"]) == 3
    assert not any(p.name.endswith(".tmp") for p in (tmp_path / "c").iterdir())
    off = Cache(None)
    off.store(key, {"a": np.zeros(1)})
    assert off.load(key) is None


def test_truncated_or_tampered_entry_is_dropped(tmp_path):
    cache = Cache(tmp_path)
    key = cache_key("x", "1", a=2)
    cache.store(key, {"load": np.arange(100.0)})
    path = cache.path(key)
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    assert cache.load(key) is None and not path.exists()
    # A readable file whose contents do not match its checksum is refused too.
    cache.store(key, {"load": np.arange(100.0)})
    other = Cache(tmp_path / "other")
    other.store(key, {"load": np.arange(100.0) + 1})
    with np.load(other.path(key)) as good:
        arrays = dict(good)
    arrays["__checksum__"] = np.array("0" * 64)
    np.savez(path, **arrays)
    assert cache.load(key) is None


def _decode_load(arrays):
    return arrays["load"]


def test_entry_copied_under_another_name_is_not_used(tmp_path):
    cache = Cache(tmp_path)
    first, second = cache_key("x", "1", a=1), cache_key("x", "1", a=2)
    cache.store(first, {"load": np.arange(3.0)})
    cache.path(second).write_bytes(cache.path(first).read_bytes())
    assert cache.load(second) is None and not cache.path(second).exists()
    np.testing.assert_array_equal(cache.load(first)["load"], np.arange(3.0))


def test_entry_missing_an_array_is_removed_and_recomputed(tmp_path):
    cache = Cache(tmp_path)
    key = cache_key("x", "1", a=3)
    cache.store(key, {"area": np.ones(2)})       # valid checksum, but no "load"
    assert cache.load(key, decode=_decode_load) is None
    assert not cache.path(key).exists()
    cache.store(key, {"load": np.ones(2)})
    np.testing.assert_array_equal(cache.load(key, decode=_decode_load), np.ones(2))


def test_directory_at_an_entry_path_is_replaced(tmp_path):
    cache = Cache(tmp_path)
    key = cache_key("x", "1", a=4)
    (cache.path(key) / "inner").mkdir(parents=True)
    assert cache.load(key) is None
    cache.store(key, {"load": np.ones(1)})
    assert cache.path(key).is_file() and cache.load(key)["load"][0] == 1.0


def test_stale_temporary_files_are_cleaned_and_fresh_ones_kept(tmp_path):
    import os
    import time

    stale, fresh = tmp_path / ".x-1.abc.tmp", tmp_path / ".x-2.def.tmp"
    stale.write_bytes(b"half")
    fresh.write_bytes(b"half")
    old = time.time() - 2 * 3600
    os.utime(stale, (old, old))
    Cache(tmp_path)
    assert not stale.exists() and fresh.exists()


def test_unwritable_cache_warns_and_does_not_stop_the_computation(tmp_path):
    import pytest

    from validation.run.cache import CacheWarning

    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    cache = Cache(blocker)
    with pytest.warns(CacheWarning, match="not written"):
        cache.store(cache_key("x", "1", a=5), {"load": np.ones(1)})


def test_check_directory_names_what_is_wrong(tmp_path):
    import pytest

    from validation.run.cache import check_directory

    assert check_directory(tmp_path / "new" / "folder", "--out").is_dir()
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(ValueError, match="--cache .* is not a writable directory"):
        check_directory(blocker, "--cache")
    with pytest.raises(ValueError, match="--out '/proc/nope' is not a writable directory"):
        check_directory("/proc/nope", "--out")


class _Cyclic:
    """Garbage in a reference cycle whose finaliser runs Python code: a collection inside the
    AST constructor then lets another thread run (how the CPython 3.11 race shows itself)."""

    def __init__(self):
        self.itself = self

    def __del__(self):
        sum(range(20))


def test_entries_are_read_by_several_threads_at_once(tmp_path):
    cache = Cache(tmp_path)
    stored = {"a": np.zeros(3), "b": np.ones(4), "c": np.arange(5.0)}
    cache.store("k", stored)
    errors, loaded = [], []

    def read():
        try:
            for _ in range(300):
                loaded.append(cache.load("k"))
                [_Cyclic() for _ in range(5)]
        except Exception as error:  # noqa: BLE001 -- the test reports what a thread raised
            errors.append(error)

    interval, thresholds = sys.getswitchinterval(), gc.get_threshold()
    sys.setswitchinterval(1e-6)
    gc.set_threshold(5)
    try:
        threads = [threading.Thread(target=read) for _ in range(4)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
    finally:
        sys.setswitchinterval(interval)
        gc.set_threshold(*thresholds)
    assert errors == []
    assert len(loaded) == 1200
    assert all(entry is not None and np.array_equal(entry["c"], stored["c"]) for entry in loaded)
