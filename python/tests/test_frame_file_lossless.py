"""Lossless PLY, KITTI .bin and nuScenes .pcd.bin frames (docs/FORMAT.md "Lossless frame-file streams"): capz.read
of a PLY, a .bin and a .pcd.bin folder, capz.compress / capz.decompress of the take (positions bit for bit,
fields exact), and compress_file with lossless=True writing the same bytes as `capz compress
--lossless`, whose archive `capz decompress` turns back into the frame files byte for byte."""
import filecmp
import os
import struct

import numpy as np
import pytest

import capz
from conftest import cli


def sweep(f):
    """Frame f: 5 + 2 f points on a spiral, float32 x y z intensity; point 1 a NaN gap."""
    pts = []
    for i in range(5 + 2 * f):
        a = 0.4 * i + 0.01 * f
        pts.append([12.5 * np.cos(a), 12.5 * np.sin(a), -0.5 + 0.01 * i, float(i % 7)])
    p = np.array(pts, np.float32)
    p[1, :3] = np.nan
    return p


def write_folder(d, kind):
    d.mkdir()
    for f in range(3):
        p = sweep(f)
        if kind == "bin":
            p.astype("<f4").tofile(str(d / f"{f:06d}.bin"))
            continue
        if kind == "nus":  # nuScenes: x y z intensity ring, NAME.pcd.bin
            ring = (np.arange(len(p)) % 32).astype(np.float32)[:, None]
            np.hstack([p, ring]).astype("<f4").tofile(str(d / f"{f:06d}.pcd.bin"))
            continue
        head = ("ply\nformat ascii 1.0\ncomment written by numpy\nelement vertex %d\n"
                "property float x\nproperty float y\nproperty float z\nproperty float intensity\n"
                "element face 0\nproperty list uchar int vertex_indices\nend_header\n" % len(p))
        body = "".join(" ".join("%.6f" % v for v in row) + "\n" for row in p)
        (d / f"{f:06d}.ply").write_text(head + body)
    return d


@pytest.mark.parametrize("kind", ["ply", "bin", "nus"])
def test_read_compress_decompress_exact(tmp_path, kind):
    d = write_folder(tmp_path / kind, kind)
    t = capz.read(str(d))
    assert t.ragged and t.frames == 3
    np.testing.assert_array_equal(t.frame_offsets, [0, 5, 12, 21])
    z, st = capz.compress(t, lossless=True, stats=True)
    assert st["lossless"]
    back = capz.decompress(z)
    np.testing.assert_array_equal(back.frame_offsets, t.frame_offsets)
    np.testing.assert_array_equal(back.valid, t.valid)
    ok = np.asarray(t.valid)
    assert np.asarray(back.xyz)[ok].tobytes() == np.asarray(t.xyz)[ok].tobytes()
    np.testing.assert_array_equal(back.attributes["intensity"], t.attributes["intensity"])
    if kind == "nus":  # nuScenes' ring comes as a float32 field
        ring = np.concatenate([np.arange(5 + 2 * f) % 32 for f in range(3)]).astype(np.float32)
        np.testing.assert_array_equal(np.asarray(t.attributes["ring"]).ravel(), ring)
        np.testing.assert_array_equal(back.attributes["ring"], t.attributes["ring"])


@pytest.mark.parametrize("kind", ["ply", "bin", "nus"])
def test_compress_file_lossless_same_bytes_as_cli_and_files_back(tmp_path, kind):
    d = write_folder(tmp_path / kind, kind)
    ours, theirs = str(tmp_path / "py.capz"), str(tmp_path / "cli.capz")
    report = capz.compress_file(str(d), ours, lossless=True)
    cli("compress", str(d), "-o", theirs, "--lossless", "-q")
    with open(ours, "rb") as a, open(theirs, "rb") as b:
        assert a.read() == b.read()
    assert report["lossless"]
    back = tmp_path / "back"
    cli("decompress", ours, "-o", str(back) + "/", "-q")
    names = sorted(os.listdir(d))
    assert sorted(os.listdir(back)) == names
    for n in names:
        assert filecmp.cmp(str(d / n), str(back / n), shallow=False), n
    # The take the archive decodes to is the folder's, bit for bit.
    t, z = capz.read(str(d)), capz.read(ours)
    ok = np.asarray(t.valid)
    assert np.asarray(z.xyz)[ok].tobytes() == np.asarray(t.xyz)[ok].tobytes()


def test_bin_nan_payload_comes_back(tmp_path):
    d = write_folder(tmp_path / "bin", "bin")
    raw = bytearray((d / "000001.bin").read_bytes())
    raw[16:20] = struct.pack("<I", 0x7FC00123)  # point 1's x: a NaN of its own payload
    (d / "000001.bin").write_bytes(bytes(raw))
    z = str(tmp_path / "n.capz")
    capz.compress_file(str(d), z, lossless=True)
    back = tmp_path / "back"
    cli("decompress", z, "-o", str(back) + "/", "-q")
    assert (back / "000001.bin").read_bytes() == bytes(raw)
