"""Take.from_arrays: with and without gaps, attributes, analog; what the arrays look like."""
import numpy as np
import pytest

import capz
from conftest import synthetic_xyz


def test_without_gaps():
    xyz = synthetic_xyz(frames=50, points=4)
    t = capz.Take.from_arrays(xyz, rate=120.0, units="m", labels=["a", "b", "c", "d"],
                              first_frame=7)
    assert (t.frames, t.points, t.rate, t.units, t.first_frame) == (50, 4, 120.0, "m", 7)
    assert t.labels == ["a", "b", "c", "d"] and t.valid.all() and t.gap_samples == 0
    np.testing.assert_array_equal(t.xyz, xyz)
    back = capz.decompress(capz.compress(t, max_error="0.1mm"))
    assert np.abs(back.xyz - xyz).max() <= 1e-4 * (1 + 1e-9)
    assert back.first_frame == 7 and back.labels == t.labels


def test_gaps_from_nan():
    xyz = synthetic_xyz(frames=40, points=3)
    xyz[5:9, 1] = np.nan
    xyz[20, 2, 0] = np.nan  # one NaN coordinate makes the sample a gap
    t = capz.Take.from_arrays(xyz)
    expect = np.ones((40, 3), bool)
    expect[5:9, 1] = False
    expect[20, 2] = False
    np.testing.assert_array_equal(t.valid, expect)
    assert np.isnan(t.xyz[~expect]).all() and t.gap_samples == 5
    back = capz.decompress(capz.compress(t, lossless=True))
    np.testing.assert_array_equal(back.valid, expect)
    np.testing.assert_array_equal(back.xyz[expect], xyz[expect])


def test_gaps_from_valid_ignore_their_values():
    xyz = synthetic_xyz(frames=30, points=2)
    valid = np.ones((30, 2), bool)
    valid[3, 0] = False
    xyz[3, 0] = [np.inf, 1e300, np.nan]  # anything at a gap
    t = capz.Take.from_arrays(xyz, valid=valid)
    np.testing.assert_array_equal(t.valid, valid)
    assert np.isnan(t.xyz[3, 0]).all()


def test_non_contiguous_input_is_accepted():
    xyz = np.asfortranarray(synthetic_xyz(frames=20, points=5))
    t = capz.Take.from_arrays(xyz[:, ::2])
    np.testing.assert_array_equal(t.xyz, xyz[:, ::2])


@pytest.mark.parametrize("dtype", ["<f4", "<f8", "u1", "<u2", "<u4", "<u8", "i1", "<i2",
                                   "<i4", "<i8", ">f4", ">i2"])
def test_attributes(dtype):
    rng = np.random.default_rng(3)
    xyz = synthetic_xyz(frames=6, points=5)
    scalar = (rng.uniform(0, 100, size=(6, 5))).astype(dtype)
    vector = (rng.uniform(0, 100, size=(6, 5, 3))).astype(dtype)
    t = capz.Take.from_arrays(xyz, units="", attributes={"intensity": scalar, "normal": vector})
    a = t.attributes
    assert list(a) == ["intensity", "normal"]
    assert a["intensity"].shape == (6, 5) and a["normal"].shape == (6, 5, 3)
    want = np.dtype(dtype).newbyteorder("<")
    assert a["intensity"].dtype == want and a["normal"].dtype == want
    np.testing.assert_array_equal(a["intensity"], scalar)
    np.testing.assert_array_equal(a["normal"], vector)
    assert "2 attributes" in repr(t)


def test_analog():
    xyz = synthetic_xyz(frames=10, points=2)
    analog = np.arange(10 * 4 * 3, dtype=np.float64).reshape(40, 3)
    t = capz.Take.from_arrays(xyz, analog=analog, analog_rate=400.0,
                              analog_labels=["fx", "fy", "fz"])
    assert t.analog_samples_per_frame == 4 and t.analog_rate == 400.0
    np.testing.assert_array_equal(t.analog, analog)
    back = capz.decompress(capz.compress(t))
    np.testing.assert_array_equal(back.analog, analog)
    assert back.analog_labels == ["fx", "fy", "fz"]


def test_views_write_through_and_copy_is_deep():
    t = capz.Take.from_arrays(synthetic_xyz(frames=5, points=2))
    c = t.copy()
    t.xyz[0, 0, 0] = 12.5
    assert t.xyz[0, 0, 0] == 12.5 and c.xyz[0, 0, 0] != 12.5


def test_metadata_setters():
    t = capz.Take.from_arrays(synthetic_xyz(frames=5, points=2))
    t.rate, t.units, t.labels = 50.0, "cm", ["x", "y"]
    assert (t.rate, t.units, t.labels) == (50.0, "cm", ["x", "y"])
    for attr, value in (("rate", -1.0), ("units", "parsec"), ("labels", ["only one"])):
        with pytest.raises(capz.Error):
            setattr(t, attr, value)


def turning_transforms(samples, segments):
    """Homogeneous transforms [sample, segment, row, column]: a turn about z and a shift."""
    m = np.zeros((samples, segments, 4, 4), np.float32)
    a = 0.05 * np.arange(samples)[:, None] + np.arange(segments)[None, :]
    m[..., 0, 0], m[..., 0, 1] = np.cos(a), -np.sin(a)
    m[..., 1, 0], m[..., 1, 1] = np.sin(a), np.cos(a)
    m[..., 2, 2] = 1
    m[..., 0, 3] = 100 + np.arange(samples)[:, None]
    m[..., 1, 3], m[..., 2, 3] = 200, 300 + np.arange(segments)[None, :]
    m[..., 3, 3] = 1
    return m


def test_rotations_round_trip(tmp_path):
    frames, segments, ratio = 12, 3, 2
    m = turning_transforms(frames * ratio, segments)
    rel = np.full((frames * ratio, segments), 0.5, np.float32)
    rel[3, 1] = np.nan
    rot = {"matrices": m, "reliability": rel, "labels": ["pelvis", "thigh", "shank"],
           "rate": 200.0}
    t = capz.Take.from_arrays(synthetic_xyz(frames, 4), rotations=rot)
    r = t.rotations
    assert r["matrices"].shape == (24, 3, 4, 4) and r["matrices"].dtype == np.float32
    np.testing.assert_array_equal(r["matrices"], m)  # [sample, segment, row, column]
    np.testing.assert_array_equal(r["matrices"][..., 3, :], np.broadcast_to([0, 0, 0, 1],
                                                                           (24, 3, 4)))
    np.testing.assert_array_equal(r["reliability"], rel)
    assert (r["labels"], r["rate"], r["samples_per_frame"]) == (rot["labels"], 200.0, 2)
    back = capz.decompress(capz.compress(t, max_error="0.5mm")).rotations
    np.testing.assert_array_equal(back["matrices"], m)  # rotations are kept bit for bit
    np.testing.assert_array_equal(back["reliability"], rel)
    assert back["labels"] == rot["labels"]
    out = str(tmp_path / "rot.c3d")
    capz.write(t, out)
    again = capz.read(out).rotations
    np.testing.assert_array_equal(again["matrices"], m)
    assert again["labels"] == rot["labels"] and again["samples_per_frame"] == 2


def test_field_names_a_frame_file_cannot_hold_are_refused():
    """A field named x, y or z, or with a blank in its name, is refused by name (a field named x
    was written as a PCD folder with two x fields and crashed the interpreter; "a b" gave files
    that did not read back)."""
    xyz = np.zeros((1, 10, 3))
    for name in ["x", "z", "a b", "tab\there"]:
        with pytest.raises(capz.Error) as e:
            capz.Take.from_arrays(xyz, attributes={name: np.zeros((1, 10), np.float32)})
        assert name in str(e.value)
    with pytest.raises(capz.Error):
        capz.Take.from_arrays([np.zeros((10, 3))], attributes={"y": [np.zeros(10, np.float32)]})
    t = capz.Take.from_arrays(xyz, attributes={"intensity": np.zeros((1, 10), np.float32)})
    assert "intensity" in t.attributes
