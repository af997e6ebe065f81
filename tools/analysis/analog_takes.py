"""Helper: the analog samples of a take, for rand_channels.py and code_density.py.
(analysis only, not part of capz; the findings are in docs/lab/2026-11-27-analog-misses.md)"""
import numpy as np

import capz


def analog_takes(paths):
    """Yields (path, analog) for each path capz reads that has analog samples: analog is float64,
    (frames x samples per frame, channels). Prints one line for each other path and goes on."""
    for path in paths:
        try:
            take = capz.read(path)
        except capz.Error as e:
            print(f"{path}: not read ({e})")
            continue
        analog = np.asarray(take.analog, dtype=np.float64)
        if analog.size == 0:
            print(f"{path}: no analog samples")
            continue
        yield path, analog


def lattice_ints(x):
    """x's samples as integers k on a step s, as (k, s): (x, 1) when every value is a whole
    number, else k = round(x / s) for s the smallest gap between distinct values, when k s is
    within s / 1000 of every sample; None otherwise."""
    vals = np.unique(x)
    if np.all(vals == np.round(vals)):
        return x.astype(np.int64), 1.0
    gaps = np.diff(vals)
    step = gaps[gaps > 0].min()
    k = np.round(x / step)
    if np.abs(k * step - x).max() > step * 1e-3:
        return None
    return k.astype(np.int64), step


def lattice_channels(a, min_distinct):
    """Yields (c, k, s) for each channel c of a whose samples are finite, take at least
    min_distinct values and are integers k on a step s (lattice_ints)."""
    for c in range(a.shape[1]):
        x = a[:, c]
        if not np.all(np.isfinite(x)) or len(np.unique(x)) < min_distinct:
            continue
        fit = lattice_ints(x)
        if fit is not None:
            yield (c, *fit)
