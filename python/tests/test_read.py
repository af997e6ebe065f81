"""Reading every shared format into arrays that match the C++ reader.

The C++ reader's view of a file is taken through the command line: `capz info --json` for the
metadata and `capz convert FILE folder/` for the coordinates, a folder of binary PCD frames that
numpy parses here on its own (gaps are NaN points there). The package must give the same.
"""
import os

import numpy as np
import pytest

import capz
from conftest import cli, cli_info, read_pcd_folder_xyz, shared

FILES = [
    "c3d/c3dorg/sample_01/Eb015pr.c3d",  # Intel, float storage
    "c3d/c3dorg/sample_01/Eb015vi.c3d",  # DEC, int16 storage
    "c3d/btkdata/PiG/PiG_Calibration2-NoOption.c3d",  # gaps, analog
    "trc/opensim/dataWithBlanksForMissingMarkers.trc",
    "trc/opensim/std_walking2_markers.trc",
]


def check_against_cli(path, take, tmp_path):
    info = cli_info(path)
    assert take.frames == info["frames"] and take.points == info["points"]
    assert take.xyz.shape == (info["frames"], info["points"], 3)
    assert take.xyz.dtype == np.float64 and take.valid.dtype == np.bool_
    assert take.valid.shape == (info["frames"], info["points"])
    assert take.labels == info["labels"]
    assert take.units == info["units"]
    assert take.first_frame == info["first_frame"]
    assert (info["rate"] or 0) == take.rate
    assert int((~take.valid).sum()) == info["gap_samples"]
    assert take.analog.shape[1] == info["analog"]["channels"]
    assert take.analog_labels == info["analog"]["labels"]
    assert take.analog.shape[0] == take.frames * info["analog"]["samples_per_frame"]
    # Coordinates: the C++ reader's, through a PCD folder parsed by numpy.
    out = str(tmp_path / "frames") + "/"
    cli("convert", path, out)
    ref = read_pcd_folder_xyz(out)
    assert ref.shape == take.xyz.shape
    gaps = np.isnan(ref).any(axis=2)
    np.testing.assert_array_equal(~gaps, take.valid)
    np.testing.assert_array_equal(ref[~gaps], take.xyz[take.valid])
    assert np.isnan(take.xyz[~take.valid]).all()


@pytest.mark.parametrize("rel", FILES)
def test_read_c3d_trc_matches_cpp_reader(rel, tmp_path):
    path = shared(rel)
    take = capz.read(path)
    assert take.format == ("c3d" if rel.endswith(".c3d") else "trc")
    check_against_cli(path, take, tmp_path)


def test_read_pcd_folder_matches_files(tmp_path):
    folder = shared("pcd/pcow")
    take = capz.read(folder)
    assert take.format == "pcd-folder"
    ref = read_pcd_folder_xyz(folder)  # the frames as they are on disk
    assert take.xyz.shape == ref.shape
    np.testing.assert_array_equal(take.valid, ~np.isnan(ref).any(axis=2))
    np.testing.assert_array_equal(take.xyz[take.valid], ref[~np.isnan(ref).any(axis=2)])
    info = cli_info(folder)
    assert take.frames == info["frames"] and take.points == info["points"]
    assert take.units == info["units"] == "m" and take.units_assumed and info["units_assumed"]


def test_read_capz_is_decompress(tmp_path):
    path = shared("c3d/btkdata/PiG/PiG_Calibration2-NoOption.c3d")
    out = str(tmp_path / "t.capz")
    cli("compress", path, "-o", out, "--max-error", "0.2mm", "-q")
    a = capz.read(out)
    with open(out, "rb") as f:
        b = capz.decompress(f.read())
    np.testing.assert_array_equal(a.valid, b.valid)
    np.testing.assert_array_equal(a.xyz, b.xyz)  # NaN at the same gaps compare equal here
    np.testing.assert_array_equal(a.analog, b.analog)
    assert a.labels == b.labels and a.rate == b.rate


def test_arrays_are_views_that_keep_the_take_alive():
    take = capz.read(shared("trc/opensim/std_walking2_markers.trc"))
    xyz = take.xyz
    assert not xyz.flags.owndata and xyz.flags.c_contiguous
    first = float(np.nan_to_num(xyz[0, 0, 0]))
    del take
    assert float(np.nan_to_num(xyz[0, 0, 0])) == first  # the view holds the take
