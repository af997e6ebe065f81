#!/usr/bin/env python3
"""Would another channel's burst sharpen a channel's magnitude context?
(analysis only, not part of capz; the findings are in docs/lab/2026-11-27-analog-misses.md)

    PYTHONPATH=build/python /usr/bin/python3 tools/analysis/cross_magnitude.py FILE.c3d ...

For each integer channel (or float channel on a lattice, analog_takes.lattice_channels) of a
take: residuals of a whole-channel least-squares predictor of order 8, less, where it lowers
their sum of magnitudes, a weight (1/64 steps) times an earlier channel's residuals (capz's
inter-channel stage, FORMAT.md 11.8, in spirit). Each residual is priced as an adaptive
model codes it: a token (its bit length) under a context, plus its raw bits and sign. Two
contexts: (A) the channel's running mean magnitude in 48 classes, as capz's; (B) the same times
3 classes of an earlier channel's residual magnitude at the same row against that channel's own
running mean (below half, near, above twice), the earlier channel chosen after the fact as the
one that prices lowest (optimistic). Prints, per take, the bytes under A and under B.
"""
import math
import sys

import numpy as np

from analog_takes import analog_takes, lattice_channels


def residuals(k, order=8):
    x = k.astype(np.float64)
    n = len(x)
    r = np.zeros(n, np.int64)
    if n <= 2 * order:
        r[1:] = np.diff(k)
        return r
    X = np.stack([x[order - j - 1:n - j - 1] for j in range(order)], 1)
    w, *_ = np.linalg.lstsq(X, x[order:], rcond=None)
    r[:order] = k[:order] - np.r_[0, k[:order - 1]]
    r[order:] = k[order:] - np.round(X @ w).astype(np.int64)
    return r


def with_reference(r, earlier):
    best, cost = r, np.abs(r).sum()
    for o in earlier:
        den = float((o * o).sum())
        if den == 0:
            continue
        w = round(float((o * r).sum()) / den * 64) / 64
        e = r - np.round(w * o).astype(np.int64)
        if np.abs(e).sum() < cost:
            best, cost = e, np.abs(e).sum()
    return best


def running_mean(a):
    out = np.zeros(len(a))
    m = 0.0
    for i, v in enumerate(a):
        out[i] = m
        m += (v - m) / 16
    return out


def price(r, ctx, contexts):
    freq = np.ones((contexts, 24))
    total = np.full(contexts, 24.0)
    bits = 0.0
    for v, c in zip(r, ctx):
        b = int(abs(int(v))).bit_length()
        bits += -math.log2(freq[c, b] / total[c]) + (b if b else 0)
        freq[c, b] += 24
        total[c] += 24
        if total[c] > 65536:
            freq[c] = np.maximum(1, freq[c] / 2)
            total[c] = freq[c].sum()
    return bits / 8


def main(paths):
    for path, analog in analog_takes(paths):
        chans = [k for _, k, _ in lattice_channels(analog, 8)]
        if not chans:
            continue
        plain = [residuals(k) for k in chans]
        res = [with_reference(plain[c], plain[:c]) for c in range(len(plain))]
        a_total = b_total = 0.0
        for c, r in enumerate(res):
            own = np.minimum(47, np.floor(np.log2(running_mean(np.abs(r)) + 1) * 4)).astype(int)
            a = price(r, own, 48)
            b = a
            for o in res[:c]:
                m = np.abs(o).astype(np.float64)
                mo = running_mean(m)
                rel = np.where(m > 2 * mo + 1, 2, np.where(2 * m + 1 < mo, 0, 1))
                b = min(b, price(r, own * 3 + rel, 144))
            a_total += a
            b_total += b
        print(f"{path}: {len(chans)} channels, A {a_total:.0f} B, B {b_total:.0f} B "
              f"({b_total / a_total:.4f})", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
