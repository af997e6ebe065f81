"""Bad arrays and damaged bytes raise capz.Error with a clear message; nothing crashes."""
import numpy as np
import pytest

import capz
from conftest import shared, synthetic_xyz


def raises(fn, code, text):
    with pytest.raises(capz.Error) as e:
        fn()
    assert e.value.code == code, e.value
    assert text in e.value.message, e.value.message
    return e.value


@pytest.mark.parametrize("xyz,text", [
    (synthetic_xyz(4, 2).astype(np.float32), "xyz must be float64, got float32"),
    (np.zeros((4, 2, 3), np.int64), "xyz must be float64, got int64"),
    (np.zeros((4, 2), np.float64), "xyz must have shape (frames, points, 3)"),
    (np.zeros((4, 2, 2), np.float64), "xyz must have shape (frames, points, 3)"),
    ("not an array", "xyz must be float64"),
])
def test_bad_xyz(xyz, text):
    raises(lambda: capz.Take.from_arrays(xyz), "invalid-parameter", text)


def test_bad_values_and_companions():
    xyz = synthetic_xyz(6, 3)
    inf = xyz.copy()
    inf[2, 1, 0] = np.inf
    raises(lambda: capz.Take.from_arrays(inf), "invalid-parameter", "xyz[2, 1] is infinite")
    nan = xyz.copy()
    nan[4, 2, 1] = np.nan
    valid = np.ones((6, 3), bool)
    raises(lambda: capz.Take.from_arrays(nan, valid=valid), "invalid-parameter",
           "xyz[4, 2] is marked valid but is not a finite number")
    raises(lambda: capz.Take.from_arrays(xyz, valid=np.ones((6, 3), np.uint8)),
           "invalid-parameter", "valid must be bool, got uint8")
    raises(lambda: capz.Take.from_arrays(xyz, valid=np.ones((3, 6), bool)),
           "invalid-parameter", "valid must have shape (6, 3)")
    raises(lambda: capz.Take.from_arrays(xyz, labels=["a"]), "invalid-parameter",
           "labels: 3 expected, got 1")
    raises(lambda: capz.Take.from_arrays(xyz, units="parsec"), "invalid-parameter",
           "unknown unit 'parsec'")
    raises(lambda: capz.Take.from_arrays(xyz, rate=float("nan")), "invalid-parameter",
           "rate must be a finite number")
    raises(lambda: capz.Take.from_arrays(xyz, analog=np.zeros((7, 2))), "invalid-parameter",
           "positive multiple of the 6 frames")
    raises(lambda: capz.Take.from_arrays(xyz, analog=np.zeros((12, 2), np.float32)),
           "invalid-parameter", "analog must be float64")
    raises(lambda: capz.Take.from_arrays(xyz, attributes={"c": np.zeros((6, 3), np.float16)}),
           "invalid-parameter", "dtype float16 is not a PCD field type")
    raises(lambda: capz.Take.from_arrays(xyz, attributes={"c": np.zeros((6, 4), np.uint8)}),
           "invalid-parameter", "attribute 'c' must have shape (6, 3)")
    raises(lambda: capz.Take.from_arrays(xyz, attributes={"c": np.zeros((6, 3), bool)}),
           "invalid-parameter", "dtype bool is not a PCD field type")
    raises(lambda: capz.Take.from_arrays(xyz, rotations={"matrices": np.zeros((6, 1, 4, 4))}),
           "invalid-parameter", "rotation matrices must be float32, got float64")
    raises(lambda: capz.Take.from_arrays(
        xyz, rotations={"matrices": np.zeros((6, 1, 3, 3), np.float32)}),
        "invalid-parameter", "shape (samples, segments, 4, 4)")
    raises(lambda: capz.Take.from_arrays(
        xyz, rotations={"matrices": np.zeros((7, 1, 4, 4), np.float32)}),
        "invalid-parameter", "positive multiple of the 6 frames")


def test_nan_written_into_a_view_is_caught_before_coding():
    t = capz.Take.from_arrays(synthetic_xyz(6, 3))
    t.xyz[1, 1, 1] = np.nan
    raises(lambda: capz.compress(t), "invalid-parameter", "xyz[1, 1] is marked valid")


def test_bad_targets(small_take):
    raises(lambda: capz.compress(small_take, max_error="-1mm"), "invalid-parameter",
           "a length must be a finite number >= 0")
    raises(lambda: capz.compress(small_take, max_error="0"), "invalid-parameter",
           "must be > 0")
    raises(lambda: capz.compress(small_take, max_error=[1]), "invalid-parameter",
           "max_error must be a length")
    raises(lambda: capz.compress(small_take, kg_error=-2), "invalid-parameter", "> 0")
    raises(lambda: capz.compress(small_take, lossless=True, kg_error=1), "usage", "only one")
    raises(lambda: capz.compress(small_take, codec="nope"), "invalid-parameter", "nope")
    raises(lambda: capz.compress("take"), "invalid-parameter", "expected a capz.Take")


def test_damaged_bytes(small_take):
    data = capz.compress(small_take, max_error="0.1mm")
    capz.decompress(data)
    raises(lambda: capz.decompress(data[: len(data) // 2]), "corrupt", "")
    raises(lambda: capz.decompress(b"not a capz stream at all"), "not-our-format", "")
    raises(lambda: capz.decompress(b""), "not-our-format", "")
    codes = []
    rng = np.random.default_rng(7)
    for pos in rng.choice(np.arange(16, len(data)), size=40, replace=False):
        bad = bytearray(data)
        bad[pos] ^= 0x5A
        with pytest.raises(capz.Error) as e:  # every chunk carries a CRC
            capz.decompress(bytes(bad), "damaged.capz")
        assert "damaged.capz" in e.value.message
        codes.append(e.value.code)
    assert set(codes) <= {"corrupt", "unsupported-version", "not-our-format"}
    raises(lambda: capz.decompress("text"), "invalid-parameter", "decompress wants bytes")


def test_memory_limit(small_take, tmp_path):
    """A stream needing more decoded memory than memory_limit raises "memory-limit" (exit status
    8) before decoding; 0 is no limit; the default is DEFAULT_MEMORY_LIMIT."""
    data = capz.compress(small_take, max_error="0.1mm")
    e = raises(lambda: capz.decompress(data, "small.capz", memory_limit=64), "memory-limit",
               "small.capz")
    assert e.exit_status == 8 and "memory limit" in e.message
    path = tmp_path / "small.capz"
    path.write_bytes(data)
    raises(lambda: capz.read(path, memory_limit=64), "memory-limit", "small.capz")
    with capz.open(path, memory_limit=64) as z:
        raises(lambda: z.read_frames(0, 2), "memory-limit", "small.capz")
    for limit in (None, 0, capz.DEFAULT_MEMORY_LIMIT, 1 << 20):
        assert capz.decompress(data, memory_limit=limit).frames == small_take.frames
        assert capz.read(path, memory_limit=limit).frames == small_take.frames
    assert capz.DEFAULT_MEMORY_LIMIT == 4 << 30
    for bad in (-1, 1.5, "1G", True, 1 << 64):
        raises(lambda: capz.decompress(data, memory_limit=bad), "invalid-parameter",
               "memory_limit")


def test_files():
    raises(lambda: capz.read("/nonexistent/walk.c3d"), "io", "/nonexistent/walk.c3d")
    with pytest.raises(capz.Error) as e:
        capz.read(shared("c3d/btkdata/others/Empty.c3d"))
    assert e.value.exit_status == {"io": 2, "not-our-format": 3, "corrupt": 5}[e.value.code]
    assert "Empty.c3d" in str(e.value)


def test_write_capz_path_is_refused(small_take, tmp_path):
    raises(lambda: capz.write(small_take, str(tmp_path / "x.capz")), "usage", "compress")


def test_error_pickles():
    import pickle

    e = raises(lambda: capz.decompress(b"nope"), "not-our-format", "")
    back = pickle.loads(pickle.dumps(e))
    assert (back.code, back.message, back.exit_status) == (e.code, e.message, e.exit_status)
    assert back.exit_status == 3 and str(back) == str(e)


def test_every_must_reject_stream_raises():
    import glob
    import os

    from conftest import REPO

    streams = sorted(glob.glob(os.path.join(REPO, "tests", "corrupt", "streams", "*.capz")))
    assert len(streams) > 10
    for path in streams:
        with open(path, "rb") as f:
            data = f.read()
        with pytest.raises(capz.Error) as e:
            capz.decompress(data, os.path.basename(path))
        assert e.value.code in ("corrupt", "not-our-format", "unsupported-version"), path
        with pytest.raises(capz.Error):  # the same through a file, all frames read
            with capz.open(path) as z:
                z.read_frames()
