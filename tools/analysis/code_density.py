#!/usr/bin/env python3
"""How much could the uneven use of ADC codes save on a take's integer analog channels?
(analysis only, not part of capz; the findings are in docs/lab/2026-11-27-analog-misses.md)

    PYTHONPATH=build/python /usr/bin/python3 tools/analysis/code_density.py FILE.c3d ...

For each channel of integers, or of floats on a lattice k s (s the smallest gap between its
distinct values), with 64 or more distinct values: the first difference d of k is the residual
and L its histogram over the channel; w(r) the frequency of k mod m, over 1/m. A coder that
weighs L(d) by w((p + d) mod m), p the previous value, saves log2 w(k mod m) - log2 Z(p mod m)
bits a sample (Z the normaliser). The line sums that over the channels for m = 2 .. 64, in bytes.
Both L and w are fitted to the channel itself, so this is an optimistic estimate: an adaptive
coder pays for learning w, about m/2 log2(n) bits a channel.
"""
import math
import sys

import numpy as np

from analog_takes import analog_takes, lattice_channels


def saving_bytes(k, m):
    d = np.diff(k)
    prev, cur = k[:-1], k[1:]
    lo = d.min()
    L = np.bincount(d - lo).astype(float)
    L /= L.sum()
    w = np.bincount(cur % m, minlength=m).astype(float) + 0.5
    w = w / w.sum() * m
    es = np.arange(len(L)) + lo
    Z = np.array([(L * w[(r + es) % m]).sum() for r in range(m)])
    return float((np.log2(w[cur % m]) - np.log2(Z[prev % m])).sum() / 8)


def main(paths):
    mods = (2, 4, 8, 16, 32, 64)
    for path, a in analog_takes(paths):
        total = dict.fromkeys(mods, 0.0)
        for _, k, _ in lattice_channels(a, 64):
            for m in mods:
                total[m] += saving_bytes(k, m)
        print(f"{path}\t" + "\t".join(f"m={m}:{math.floor(v)}" for m, v in total.items()))


if __name__ == "__main__":
    main(sys.argv[1:])
