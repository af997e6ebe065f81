"""capz.write(..., trc_delimiter=...): the CLI's --trc-delimiter from Python (issue #38 item 1).
A take keeps the delimiter its TRC came with; "tab" and "comma" ask for one; the bytes are those
`capz convert --trc-delimiter` writes."""
import os

import numpy as np
import pytest

import capz
from conftest import cli, shared


def _text(path):
    with open(path, "rb") as f:
        return f.read().decode("latin-1")


def _same_samples(a, b):
    assert a.frames == b.frames and a.points == b.points
    assert np.array_equal(a.valid, b.valid)
    assert np.array_equal(a.xyz[a.valid], b.xyz[b.valid])


def test_a_comma_take_keeps_its_commas_unless_asked(tmp_path):
    src = shared("repo:comma_trc/std_walking5_markers.pyomeca.trc")
    take = capz.read(src)
    capz.write(take, tmp_path / "kept.trc")
    kept = _text(tmp_path / "kept.trc")
    assert kept.startswith("PathFileType,4,(X/Y/Z),")
    widths = {line.count(",") for line in kept.splitlines()}
    assert len(widths) == 1, f"every line padded to one width, got {sorted(widths)}"

    capz.write(take, tmp_path / "tabs.trc", trc_delimiter="tab")
    tabs = _text(tmp_path / "tabs.trc")
    assert tabs.startswith("PathFileType\t4\t(X/Y/Z)\t") and "," not in tabs
    for p in ("kept.trc", "tabs.trc"):
        _same_samples(take, capz.read(tmp_path / p))


def test_comma_from_python_is_the_bytes_capz_convert_writes(tmp_path):
    src = shared("repo:std_walking5_markers.trc")
    capz.write(capz.read(src), tmp_path / "py.trc", trc_delimiter="comma")
    cli("convert", "-q", "--trc-delimiter", "comma", src, str(tmp_path / "cli.trc"))
    assert _text(tmp_path / "py.trc") == _text(tmp_path / "cli.trc")
    assert _text(tmp_path / "py.trc").startswith("PathFileType,4,(X/Y/Z),")
    # A tab take's default stays tabs, as convert's.
    capz.write(capz.read(src), tmp_path / "default.trc")
    cli("convert", "-q", src, str(tmp_path / "cli-tab.trc"))
    assert _text(tmp_path / "default.trc") == _text(tmp_path / "cli-tab.trc")


def test_the_archive_of_a_comma_trc_writes_commas(tmp_path):
    src = shared("repo:comma_trc/std_walking5_markers.sheet-crlf.trc")
    archive = tmp_path / "s.capz"
    capz.compress_file(src, archive, lossless=True)
    capz.write(capz.read(archive), tmp_path / "back.trc")
    assert _text(tmp_path / "back.trc").startswith("PathFileType,4,(X/Y/Z),")
    capz.write(capz.read(archive), tmp_path / "back-tab.trc", trc_delimiter="tab")
    assert "," not in _text(tmp_path / "back-tab.trc")


def test_a_bad_delimiter_is_refused_and_writes_nothing(tmp_path):
    take = capz.read(shared("repo:std_walking5_markers.trc"))
    with pytest.raises(capz.Error) as e:
        capz.write(take, tmp_path / "x.trc", trc_delimiter="semicolon")
    assert e.value.code == "invalid-parameter"
    assert not os.path.exists(tmp_path / "x.trc")
