"""Copies and pickles of a Take: every public attribute the same, and nothing shared."""
import copy
import multiprocessing
import os
import pickle

import numpy as np
import pytest

import capz
from conftest import REPO


def _public(take):
    out = {}
    for name in dir(take):
        if name.startswith("_"):
            continue
        value = getattr(take, name)
        if not callable(value):
            out[name] = value
    return out


def _same(a, b):
    if isinstance(a, np.ndarray):
        return (isinstance(b, np.ndarray) and a.shape == b.shape and a.dtype == b.dtype and
                a.tobytes() == b.tobytes())
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return type(a) is type(b) and len(a) == len(b) and all(map(_same, a, b))
    if isinstance(a, float) and np.isnan(a):
        return isinstance(b, float) and np.isnan(b)
    return type(a) is type(b) and a == b


def _takes():
    data = os.path.join(REPO, "data")
    takes = [capz.read(os.path.join(data, n))
             for n in ("EB015PI.c3d", "admarche2.c3d", "std_walking5_markers.trc", "depth_small")]
    rng = np.random.default_rng(3)
    xyz = rng.normal(size=(9000, 2, 3)) * 1e3  # two windows of frames; float64 bits throughout
    xyz[17, 1] = np.nan
    arrays = capz.Take.from_arrays(xyz, rate=250.0, units="m", labels=["a", "b"],
                                   analog=rng.normal(size=(18000, 1)), analog_rate=500.0)
    arrays.set_parameter("SUBJECTS", "NAMES", ["Ann"])
    takes.append(arrays)
    lossy = capz.read(os.path.join(data, "EB015PI.c3d"))
    takes.append(capz.decompress(capz.compress(lossy, analog_max_error={"V": 0.01})))
    return takes


def test_copies_and_pickles_hold_every_attribute():
    for take in _takes():
        want = _public(take)
        for how, other in (("pickle", pickle.loads(pickle.dumps(take))),
                           ("deepcopy", copy.deepcopy(take)), ("copy", copy.copy(take)),
                           ("method", take.copy())):
            got = _public(other)
            assert sorted(got) == sorted(want), how
            for name in want:
                assert _same(got[name], want[name]), (repr(take), how, name)


def test_warnings_and_source_are_pickled():
    take = capz.read(os.path.join(REPO, "data", "admarche2.c3d"))
    assert take.warnings and take.source
    back = pickle.loads(pickle.dumps(take))
    assert back.warnings == take.warnings and back.source == take.source


def test_copies_share_nothing():
    take = capz.read(os.path.join(REPO, "data", "EB015PI.c3d"))
    params, events = take.parameters, take.events
    for other in (take.copy(), copy.copy(take), copy.deepcopy(take),
                  pickle.loads(pickle.dumps(take))):
        other.set_parameter("SUBJECTS", "MASS", 70.5)
        other.set_events([{"label": "Foot Strike", "time": 1.0}])
        assert other.parameter("SUBJECTS", "MASS") is not None
        assert take.parameter("SUBJECTS", "MASS") is None
        assert take.events == events and sorted(take.parameters) == sorted(params)


def test_a_pool_returns_takes():
    data = os.path.join(REPO, "data")
    paths = [os.path.join(data, n) for n in ("EB015PI.c3d", "std_walking5_markers.trc")]
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        takes = pool.map(capz.read, paths)
    for path, got in zip(paths, takes):
        want = _public(capz.read(path))
        have = _public(got)
        for name in want:
            assert _same(have[name], want[name]), (path, name)


def test_a_state_from_elsewhere_is_refused():
    take = capz.read(os.path.join(REPO, "data", "EB015PI.c3d"))
    state = take.__reduce_ex__(2)[2]
    for bad in ((2,) + tuple(state[1:]), (1, b"not an archive", "", []), (1,)):
        fresh = capz.Take.__new__(capz.Take)  # what pickle.loads sets the state of
        with pytest.raises(capz.Error):
            fresh.__setstate__(bad)
