"""compress_file gives the same bytes as `capz compress`, for every input kind and target."""
import json
import os
import signal
import threading
import warnings

import numpy as np
import pytest

import capz
from conftest import cli, shared

CASES = [
    ("repo:EB015PI.c3d", {"max_error": "0.5mm"}, ["--max-error", "0.5mm"]),
    ("repo:EB015PI.c3d", {"analog_max_error": {"N": 0.5, "Nmm": 50}},
     ["--analog-max-error", "N=0.5,Nmm=50"]),
    ("repo:std_walking5_markers.trc", {"lossless": True}, ["--lossless"]),
    ("c3d/btkdata/PiG/PiG_Calibration2-NoOption.c3d", {}, []),  # the default bound, 0.1 mm
    ("c3d/btkdata/PiG/PiG_Calibration2-NoOption.c3d", {"max_error": "0.5mm"},
     ["--max-error", "0.5mm"]),
    ("c3d/c3dorg/sample_01/Eb015vi.c3d", {"lossless": True}, ["--lossless"]),
    ("trc/opensim/dataWithBlanksForMissingMarkers.trc", {"max_error": 0.02},
     ["--max-error", "0.02"]),
    ("trc/opensim/std_walking2_markers.trc", {"kg_error": 0.3}, ["--kg-error", "0.3"]),
    ("trc/opensim/std_walking2_markers.trc", {"codec": "ts", "max_error": "0.3mm"},
     ["--codec", "ts", "--max-error", "0.3mm"]),
    ("c3d/c3dorg/sample_01/Eb015pr.c3d", {"codec": "auto", "window": 64},
     ["--codec", "auto", "--window", "64"]),
    ("pcd/pcow", {}, []),  # no units: 1e-4 of the bounding-box diagonal
    ("pcd/pcow", {"max_error": "0.5mm", "units": "m"}, ["--max-error", "0.5mm", "--units", "m"]),
]


@pytest.mark.parametrize("rel,kwargs,args", CASES)
def test_same_bytes_as_cli(rel, kwargs, args, tmp_path):
    src = shared(rel)
    ours, theirs = str(tmp_path / "py.capz"), str(tmp_path / "cli.capz")
    report = capz.compress_file(src, ours, **kwargs)
    out = json.loads(cli("compress", src, "-o", theirs, "--json", *args))
    with open(ours, "rb") as a, open(theirs, "rb") as b:
        mine, cli_bytes = a.read(), b.read()
    assert mine == cli_bytes
    assert report["bytes"] == out["output_bytes"] == len(mine)
    assert report["grid_step"] == out["grid_step"] and report["codec"] == out["codec"]


def test_compress_file_refuses_to_overwrite(tmp_path):
    src = shared("trc/opensim/std_walking2_markers.trc")
    out = str(tmp_path / "o.capz")
    capz.compress_file(src, out)
    with pytest.raises(capz.Error) as e:
        capz.compress_file(src, out)
    assert e.value.code == "usage" and e.value.exit_status == 1
    capz.compress_file(src, out, overwrite=True, max_error="1mm")


def test_compress_file_default_output_and_bad_options(tmp_path):
    import shutil

    src = str(tmp_path / "w.trc")
    shutil.copy(shared("trc/opensim/std_walking2_markers.trc"), src)
    capz.compress_file(src)
    assert capz.open(src + ".capz").frames == capz.read(src).frames
    for kwargs in ({"max_error": "0.1mm", "lossless": True}, {"max_error": "-1"},
                   {"max_error": "0"}, {"kg_error": 0}, {"max_error": "1 parsec"},
                   {"codec": "nope"}, {"units": "furlong"}):
        with pytest.raises(capz.Error) as e:
            capz.compress_file(src, str(tmp_path / "x.capz"), **kwargs)
        assert e.value.code in ("usage", "invalid-parameter"), kwargs
    assert not (tmp_path / "x.capz").exists()  # nothing partial left


def test_a_stray_point_does_not_set_the_default_bound(tmp_path):
    """One far point (a driver's garbage return) used to set the default bound for all: 1e-4 of a
    diagonal of 500 km is 50 m. The others' box sets it now, with a warning, as the CLI's note."""
    import numpy as np
    rng = np.random.default_rng(7)
    xyz = rng.random((1, 5000, 3)) * [100.0, 100.0, 10.0]
    xyz[0, 5] = [5e5, 0, 0]
    take = capz.Take.from_arrays(xyz, units="")  # no units: the default is a fraction of the box
    with pytest.warns(UserWarning, match="far outside the others"):
        _, stats = capz.compress(take, stats=True)
    assert 0.001 < stats["grid_step"] < 0.05
    path = tmp_path / "sweep.pcd"
    capz.write(take, str(path))
    with pytest.warns(UserWarning, match="far outside the others"):
        stats = capz.compress_file(str(path), str(tmp_path / "s.capz"))
    out = json.loads(cli("compress", str(path), "-o", str(tmp_path / "c.capz"), "--json"))
    assert stats["grid_step"] == out["grid_step"] < 0.05


def test_absent_samples_holding_coordinates_warn_as_the_cli_notes(tmp_path):
    """A C3D whose samples are marked absent but hold coordinates (SIMI, sample_16): at a bound
    they are not kept, which the CLI's note says and compress_file now warns too (it said
    nothing); lossless=True keeps them, without a word."""
    giant = shared("c3d/c3dorg/sample_16/giant.c3d")
    with pytest.warns(UserWarning, match="10295 samples marked absent .* hold coordinates"):
        capz.compress_file(giant, str(tmp_path / "g.capz"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        capz.compress_file(giant, str(tmp_path / "l.capz"), lossless=True)


def test_progress_reports_each_window_and_same_bytes(tmp_path):
    src = shared("repo:lidar_small")
    calls = []
    out = str(tmp_path / "p.capz")
    capz.compress_file(src, out, max_error="1mm", window=2,
                       progress=lambda done, total: calls.append((done, total)))
    assert calls == [(2, 6), (4, 6), (6, 6)]
    plain = str(tmp_path / "q.capz")
    capz.compress_file(src, plain, max_error="1mm", window=2)
    with open(out, "rb") as a, open(plain, "rb") as b:
        assert a.read() == b.read()
    take = capz.read(src)
    seen = []
    data = capz.compress(take, max_error="1mm", window=4, progress=lambda d, t: seen.append(d))
    assert seen == [4, 6] and data == capz.compress(take, max_error="1mm", window=4)


class Stop(Exception):
    pass


def test_an_exception_from_progress_stops_and_leaves_nothing(tmp_path):
    src = shared("repo:lidar_small")

    def stop(done, total):
        if done >= 2:
            raise Stop("enough")

    out = str(tmp_path / "s.capz")
    with pytest.raises(Stop):
        capz.compress_file(src, out, max_error="1mm", window=1, progress=stop)
    assert os.listdir(tmp_path) == []  # no output, no temporary
    with pytest.raises(Stop):
        capz.compress(capz.read(src), max_error="1mm", window=1, progress=stop)


def test_ctrl_c_stops_compress_file_after_the_window_at_hand(tmp_path):
    # SIGINT sent from another thread while the library codes (the GIL released, no progress
    # callback): its handler runs at the end of the window at hand, and KeyboardInterrupt stops
    # the coding with nothing written. Without the check the 400 windows would all be coded and
    # the archive written before KeyboardInterrupt was raised.
    rng = np.random.default_rng(1)
    xyz = np.cumsum(rng.normal(0, 0.001, (400, 4096, 3)), axis=0) + rng.normal(0, 1, (1, 4096, 3))
    src = str(tmp_path / "frames")
    with warnings.catch_warnings():  # (PCD frames keep no frame rate)
        warnings.simplefilter("ignore")
        capz.write(capz.Take.from_arrays(xyz, units="m"), src)
    out = str(tmp_path / "c.capz")
    timer = threading.Timer(0.05, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            capz.compress_file(src, out, max_error="1mm", window=1)
    finally:
        timer.cancel()
    assert os.listdir(tmp_path) == ["frames"]


def test_decompress_and_read_report_each_window_and_stop_on_an_exception(tmp_path):
    src = shared("repo:lidar_small")
    out = str(tmp_path / "w.capz")
    capz.compress_file(src, out, max_error="1mm", window=2)
    with open(out, "rb") as f:
        data = f.read()
    seen = []
    back = capz.decompress(data, progress=lambda done, total: seen.append((done, total)))
    assert seen == [(2, 6), (4, 6), (6, 6)] and back.frames == 6
    read = []
    assert capz.read(out, progress=lambda d, t: read.append(d)).frames == 6 and read == [2, 4, 6]

    def stop(done, total):
        if done >= 4:
            raise Stop("enough")

    with pytest.raises(Stop):
        capz.decompress(data, progress=stop)
    with pytest.raises(Stop):
        capz.read(out, progress=stop)


def test_read_of_a_folder_reports_each_block_and_stops_on_an_exception(tmp_path):
    # Frame folders and files (and C3D, TRC) are read a block at a time (up to 64 frames):
    # progress after each, and an exception it raises, or Ctrl-C, stops the read there.
    src = shared("repo:lidar_small")
    whole = capz.read(src)
    seen = []
    back = capz.read(src, progress=lambda done, total: seen.append((done, total)))
    assert seen and seen[-1] == (whole.frames, whole.frames)
    assert [d for d, _ in seen] == sorted(set(d for d, _ in seen))
    assert np.array_equal(back.xyz, whole.xyz, equal_nan=True)
    assert np.array_equal(back.valid, whole.valid)
    frames = str(tmp_path / "frames")
    rng = np.random.default_rng(2)
    with warnings.catch_warnings():  # (PCD frames keep no frame rate)
        warnings.simplefilter("ignore")
        capz.write(capz.Take.from_arrays(rng.normal(0, 1, (200, 64, 3)), units="m"), frames)
    calls = []

    def stop(done, total):
        calls.append(done)
        if len(calls) == 2:
            raise Stop("enough")

    with pytest.raises(Stop):
        capz.read(frames, progress=stop)
    assert len(calls) == 2 and calls[1] < 200

