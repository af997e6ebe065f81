"""capz.open: frames decoded on demand, and the info `capz info --json` prints."""
import numpy as np
import pytest

import capz
from conftest import cli, cli_info, shared


@pytest.fixture
def archive(tmp_path):
    src = shared("repo:EB015PI.c3d")  # 450 frames, gaps, 16 analog channels
    out = str(tmp_path / "a.capz")
    cli("compress", src, "-o", out, "--window", "32", "-q")
    return out


def test_read_frames_equals_slice_of_whole(archive):
    whole = capz.read(archive)
    with capz.open(archive) as z:
        assert z.frames == whole.frames and z.points == whole.points
        for first, count in [(0, 10), (100, 50), (31, 2), (400, 100), (0, None)]:
            part = z.read_frames(first=first, count=count)
            end = whole.frames if count is None else min(whole.frames, first + count)
            assert part.frames == end - first
            np.testing.assert_array_equal(part.valid, whole.valid[first:end])
            np.testing.assert_array_equal(part.xyz, whole.xyz[first:end])
            spf = whole.analog_samples_per_frame
            np.testing.assert_array_equal(part.analog, whole.analog[first * spf:end * spf])
            assert part.first_frame == whole.first_frame + first
            assert part.labels == whole.labels
        assert z.read_frames(first=whole.frames + 5, count=3).frames == 0


def test_info_is_cli_info_for_every_golden_stream():
    """Every format version and source kind (C3D with events and analog, TRC, PCD with fields
    and bounds, rotations): capz.open().info is `capz info --json`, key for key."""
    import glob
    import os
    from conftest import REPO
    streams = sorted(glob.glob(os.path.join(REPO, "tests", "golden", "streams", "*.capz")))
    assert len(streams) >= 20
    kinds = set()
    for path in streams:
        with capz.open(path) as z:
            info = z.info
        assert info == cli_info(path), path
        kinds.add(info["source_format"])
        kinds |= {k for k in ("fields", "events") if k in info}
    assert {"c3d", "trc", "pcd-folder", "fields", "events"} <= kinds


def test_info_is_cli_info(archive):
    with capz.open(archive) as z:
        info = z.info
    assert info == cli_info(archive)
    assert info["windows"] > 1 and info["window_frames"] == 32
    # The archive records the original C3D it was made from: its size and XXH3-128.
    assert info["original"]["bytes"] > 0 and len(info["original"]["xxh3_128"]) == 32


def test_closed_file_raises(archive):
    z = capz.open(archive)
    z.close()
    with pytest.raises(capz.Error):
        z.read_frames(0, 1)


def test_open_non_capz_raises():
    with pytest.raises(capz.Error) as e:
        capz.open(shared("trc/opensim/std_walking2_markers.trc"))
    assert e.value.code == "not-our-format"
