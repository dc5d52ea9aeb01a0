"""The on-disk result cache."""

import numpy as np

from validation.cache import Cache, cache_key


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
