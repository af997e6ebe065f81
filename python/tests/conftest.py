"""Shared helpers of the Python package's tests (run by ctest as python_pytest, label python).

CAPZ_CLI (the capz binary) and CAPZ_SHARED_DATA (../shared/data) come from ctest's environment
(python/CMakeLists.txt); tests needing what is absent skip with a message.
"""
import json
import os
import subprocess

import numpy as np
import pytest

import capz

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
SHARED = os.environ.get("CAPZ_SHARED_DATA", os.path.join(REPO, "..", "shared", "data"))
CLI = os.environ.get("CAPZ_CLI", os.path.join(REPO, "build", "capz"))


def shared(rel):
    """A path under the shared real data ("repo:NAME": the repository's data/NAME), or a skip
    when it is absent."""
    p = os.path.join(REPO, "data", rel[5:]) if rel.startswith("repo:") else os.path.join(SHARED, rel)
    if not os.path.exists(p):
        pytest.skip(f"shared data not found: {p}")
    return p


def cli(*args):
    """Runs the capz command line; returns stdout (fails the test on a non-zero status)."""
    if not os.path.exists(CLI):
        pytest.skip(f"capz CLI not built: {CLI}")
    r = subprocess.run([CLI, *args], capture_output=True, text=True)
    assert r.returncode == 0, f"capz {' '.join(args)}: {r.stderr}"
    return r.stdout


def cli_info(path):
    return json.loads(cli("info", "--json", path))


_PCD_TYPES = {("F", 4): "<f4", ("F", 8): "<f8", ("U", 1): "u1", ("U", 2): "<u2",
              ("U", 4): "<u4", ("I", 1): "i1", ("I", 2): "<i2", ("I", 4): "<i4"}


def read_pcd_binary(path):
    """One binary PCD file parsed with numpy alone: a structured array, one record a point."""
    with open(path, "rb") as f:
        raw = f.read()
    header, fields = {}, None
    pos = 0
    while True:
        end = raw.index(b"\n", pos)
        line = raw[pos:end].decode("ascii").strip()
        pos = end + 1
        if not line or line.startswith("#"):
            continue
        key, *vals = line.split()
        header[key] = vals
        if key == "DATA":
            break
    assert header["DATA"] == ["binary"], f"{path}: this parser reads binary PCD only"
    names = header["FIELDS"]
    sizes = [int(s) for s in header["SIZE"]]
    types = header["TYPE"]
    counts = [int(c) for c in header.get("COUNT", ["1"] * len(names))]
    fields = []
    for i, (n, s, t, c) in enumerate(zip(names, sizes, types, counts)):
        fields.append((f"{n}_{i}" if n == "_" else n, _PCD_TYPES[(t, s)], (c,) if c > 1 else ()))
    n_points = int(header["POINTS"][0])
    return np.frombuffer(raw, dtype=np.dtype(fields), count=n_points, offset=pos)


def read_pcd_folder_xyz(folder):
    """x y z of every frame of a folder of binary PCD files (natural order: the names sort so
    in the shared data and in what capz writes): float64 (frames, points, 3), NaN at gaps."""
    names = sorted(n for n in os.listdir(folder) if n.endswith(".pcd"))
    frames = []
    for n in names:
        rec = read_pcd_binary(os.path.join(folder, n))
        frames.append(np.stack([rec["x"], rec["y"], rec["z"]], axis=1).astype(np.float64))
    return np.stack(frames)


def synthetic_xyz(frames=120, points=9, seed=1):
    """Smooth marker trajectories in mm."""
    rng = np.random.default_rng(seed)
    t = np.arange(frames)[:, None, None] / 100.0
    base = rng.uniform(-800, 800, size=(1, points, 3))
    amp = rng.uniform(10, 200, size=(1, points, 3))
    return base + amp * np.sin(2 * np.pi * 0.7 * t + rng.uniform(0, 6, size=(1, points, 3)))


@pytest.fixture
def small_take():
    xyz = synthetic_xyz()
    xyz[10:20, 2] = np.nan  # a gap
    xyz[50, 5] = np.nan
    return capz.Take.from_arrays(xyz, rate=100.0, units="mm",
                                 labels=[f"M{i}" for i in range(xyz.shape[1])])
