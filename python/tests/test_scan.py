"""Ragged takes (frames of their own point count): read from PCD, PLY and .bin folders, the
flattened arrays with their frame offsets, frame views, from_arrays with a list of frames,
written back and read again."""
import struct

import numpy as np
import pytest

import capz


def write_bin(path, points):
    with open(path, "wb") as f:
        for p in points:
            f.write(struct.pack("<ffff", *p))


@pytest.fixture
def bin_folder(tmp_path):
    d = tmp_path / "velodyne"
    d.mkdir()
    write_bin(d / "000000.bin", [(1, 2, 3, 0.5), (4, 5, 6, 0.25), (float("nan"), 0, 0, 1)])
    write_bin(d / "000001.bin", [])
    write_bin(d / "000002.bin", [(-1, -2, -3, 2.0)])
    return d


def test_bin_folder_reads_as_ragged_take(bin_folder):
    t = capz.read(str(bin_folder))
    assert t.ragged and t.points == 0 and t.frames == 3 and t.total_points == 4
    assert t.format == "bin-folder" and t.units == "m" and t.units_assumed
    np.testing.assert_array_equal(t.frame_offsets, [0, 3, 3, 4])
    assert t.xyz.shape == (4, 3) and t.valid.shape == (4,)
    np.testing.assert_array_equal(t.valid, [True, True, False, True])
    assert t.attributes["intensity"].dtype == np.float32
    np.testing.assert_array_equal(t.attributes["intensity"], [0.5, 0.25, 1, 2])
    f = t.frame(2)
    np.testing.assert_array_equal(f.xyz, [[-1, -2, -3]])
    assert t.frame(1).xyz.shape == (0, 3) and t.frame(-1).valid.all()
    assert [len(f.valid) for f in t.iter_frames()] == [3, 0, 1]
    f.xyz[0, 0] = 9  # a view: the take changes
    assert t.xyz[3, 0] == 9
    with pytest.raises(IndexError):
        t.frame(3)


def test_from_list_of_frames_and_write_read_back(tmp_path):
    frames = [np.array([[0.5, 1, 2], [np.nan, 0, 0]]), np.zeros((0, 3)), np.array([[3.0, 4, 5]])]
    ring = [np.array([1, 2], np.uint16), np.zeros(0, np.uint16), np.array([7], np.uint16)]
    t = capz.Take.from_arrays(frames, units="m", attributes={"ring": ring})
    assert t.ragged and t.frames == 3
    np.testing.assert_array_equal(t.frame_offsets, [0, 2, 2, 3])
    np.testing.assert_array_equal(t.valid, [True, False, True])
    np.testing.assert_array_equal(t.attributes["ring"], [1, 2, 7])
    capz.write(t, str(tmp_path / "pcd") + "/")
    capz.write(capz.read(str(tmp_path / "pcd")), str(tmp_path / "ply"), to="ply",
               ply_encoding="ascii")
    back = capz.read(str(tmp_path / "ply"))
    assert back.format == "ply-folder"
    np.testing.assert_array_equal(back.frame_offsets, t.frame_offsets)
    np.testing.assert_array_equal(back.valid, t.valid)
    np.testing.assert_array_equal(back.xyz[back.valid], t.xyz[t.valid])
    np.testing.assert_array_equal(back.attributes["ring"], [1, 2, 7])


def test_fixed_take_frames_are_views_too():
    xyz = np.arange(2 * 3 * 3, dtype=np.float64).reshape(2, 3, 3)
    t = capz.Take.from_arrays(xyz)
    assert not t.ragged and t.total_points == 6
    np.testing.assert_array_equal(t.frame_offsets, [0, 3, 6])
    np.testing.assert_array_equal(t.frame(1).xyz, xyz[1])


def test_ragged_take_compresses_and_is_refused_by_c3d(tmp_path, bin_folder):
    t = capz.read(str(bin_folder))
    back = capz.decompress(capz.compress(t, max_error="1mm"))
    np.testing.assert_array_equal(back.frame_offsets, t.frame_offsets)
    ok = np.asarray(t.valid)
    assert np.abs(np.asarray(back.xyz)[ok] - np.asarray(t.xyz)[ok]).max() <= 0.001
    with pytest.raises(capz.Error):
        capz.write(t, str(tmp_path / "x.c3d"), drop_fields=True)
    assert not (tmp_path / "x.c3d").exists()


def test_bad_frames_name_the_file(tmp_path):
    d = tmp_path / "bad"
    d.mkdir()
    (d / "a.bin").write_bytes(b"\0" * 20)
    with pytest.raises(capz.Error) as e:
        capz.read(str(d))
    assert "a.bin" in str(e.value) and e.value.code == "corrupt"
    with pytest.raises(capz.Error):
        capz.Take.from_arrays([np.zeros((2, 3))], valid=[np.ones(3, bool)])


def test_point_order_any_on_frames_of_one_count_gives_a_ragged_take(tmp_path):
    """point_order="any" on an unorganized folder of frames of one count (data/lidar_small,
    6 x 512): the frames are reordered as a scan's and decode as a ragged take of equal counts,
    each frame's points within the bound as a set; never larger than kept; the CLI makes the
    same bytes."""
    import os
    import subprocess
    src = os.path.join(os.path.dirname(__file__), "..", "..", "data", "lidar_small")
    t = capz.read(src)
    assert not t.ragged and t.points == 512
    z = capz.compress(t, max_error=0.01, point_order="any")
    (tmp_path / "any.capz").write_bytes(bytes(z))
    assert capz.open(str(tmp_path / "any.capz")).info["point_order"] == "reordered"
    d = capz.decompress(z)
    assert d.ragged and d.frames == t.frames
    np.testing.assert_array_equal(np.diff(d.frame_offsets), [512] * t.frames)
    for f in range(t.frames):
        a, b = t.frame(f), d.frame(f)
        assert b.valid.sum() == a.valid.sum()
        pa = a.xyz[a.valid.astype(bool)]
        pb = b.xyz[b.valid.astype(bool)]
        # every decoded point has a source point within the bound (a set check, one direction
        # each way on these few points)
        dist = np.abs(pa[:, None, :] - pb[None, :, :]).max(axis=2)
        assert dist.min(axis=0).max() <= 0.01 and dist.min(axis=1).max() <= 0.01
    assert len(z) <= len(capz.compress(t, max_error=0.01))
    cli = os.environ.get("CAPZ_CLI")
    if cli:
        out = tmp_path / "cli.capz"
        subprocess.run([cli, "compress", src, "-o", str(out), "-q", "--max-error", "0.01",
                        "--point-order", "any"], check=True)
        assert out.read_bytes() == bytes(z)


def test_point_order_any_keeps_each_frames_points_and_fields(tmp_path):
    """point_order="any": each frame's points come back as a set, each with its own fields,
    within the bound, never larger than kept; without the fields (whose timestamps and angles
    sorting would cost more than it saves the positions here) the points are reordered; the CLI
    makes the same bytes."""
    import os
    import subprocess
    src = os.path.join(os.path.dirname(__file__), "..", "..", "data", "scan_small")
    t = capz.read(src)
    z = capz.compress(t, max_error="1mm", point_order="any")
    d = capz.decompress(z)
    np.testing.assert_array_equal(d.frame_offsets, t.frame_offsets)
    moved = 0
    for f in range(t.frames):
        a, b = t.frame(f), d.frame(f)
        assert b.valid.sum() == a.valid.sum()
        ta = sorted(zip(*(a.attributes[k].tolist() for k in sorted(a.attributes))))
        tb = sorted(zip(*(b.attributes[k].tolist() for k in sorted(b.attributes))))
        assert ta == tb  # the same fields, point for point, as a set
    assert len(z) <= len(capz.compress(t, max_error="1mm"))
    g = capz.decompress(capz.compress(t, max_error="1mm", point_order="any", drop_fields=True))
    for f in range(t.frames):
        a, b = t.frame(f), g.frame(f)
        both = a.valid & b.valid
        moved += int((np.abs(a.xyz[both] - b.xyz[both]).max(axis=1) > 0.001).sum())
    assert moved > 0
    with pytest.raises(capz.Error):
        capz.compress(t, max_error="1mm", point_order="sorted")
    cli = os.environ.get("CAPZ_CLI")
    if cli:
        out = tmp_path / "cli.capz"
        subprocess.run([cli, "compress", src, "-o", str(out), "-q", "--max-error", "1mm",
                        "--point-order", "any"], check=True)
        report = capz.compress_file(src, str(tmp_path / "py.capz"), max_error="1mm",
                                    point_order="any")
        assert report is not None
        assert out.read_bytes() == (tmp_path / "py.capz").read_bytes()


def test_from_arrays_ragged_take_compresses_as_pcd_frames():
    """A ragged take made of a list of frames (a 0-point frame and a NaN gap among them)
    compresses at a bound and lossless (it was refused: "only PCD, PLY and .bin frames are
    coded as frames of their own point counts"); it decodes as the PCD folder write makes of it,
    every point within the bound (bit for bit lossless) and every field exact."""
    rng = np.random.default_rng(1)
    frames = [(rng.random((n, 3)) * 10).astype(np.float32).astype(np.float64)
              for n in (100, 130, 0, 90)]
    frames[0][5] = np.nan
    inten = [rng.random(len(f)).astype(np.float32) for f in frames]
    t = capz.Take.from_arrays(frames, attributes={"intensity": inten})
    assert t.ragged
    for opts, bound in (({"max_error": 0.001}, 0.001), ({"lossless": True}, 0.0)):
        d = capz.decompress(capz.compress(t, **opts))
        assert d.ragged
        np.testing.assert_array_equal(d.frame_offsets, t.frame_offsets)
        for f in range(t.frames):
            a, b = t.frame(f), d.frame(f)
            np.testing.assert_array_equal(a.valid, b.valid)
            v = a.valid.astype(bool)
            if v.any():
                assert np.abs(a.xyz[v] - b.xyz[v]).max() <= bound
            np.testing.assert_array_equal(a.attributes["intensity"], b.attributes["intensity"])


def test_float64_ragged_take_is_lossless_bit_for_bit(tmp_path):
    """Frames of their own counts in float64 map coordinates (on no decimal grid) compress
    losslessly, kept as their bits (docs/FORMAT.md "Raw windows"; refused before), and decode
    bit for bit, the archive describing its positions as float64 bits."""
    rng = np.random.default_rng(2)
    frames = [rng.random((n, 3)) * 50 + np.array([500000.1234567, 4000000.7654321, 100.5])
              for n in (120, 95, 140)]
    frames[1][7] = np.nan
    t = capz.Take.from_arrays(frames)
    z = capz.compress(t, lossless=True)
    d = capz.decompress(z)
    np.testing.assert_array_equal(d.frame_offsets, t.frame_offsets)
    np.testing.assert_array_equal(d.valid, t.valid)
    v = t.valid.astype(bool)
    assert (np.asarray(d.xyz)[v].view(np.uint64) == np.asarray(t.xyz)[v].view(np.uint64)).all()
    path = tmp_path / "utm.capz"
    path.write_bytes(z)
    with capz.open(path) as f:
        assert f.info["mode"] == "float64-bits"


def test_bin_fields_declares_another_record(tmp_path):
    """A .bin record other than KITTI's (the CLI's --bin-fields): read in it, each field of its
    type; compress_file keeps the CLI's bytes, and lossless gives the files back."""
    from conftest import cli

    rec = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("intensity", "<f4"),
                    ("ring", "<u2"), ("t", "<f8")])
    d = tmp_path / "sweeps"
    d.mkdir()
    for f, n in enumerate([56, 40]):
        a = np.zeros(n, rec)
        a["x"] = np.linspace(-10, 10, n)
        a["y"] = 3.5
        a["z"] = -1.25
        a["intensity"] = np.arange(n) % 100
        a["ring"] = np.arange(n) % 32
        a["t"] = 1.7e9 + f * 0.1 + np.arange(n) * 1e-5
        a.tofile(d / f"{f:06d}.bin")
    spec = "x y z intensity ring:U2 t:F8"
    t = capz.read(str(d), bin_fields=spec)
    assert t.ragged and t.total_points == 96
    assert t.attributes["ring"].dtype == np.uint16
    assert t.attributes["t"].dtype == np.float64
    np.testing.assert_array_equal(t.attributes["ring"][:56], np.arange(56) % 32)
    # Read as KITTI's record, the frames draw the warning that names the option.
    assert any("--bin-fields" in w for w in capz.read(str(d)).warnings)
    out = tmp_path / "py.capz"
    capz.compress_file(str(d), str(out), lossless=True, bin_fields=spec)
    cli("compress", str(d), "--lossless", "--bin-fields", spec, "-o", str(tmp_path / "cli.capz"))
    assert out.read_bytes() == (tmp_path / "cli.capz").read_bytes()
    cli("decompress", str(out), "-o", str(tmp_path / "back"))
    for f in ("000000.bin", "000001.bin"):
        assert (tmp_path / "back" / f).read_bytes() == (d / f).read_bytes()
    with pytest.raises(capz.Error) as e:
        capz.read(str(d), bin_fields="x y z i:Q4")
    assert "--bin-fields" in str(e.value)
