"""A take's C3D metadata from Python: the parameter section, residuals, camera masks, header
events and analog channels in their units, checked against a parameter reader written here from
the C3D specification (not the library's)."""
import glob
import os
import struct

import numpy as np
import pytest

import capz
from conftest import REPO, SHARED, shared


def _text(b):
    try:
        return b.decode("utf-8")
    except UnicodeDecodeError:
        return b.decode("latin-1")


def _strip(b):
    return _text(b.rstrip(b" \0"))


def _float(raw, proc):
    if proc == 85:  # DEC: the two 16-bit halves swapped, then a quarter of the IEEE value
        return struct.unpack("<f", raw[2:4] + raw[0:2])[0] / 4
    return struct.unpack(">f" if proc == 86 else "<f", raw)[0]


def parameters_of_file(path):
    """{group: {parameter: value}} of a C3D file, valued as Take.parameters documents."""
    with open(path, "rb") as f:
        data = f.read()
    start = (data[0] - 1) * 512
    proc = data[start + 3]
    end = ">" if proc == 86 else "<"
    # The section's own block count, or up to the data when it says less (files that overflow
    # it, such as btkdata's parameterOverflow.c3d).
    (data_start,) = struct.unpack(end + "H", data[16:18])
    sec = data[start:max(start + 512 * max(data[start + 2], 1), (data_start - 1) * 512)]
    groups, params = {}, []
    i = 4
    while i + 2 <= len(sec):
        nlen = struct.unpack("b", sec[i:i + 1])[0]
        gid = struct.unpack("b", sec[i + 1:i + 2])[0]
        if nlen == 0:
            break
        nlen = abs(nlen)
        name = _text(sec[i + 2:i + 2 + nlen])
        j = i + 2 + nlen
        (offset,) = struct.unpack(end + "H", sec[j:j + 2])
        body = j + 2
        if gid < 0:
            dl = sec[body]
            groups[-gid] = name
        else:
            ptype = struct.unpack("b", sec[body:body + 1])[0]
            nd = sec[body + 1]
            dims = list(sec[body + 2:body + 2 + nd])
            size = abs(ptype) * int(np.prod(dims)) if nd else abs(ptype)
            raw = sec[body + 2 + nd:body + 2 + nd + size]
            params.append((gid, name, ptype, dims, raw))
        if offset == 0:
            break
        i = j + offset
    out = {}
    for gid, name, ptype, dims, raw in params:
        key = groups.get(gid, f"#{gid}")
        if ptype == -1:
            if len(dims) <= 1:
                v = _strip(raw)
            else:
                w = dims[0]
                v = [_strip(raw[k:k + w]) for k in range(0, len(raw), w)] if w else []
        else:
            n = len(raw) // abs(ptype)
            if ptype == 4:
                vals = np.array([_float(raw[4 * k:4 * k + 4], proc) for k in range(n)], np.float32)
            elif ptype == 2:
                vals = np.frombuffer(raw, end + "i2").astype(np.int16)
            else:
                vals = np.frombuffer(raw, "u1")
            v = vals.reshape(dims[::-1]) if dims else vals[0].item()
        out.setdefault(key, {})[name] = v
    for gid, g in groups.items():
        out.setdefault(g, {})
    return out


def _same(a, b):
    if isinstance(b, np.ndarray):
        return isinstance(a, np.ndarray) and a.dtype == b.dtype and a.shape == b.shape and (
            a.tobytes() == b.tobytes())
    if isinstance(b, float):
        return isinstance(a, float) and np.float32(a).tobytes() == np.float32(b).tobytes()
    return type(a) is type(b) and a == b


def _c3d_files():
    files = sorted(glob.glob(os.path.join(SHARED, "c3d", "**", "*.[cC]3[dD]"), recursive=True))
    if not files:
        pytest.skip(f"shared C3D files not found under {SHARED}")
    return files


def _shared_takes(repaired=False):
    """(path, take) of each shared C3D file the reader reads; without repaired, not those whose
    parameter section it had to repair (bad_parameter_section.c3d: not this oracle's)."""
    for path in _c3d_files():
        try:
            take = capz.read(path)
        except capz.Error:
            continue  # a file the reader refuses (the corrupt samples)
        if repaired or not any("parameter" in w for w in take.warnings):
            yield path, take


def _check_parameters(path):
    try:
        take = capz.read(path)
    except capz.Error:
        return False  # a file the reader refuses (the corrupt samples)
    if any("parameter" in w for w in take.warnings):
        return False  # sections the reader repairs (bad_parameter_section.c3d): not this oracle's
    want, got = parameters_of_file(path), take.parameters
    assert sorted(got) == sorted(want), path
    for g in want:
        assert sorted(got[g]) == sorted(want[g]), (path, g)
        for p in want[g]:
            assert _same(got[g][p], want[g][p]), (path, g, p, got[g][p], want[g][p])
    return True


def test_parameters_of_the_bundled_samples():
    for name in ("EB015PI.c3d", "Capture0004.c3d", "admarche2.c3d", "held_analog.c3d"):
        assert _check_parameters(os.path.join(REPO, "data", name))


def test_parameters_of_every_shared_c3d():
    read = sum(_check_parameters(f) for f in _c3d_files())
    assert read >= 100


def _events_of_file(path):
    """The EVENT group's events of a C3D file, from the reader here (C3D's EVENT conventions:
    TIMES (minutes, seconds) pairs in file order, USED of them)."""
    ev = parameters_of_file(path).get("EVENT")
    if ev is None:
        return []
    def strs(k):
        v = ev.get(k)
        return [] if v is None else [v] if isinstance(v, str) else list(v)
    def ints(k):
        v = ev.get(k)
        return [] if v is None or isinstance(v, (str, list)) else \
            [int(x) for x in np.asarray(v).reshape(-1)]
    times = [] if "TIMES" not in ev else np.asarray(ev["TIMES"], np.float32).reshape(-1)
    n = len(times) // 2
    if "USED" in ev:
        n = min(n, int(np.asarray(ev["USED"]).reshape(-1)[0]) & 0xFFFF)
    out = []
    for i in range(n):
        def at(v, d):
            return v[i] if i < len(v) else d
        out.append({"label": at(strs("LABELS"), ""), "context": at(strs("CONTEXTS"), ""),
                    "time": 60.0 * float(times[2 * i]) + float(times[2 * i + 1]),
                    "description": at(strs("DESCRIPTIONS"), ""),
                    "subject": at(strs("SUBJECTS"), ""),
                    "icon_id": at(ints("ICON_IDS"), 0),
                    "generic_flag": at(ints("GENERIC_FLAGS"), 0)})
    return out


def test_events_of_every_shared_c3d(tmp_path):
    """Take.events against the EVENT group read here; capz info's JSON on the file and on its
    archive, and the archive's capz.open(...).info, list the same."""
    import json
    from conftest import cli
    with_events = 0
    for path, take in _shared_takes():
        want = _events_of_file(path)
        assert take.events == want, path
        if not want:
            continue
        with_events += 1
        assert json.loads(cli("info", "--json", path))["events"] == want, path
        archive = str(tmp_path / "a.capz")
        capz.compress_file(path, archive, max_error="1mm", overwrite=True)
        assert json.loads(cli("info", "--json", archive))["events"] == want, path
        with capz.open(archive) as z:
            assert z.info["events"] == want, path
    assert with_events >= 20


def test_set_events(tmp_path):
    """set_events writes the EVENT group a C3D reader reads back; the events a file gives, set
    again, leave its EVENT group as it was; refusals change nothing."""
    path = shared("c3d/btkdata/PiG/PiG_Motion-FlatFoot-Full.c3d")
    take = capz.read(path)
    before = take.parameters["EVENT"]
    take.set_events(take.events)
    after = take.parameters["EVENT"]
    assert sorted(after) == sorted(before)
    for k in before:
        if k == "TIMES":  # this file's is 1-D (24); written as C3D's (2, 12)
            assert before[k].shape == (24,) and after[k].shape == (12, 2)
            assert after[k].tobytes() == before[k].tobytes()
        else:
            assert _same(after[k], before[k]), k

    arrays = capz.Take.from_arrays(np.zeros((300, 1, 3)), rate=100.0, units="mm")
    want = [{"label": "Foot Strike", "context": "Left", "time": 0.5},
            {"label": "Foot Off", "context": "Right", "time": 150.25, "icon_id": 2,
             "description": "toe off", "subject": "S1", "generic_flag": -1},
            {"time": 2}]
    arrays.set_events(want)
    out = str(tmp_path / "ev.c3d")
    capz.write(arrays, out)
    full = [dict({"label": "", "context": "", "description": "", "subject": "", "icon_id": 0,
                  "generic_flag": 0}, **e) for e in want]
    for got in (_events_of_file(out), capz.read(out).events,
                capz.decompress(capz.compress(arrays)).events):
        assert [dict(e, time=float(e["time"])) for e in full] == got
    minutes = parameters_of_file(out)["EVENT"]["TIMES"]
    assert minutes.shape == (3, 2) and list(minutes[1]) == [2.0, 30.25]  # 150.25 s

    events = arrays.events
    for bad in ([{"time": -1.0}], [{"label": "x"}], [{"time": 1.0, "lable": "x"}],
                [{"time": 1.0, "icon_id": 40000}], [{"time": "1"}], [{"time": 1.0}] * 256,
                [{"time": 1.0, "label": 3}], ["x"]):
        with pytest.raises(capz.Error) as e:
            arrays.set_events(bad)
        assert e.value.code == "invalid-parameter", bad
        assert arrays.events == events
    fresh = capz.Take.from_arrays(np.zeros((2, 1, 3)), rate=100.0)
    with pytest.raises(capz.Error):
        fresh.set_events([{"time": float("nan")}])
    assert fresh.parameters == {}


def _header_events_of_file(path):
    """The header's event table (words 150-198 of the first block) read here."""
    with open(path, "rb") as f:
        head = f.read(512)
        f.seek((head[0] - 1) * 512 + 3)
        proc = f.read(1)[0]
    end = ">" if proc == 86 else "<"
    (n,) = struct.unpack(end + "H", head[300:302])
    return [{"label": _text(head[396 + 4 * i:400 + 4 * i]).strip(" \x00"),
             "time": float(np.float32(_float(head[304 + 4 * i:308 + 4 * i], proc))),
             "display": head[376 + i] == 1} for i in range(min(n, 18))]


def test_header_events_of_every_shared_c3d():
    with_events = 0
    for path, take in _shared_takes(repaired=True):
        want = _header_events_of_file(path)
        assert take.header_events == want, path
        with_events += bool(want)
    assert with_events >= 20


def test_parameter_lookup():
    take = capz.read(os.path.join(REPO, "data", "EB015PI.c3d"))
    p = take.parameter("point", "rate")
    assert p["type"] == "float" and p["dims"] == [] and p["value"] == take.rate
    labels = take.parameter("POINT", "LABELS")
    assert labels["type"] == "char" and labels["value"][: take.points] == take.labels
    assert take.parameter("POINT", "NO_SUCH") is None
    assert take.parameter("NO_SUCH", "RATE") is None
    corners = take.parameter("FORCE_PLATFORM", "CORNERS")
    if corners is not None:  # dims (3, 4, plates): numpy (plates, 4, 3)
        assert corners["value"].shape == tuple(corners["dims"][::-1])


def test_text_that_is_not_utf8_reads_as_latin1():
    take = capz.read(shared("c3d/c3dorg/sample_16/basketball.c3d"))
    assert take.descriptions[0] == "Kopf"
    golf = capz.read(shared("c3d/c3dorg/sample_16/golf.c3d"))
    assert "Fußspitze re" in golf.descriptions


def test_residuals_and_camera_masks():
    take = capz.read(os.path.join(REPO, "data", "Capture0004.c3d"))
    r, m = take.residuals, take.camera_masks
    assert r.dtype == np.float32 and r.shape == (take.frames, take.points)
    assert m.dtype == np.uint8 and m.shape == (take.frames, take.points)
    gaps = ~take.valid
    assert gaps.any() and (r[gaps] == -1).all() and (m[gaps] == 0).all()
    assert (r[take.valid] >= 0).all()
    arrays = capz.Take.from_arrays(np.zeros((2, 1, 3)), rate=100.0)
    assert arrays.residuals is None and arrays.camera_masks is None
    assert arrays.parameters == {} and arrays.events == [] and arrays.header_events == []


@pytest.mark.parametrize("coding", [{"lossless": True}, {"max_error": "1mm"}])
def test_metadata_survives_compression(coding):
    take = capz.read(os.path.join(REPO, "data", "Capture0004.c3d"))
    back = capz.decompress(capz.compress(take, **coding))
    assert np.array_equal(back.residuals, take.residuals)
    assert np.array_equal(back.camera_masks, take.camera_masks)
    assert back.events == take.events
    assert back.header_events == take.header_events
    want = take.parameters
    got = back.parameters
    assert sorted(got) == sorted(want)
    for g in want:
        for p in want[g]:
            assert _same(got[g][p], want[g][p]), (g, p)


def test_analog_in_physical_units():
    path = os.path.join(REPO, "data", "EB015PI.c3d")
    take = capz.read(path)
    par = parameters_of_file(path)["ANALOG"]
    C = take.analog.shape[1]
    scale = np.asarray(par["SCALE"], np.float64).reshape(-1)[:C]
    offset = np.asarray(par["OFFSET"], np.float64).reshape(-1)[:C]
    gen = float(np.asarray(par["GEN_SCALE"]).reshape(-1)[0])
    want = (take.analog - offset) * (scale * gen)
    assert np.array_equal(take.analog_physical, want)
    assert take.analog_units == [u.strip() for u in par["UNITS"]][:C]
    arrays = capz.Take.from_arrays(np.zeros((3, 1, 3)), rate=100.0, analog=np.ones((3, 2)),
                                   analog_rate=100.0)
    assert np.array_equal(arrays.analog_physical, np.ones((3, 2)))


def _trc_columns(path):
    """The Time and Frame# columns of a TRC file, read here line by line."""
    times, frames = [], []
    with open(path, encoding="latin-1") as f:
        lines = f.read().splitlines()
    for line in lines[5:]:
        cols = line.split("\t")
        if len(cols) < 2 or not cols[0].strip():
            continue
        frames.append(int(cols[0]))
        times.append(float(cols[1]))
    return np.array(times), np.array(frames)


def test_trc_columns():
    path = os.path.join(REPO, "data", "std_walking5_markers.trc")
    take = capz.read(path)
    times, frames = _trc_columns(path)
    trc = take.trc
    assert trc["times"].dtype == np.float64 and trc["frame_numbers"].dtype == np.int64
    assert np.array_equal(trc["frame_numbers"], frames)
    assert np.array_equal(trc["times"], times)
    assert trc["orig_data_rate"] == take.rate
    back = capz.decompress(capz.compress(take, max_error="0.5mm"))
    assert np.array_equal(back.trc["times"], times)
    assert capz.read(os.path.join(REPO, "data", "EB015PI.c3d")).trc is None


def test_random_access_gives_the_frames_words(tmp_path):
    src = os.path.join(REPO, "data", "Capture0004.c3d")
    full = capz.read(src)
    out = str(tmp_path / "c.capz")
    capz.compress_file(src, out)
    with capz.open(out) as z:
        part = z.read_frames(first=10, count=20)
    first = part.first_frame - full.first_frame
    assert part.residuals.shape == (20, full.points)
    assert np.array_equal(part.residuals, full.residuals[first:first + 20])
    assert np.array_equal(part.camera_masks, full.camera_masks[first:first + 20])
    assert sorted(part.parameters) == sorted(full.parameters)
    with capz.open(out) as z:
        head = z.read_frames(first=0, count=0)
    assert head.frames == 0 and sorted(head.parameters) == sorted(full.parameters)


def _check_cli_parameters(path, archive=None):
    """`capz info --parameters --json` on a C3D (and on its archive) against the reader here."""
    import json
    from conftest import cli
    want = parameters_of_file(path)
    for target in [path] + ([archive] if archive else []):
        got = json.loads(cli("info", "--parameters", "--json", target))["parameters"]
        assert sorted(got) == sorted(want), target
        for g in want:
            assert sorted(got[g]) == sorted(want[g]), (target, g)
            for p, w in want[g].items():
                v = got[g][p]["value"]
                if isinstance(w, np.ndarray):
                    flat = w.ravel()  # C order of the reversed dims: the file's order
                    if w.dtype == np.float32:
                        assert np.array_equal(np.asarray(v, np.float64).astype(np.float32), flat)
                    else:
                        assert list(map(int, v)) == flat.tolist(), (g, p)
                    assert got[g][p]["dims"] == list(w.shape[::-1]), (g, p)
                elif isinstance(w, float):
                    assert np.float32(v) == np.float32(w), (g, p)
                else:
                    assert v == w, (target, g, p)


def test_cli_parameters_match_the_file(tmp_path):
    for name in ("EB015PI.c3d", "Capture0004.c3d", "admarche2.c3d"):
        src = os.path.join(REPO, "data", name)
        out = str(tmp_path / (name + ".capz"))
        capz.compress_file(src, out, max_error="1mm")
        _check_cli_parameters(src, out)


def test_cli_parameters_of_every_shared_c3d():
    checked = 0
    for f, _ in _shared_takes():
        _check_cli_parameters(f)
        checked += 1
    assert checked >= 100


def test_cli_parameters_text_and_refusal():
    import subprocess
    from conftest import CLI, cli
    out = cli("info", "--parameters", os.path.join(REPO, "data", "EB015PI.c3d"))
    assert "  POINT:RATE float = 50\n" in out
    assert "  ANALOG:SCALE float[32] = -0.86 -0.884 -1.488 " in out
    assert "(24 more; -v lists all)" in out
    assert "(24 more" not in cli("info", "--parameters", "-v",
                                 os.path.join(REPO, "data", "EB015PI.c3d"))
    r = subprocess.run([CLI, "info", "--parameters", os.path.join(REPO, "data", "depth_small")],
                       capture_output=True, text=True)
    assert r.returncode == 6 and "a PCD take has no parameter section" in r.stderr


def _trc_header_of_file(path):
    """Lines 1-3 of a TRC file, read here: the PathFileType line's fields, then the keys of line 2
    with the values of line 3 (numbers as float, Units as written)."""
    with open(path, encoding="latin-1") as f:
        lines = [next(f).rstrip("\r\n") for _ in range(3)]
    head = {"PathFileType": " ".join(lines[0].rstrip(" \t").split("\t")[1:])}
    for k, v in zip(lines[1].split("\t"), lines[2].split("\t")):
        if k.strip():  # writers pad the lines with tabs
            head[k.strip()] = v.strip() if k.strip() == "Units" else float(v)
    return head


def test_cli_trc_header(tmp_path):
    """`capz info --parameters` on a TRC (and its archive) gives the file's header lines."""
    import json
    from conftest import cli
    files = [os.path.join(REPO, "data", "std_walking5_markers.trc")]
    if os.path.isdir(os.path.join(SHARED, "trc")):
        for root, _, names in os.walk(os.path.join(SHARED, "trc")):
            files += [os.path.join(root, n) for n in sorted(names) if n.lower().endswith(".trc")]
    for path in files:
        want = _trc_header_of_file(path)
        take = capz.read(path)  # the counts are what was read (a header may say otherwise)
        want["NumFrames"], want["NumMarkers"] = take.frames, take.points
        archive = str(tmp_path / "x.capz")
        capz.compress_file(path, archive, max_error="1mm", overwrite=True)
        for target in (path, archive):
            got = json.loads(cli("info", "--parameters", "--json", target))["trc_header"]
            assert got == want, (path, target)
        text = cli("info", "--parameters", path)
        assert text.startswith("TRC header\n  PathFileType ")
        assert "  NumFrames           %d\n" % want["NumFrames"] in text


def test_set_parameter_is_written_and_compressed(tmp_path):
    take = capz.read(os.path.join(REPO, "data", "EB015PI.c3d"))
    corners = take.parameters["FORCE_PLATFORM"]["CORNERS"].copy()
    corners[1, 2, 0] = 12.25
    take.set_parameter("force_platform", "corners", corners)  # an existing one, any case
    take.set_parameter("SUBJECTS", "NAMES", ["Alice", "Bob"], description="who")
    take.set_parameter("SUBJECTS", "MASS", 71.5)
    take.set_parameter("SUBJECTS", "IDS", np.array([[3, 4, 5], [6, 7, 65535]]))
    take.set_parameter("SUBJECTS", "FLAGS", np.array([1, 2], np.uint8))
    out = str(tmp_path / "x.c3d")
    capz.write(take, out)
    want = parameters_of_file(out)  # the specification reader, on the file written
    assert want["FORCE_PLATFORM"]["CORNERS"][1, 2, 0] == np.float32(12.25)
    assert want["SUBJECTS"]["NAMES"] == ["Alice", "Bob"]
    assert want["SUBJECTS"]["MASS"] == 71.5
    assert want["SUBJECTS"]["IDS"].tolist() == [[3, 4, 5], [6, 7, -1]]  # 65535 as int16 bits
    assert want["SUBJECTS"]["FLAGS"].dtype == np.uint8
    assert capz.read(out).parameter("SUBJECTS", "NAMES")["description"] == "who"
    back = capz.decompress(capz.compress(take, max_error="1mm"))
    for g in ("FORCE_PLATFORM", "SUBJECTS"):
        for p, v in take.parameters[g].items():
            assert _same(back.parameters[g][p], v), (g, p)


def test_set_parameter_refusals():
    take = capz.read(os.path.join(REPO, "data", "EB015PI.c3d"))
    bad = [("G", "N", True), ("G", "N", {"a": 1}), ("G", "N", 70000), ("G", "N", [1, 2]),
           ("G", "N", np.zeros(300)), ("G", "N", np.zeros((1,) * 8)),
           ("G", "N", np.array(["a"])), ("", "N", 1), ("G", "A NAME", 1), ("G", "N" * 128, 1)]
    for g, n, v in bad:
        with pytest.raises(capz.Error) as e:
            take.set_parameter(g, n, v)
        assert e.value.code == "invalid-parameter", (g, n, v)
    assert take.parameter("G", "N") is None  # nothing half-set
    arrays = capz.Take.from_arrays(np.zeros((2, 1, 3)), rate=100.0)
    with pytest.raises(capz.Error):
        arrays.set_parameter("SUBJECTS", "MASS", True)
    assert arrays.parameters == {}  # no section made for a refused value


@pytest.mark.parametrize("source", ["arrays", "trc"])
def test_set_parameter_on_a_take_without_a_section(tmp_path, source):
    """The take gets the section writing it alone would give, and the parameter beside it."""
    def make():
        if source == "trc":
            return capz.read(os.path.join(REPO, "data", "std_walking5_markers.trc"))
        rng = np.random.default_rng(7)
        xyz = rng.normal(size=(40, 3, 3)) * 100
        xyz[5, 1] = np.nan
        return capz.Take.from_arrays(xyz, rate=100.0, units="mm", labels=["A", "B", "C"],
                                     analog=rng.normal(size=(160, 2)), analog_rate=400.0,
                                     analog_labels=["Fz", "EMG"])
    alone, take = make(), make()
    take.set_parameter("SUBJECTS", "MASS", 70.5, "kg")
    take.set_parameter("SUBJECTS", "NAMES", ["Ann"])
    a, b = str(tmp_path / "alone.c3d"), str(tmp_path / "with.c3d")
    capz.write(alone, a)
    capz.write(take, b)
    want, got = parameters_of_file(a), parameters_of_file(b)
    assert sorted(got) == sorted(list(want) + ["SUBJECTS"])
    for g in want:
        assert got[g].keys() == want[g].keys(), g
        for p in want[g]:
            assert _same(got[g][p], want[g][p]), (g, p)
    assert got["SUBJECTS"]["MASS"] == pytest.approx(70.5)
    assert list(got["SUBJECTS"]["NAMES"]) == ["Ann"]
    x, y = capz.read(a), capz.read(b)
    assert np.array_equal(x.xyz, y.xyz, equal_nan=True) and np.array_equal(x.analog, y.analog)
    for coding in ({"lossless": True}, {"max_error": "0.5mm"}):
        back = capz.decompress(capz.compress(take, **coding))
        assert back.parameter("SUBJECTS", "NAMES")["value"] == ["Ann"]
        assert back.parameter("SUBJECTS", "MASS")["description"] == "kg"


def test_set_parameter_does_not_override_what_describes_the_data(tmp_path):
    take = capz.read(os.path.join(REPO, "data", "EB015PI.c3d"))
    take.set_parameter("POINT", "RATE", 999.0)
    take.set_parameter("POINT", "USED", 3)
    out = str(tmp_path / "x.c3d")
    capz.write(take, out)
    back = capz.read(out)
    assert back.rate == 50.0 and back.points == 26
    assert parameters_of_file(out)["POINT"]["USED"] == 26


def test_analog_labels_can_be_set(tmp_path):
    take = capz.read(os.path.join(REPO, "data", "EB015PI.c3d"))
    names = [f"CH{i}" for i in range(take.analog.shape[1])]
    take.analog_labels = names
    out = str(tmp_path / "x.c3d")
    capz.write(take, out)
    assert capz.read(out).analog_labels == names
    assert parameters_of_file(out)["ANALOG"]["LABELS"] == names
    assert capz.decompress(capz.compress(take)).analog_labels == names
    with pytest.raises(capz.Error):
        take.analog_labels = names[:-1]
    assert take.analog_labels == names


def test_write_warns_what_the_format_drops(tmp_path):
    import warnings
    pig = shared("c3d/btkdata/PiG/PiG_Motion-FlatFoot-One.c3d")
    take = capz.read(pig)
    with pytest.warns(UserWarning) as w:
        capz.write(take, str(tmp_path / "p.trc"))
    assert len(w) == 1
    assert str(w[0].message).endswith(
        "p.trc does not keep the 38 analog channels, the C3D parameter section (with its 8 "
        "events)")
    with pytest.warns(UserWarning, match=r"the frame rate \(100 Hz\)"):
        capz.write(take, str(tmp_path / "frames") + "/")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # C3D keeps it all; a TRC take into TRC too
        capz.write(take, str(tmp_path / "p.c3d"))
        capz.write(capz.read(str(tmp_path / "p.trc")), str(tmp_path / "q.trc"))


def test_text_of_a_latin1_file_is_set_back_as_latin1(tmp_path):
    """golf.c3d's descriptions are Latin-1: what is read and set again keeps its bytes, and new
    text in such a take is Latin-1 where it can be; a UTF-8 (here ASCII) take gets UTF-8."""
    path = shared("c3d/c3dorg/sample_16/golf.c3d")
    take = capz.read(path)
    want = parameters_of_file(path)["POINT"]["DESCRIPTIONS"]
    take.set_parameter("POINT", "DESCRIPTIONS", take.parameters["POINT"]["DESCRIPTIONS"])
    take.labels = take.labels
    take.set_parameter("SUBJECTS", "NAMES", ["Jürgen"], description="Größe")
    take.set_events([{"label": "Ölwechsel", "time": 1.0}])
    out = str(tmp_path / "golf.c3d")
    capz.write(take, out)
    assert parameters_of_file(out)["POINT"]["DESCRIPTIONS"] == want
    raw = open(out, "rb").read()
    for text in ("Fußspitze re", "Jürgen", "Größe", "Ölwechsel"):
        assert text.encode("latin-1") in raw and text.encode() not in raw, text
    assert capz.read(out).events[0]["label"] == "Ölwechsel"
    take.set_parameter("SUBJECTS", "SIGN", ["€"])  # no Latin-1 byte: UTF-8
    capz.write(take, out, overwrite=True)
    assert "€".encode() in open(out, "rb").read()

    ascii_take = capz.read(os.path.join(REPO, "data", "EB015PI.c3d"))
    ascii_take.set_parameter("SUBJECTS", "NAMES", ["Jürgen"])
    capz.write(ascii_take, out, overwrite=True)
    assert "Jürgen".encode() in open(out, "rb").read()
    with pytest.raises(capz.Error):
        ascii_take.labels = "x" * ascii_take.points
