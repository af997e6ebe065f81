"""compress / decompress: within the bound, gaps kept, metadata back exactly."""
import os

import numpy as np
import pytest

import capz
from conftest import REPO, shared


def assert_within(orig, back, bound, units=None):
    np.testing.assert_array_equal(orig.valid, back.valid)  # the gaps are kept
    assert np.isnan(back.xyz[~back.valid]).all()
    err = np.abs(back.xyz[orig.valid] - orig.xyz[orig.valid])
    assert err.max() <= bound * (1 + 1e-9)
    assert back.labels == orig.labels and back.rate == orig.rate and back.units == (units or orig.units)
    assert back.first_frame == orig.first_frame


@pytest.mark.parametrize("bound,in_units", [("0.5mm", 0.5), ("0.05cm", 0.5), (0.25, 0.25)])
def test_c3d_round_trip_within_bound(bound, in_units):
    take = capz.read(shared("c3d/btkdata/PiG/PiG_Calibration2-NoOption.c3d"))
    assert take.units == "mm" and (~take.valid).any()
    back = capz.decompress(capz.compress(take, max_error=bound))
    assert_within(take, back, in_units)
    np.testing.assert_array_equal(back.analog, take.analog)  # analog is lossless
    assert back.analog_labels == take.analog_labels


def test_trc_lossless_is_exact():
    take = capz.read(shared("trc/opensim/dataWithBlanksForMissingMarkers.trc"))
    data, stats = capz.compress(take, lossless=True, stats=True)
    assert stats["lossless"] and stats["bytes"] == len(data)
    back = capz.decompress(data)
    np.testing.assert_array_equal(back.valid, take.valid)
    np.testing.assert_array_equal(back.xyz[take.valid], take.xyz[take.valid])


def test_pcd_default_bound_without_units():
    take = capz.read(shared("pcd/pcow"))
    data, stats = capz.compress(take, stats=True)
    v = take.xyz[take.valid]
    diag = np.sqrt(((v.max(axis=0) - v.min(axis=0)) ** 2).sum())
    assert stats["error"]["max_error_per_coordinate"] <= 1e-4 * diag * (1 + 1e-9)
    back = capz.decompress(data)
    np.testing.assert_array_equal(back.valid, take.valid)
    assert np.abs(back.xyz[take.valid] - take.xyz[take.valid]).max() <= 1e-4 * diag * (1 + 1e-9)
    # PCD has no units: metres are assumed (take.units_assumed), so a bound with a unit works,
    # and the archive stores no units, as the CLI's.
    assert take.units == "m" and take.units_assumed
    back = capz.decompress(capz.compress(take, max_error="1mm"))
    err = np.abs(back.xyz[take.valid] - take.xyz[take.valid])
    assert err.max() <= 0.001 * (1 + 1e-9) and back.units == ""
    back = capz.decompress(capz.compress(take, max_error="1mm", units="cm"))  # overrides
    assert_within(take, back, 0.1, units="cm")


def test_kg_target_met(small_take):
    back = capz.decompress(capz.compress(small_take, kg_error=0.5))
    assert capz.compare(small_take, back)["kg_error_percent"] <= 0.5
    np.testing.assert_array_equal(back.valid, small_take.valid)


def test_synthetic_round_trip_and_compare(small_take):
    data = capz.compress(small_take, max_error="0.1mm")
    back = capz.decompress(data)
    assert_within(small_take, back, 0.1)
    e = capz.compare(small_take, back)
    assert 0 < e["max_error_per_coordinate"] <= 0.1 * (1 + 1e-9)
    assert e["mask_mismatches"] == 0 and e["samples"] == int(small_take.valid.sum())


def test_gap_values_do_not_change_the_bytes(small_take):
    # A gap's coordinates are unspecified: NaN (as the package shows them) or 0 code the same.
    zeros = np.where(small_take.valid[..., None], small_take.xyz, 0.0)
    other = capz.Take.from_arrays(zeros, valid=small_take.valid, rate=100.0, units="mm",
                                  labels=small_take.labels)
    assert capz.compress(other) == capz.compress(small_take)


def test_codec_auto_and_options(small_take):
    data, st = capz.compress(small_take, max_error=0.1, codec="auto", stats=True)
    assert st["codec"] in ("none", "ts", "pdct")
    assert_within(small_take, capz.decompress(data), 0.1)
    a = capz.compress(small_take, max_error=0.1, window=16)
    b = capz.compress(small_take, max_error=0.1)
    assert a != b and capz.open  # windows of 16 frames make a different stream
    assert_within(small_take, capz.decompress(a), 0.1)


def test_write_and_read_back(small_take, tmp_path):
    for name in ("t.c3d", "t.trc", "frames/"):
        out = str(tmp_path / name)
        if name.endswith("/"):
            with pytest.warns(UserWarning, match="frame rate"):  # PCD frames store none
                capz.write(small_take, out)
        else:
            capz.write(small_take, out)
        back = capz.read(out)
        np.testing.assert_array_equal(back.valid, small_take.valid)
        # C3D stores float32 here, TRC and PCD decimals or float32: close, not exact
        np.testing.assert_allclose(back.xyz[back.valid], small_take.xyz[small_take.valid],
                                   rtol=0, atol=1e-3)
    with pytest.raises(capz.Error) as e:
        capz.write(small_take, str(tmp_path / "t.c3d"))
    assert e.value.code == "usage"  # exists, no overwrite
    capz.write(small_take, str(tmp_path / "t.c3d"), overwrite=True)


def test_pcd_fields_read_and_survive_the_codec(tmp_path):
    # data/lidar_small: intensity (F4), ring (U2), time (F4) per point, NaN where nothing is hit.
    take = capz.read(os.path.join(REPO, "data", "lidar_small"))
    assert list(take.attributes) == ["intensity", "ring", "time"]
    assert take.attributes["ring"].dtype == np.uint16
    assert take.attributes["intensity"].shape == (take.xyz.shape[0], take.xyz.shape[1])
    for kw in ({"lossless": True}, {"max_error": 0.01}):
        back = capz.decompress(capz.compress(take, **kw))
        assert list(back.attributes) == list(take.attributes)
        for name, a in take.attributes.items():
            # bit for bit, NaN intensities included
            np.testing.assert_array_equal(back.attributes[name].view(np.uint8), a.view(np.uint8))
    out = tmp_path / "back"
    capz.write(back, str(out) + "/")
    again = capz.read(str(out))
    np.testing.assert_array_equal(again.attributes["time"], take.attributes["time"])


def test_fields_are_not_dropped_without_being_asked(tmp_path):
    take = capz.read(os.path.join(REPO, "data", "lidar_small"))
    take = capz.Take.from_arrays(take.xyz, valid=take.valid, rate=10.0, units="m",
                                 attributes=dict(take.attributes))
    with pytest.raises(capz.Error) as e:
        capz.write(take, str(tmp_path / "a.c3d"))
    assert e.value.code == "usage" and "intensity, ring, time" in str(e.value)
    capz.write(take, str(tmp_path / "a.c3d"), drop_fields=True)
    assert capz.read(str(tmp_path / "a.c3d")).attributes == {}


def test_threads_and_field_bounds():
    take = capz.read(os.path.join(REPO, "data", "lidar_small"))
    one = capz.compress(take, lossless=True, window=2)
    assert capz.compress(take, lossless=True, window=2, threads=2) == one
    assert capz.compress(take, lossless=True, window=2, threads=0) == one
    bounded = capz.compress(take, lossless=True, attr_error={"intensity": 0.01})
    assert len(bounded) < len(one)
    back = capz.decompress(bounded)
    a, b = take.attributes["intensity"], back.attributes["intensity"]
    finite = np.isfinite(a)
    assert np.array_equal(np.isnan(a), np.isnan(b))
    assert np.abs(a[finite].astype(np.float64) - b[finite]).max() <= 0.01
    np.testing.assert_array_equal(back.attributes["time"], take.attributes["time"])
    assert capz.decompress(capz.compress(take, lossless=True, drop_fields=True)).attributes == {}
    with pytest.raises(capz.Error) as e:
        capz.compress(take, attr_error={"colour": 0.1})
    assert e.value.code == "invalid-parameter"
    with pytest.raises(capz.Error):
        capz.compress(take, threads=-1)


def test_analog_max_error_bounds_the_named_channels_only(tmp_path):
    take = capz.read(os.path.join(REPO, "data", "EB015PI.c3d"))
    lossless = capz.compress(take)
    data = capz.compress(take, analog_max_error={"N": 0.5, "Nmm": 50})
    assert len(data) < len(lossless)
    back = capz.decompress(data)
    diff = np.abs(back.analog - take.analog)
    moved = (diff > 0).any(axis=0)  # per channel
    # The force (nt) and moment (ntmm) channels move, the four d.u. channels do not.
    assert moved.sum() > 0 and (~moved).sum() >= 4
    np.testing.assert_array_equal(back.xyz[take.valid], capz.decompress(lossless).xyz[take.valid])
    path = str(tmp_path / "a.capz")
    with open(path, "wb") as f:
        f.write(data)
    bounds = capz.open(path).info["analog_bounds"]
    assert {b["unit"] for b in bounds} == {"nt", "ntmm"}
    assert {b["bound"] for b in bounds} == {0.5, 50.0}
    bounded = {b["channel"] for b in bounds}
    assert not any(moved[c] for c in range(take.analog.shape[1]) if c not in bounded)
    with pytest.raises(capz.Error) as e:
        capz.compress(take, lossless=True, analog_max_error={"N": 0.5})
    assert e.value.code == "invalid-parameter"
    with pytest.raises(capz.Error):
        capz.compress(take, analog_max_error={"N": "half"})
    # A key that names no channel is a UserWarning (the CLI's note), the data as without it.
    with pytest.warns(UserWarning, match="'kN' names no analog channel"):
        other = capz.compress(take, analog_max_error={"N": 0.5, "Nmm": 50, "kN": 1})
    assert other == data
