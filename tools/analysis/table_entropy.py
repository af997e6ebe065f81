#!/usr/bin/env python3
"""What could contexts save on the value tables of a take's rank channels?
(analysis only, not part of capz; the findings are in docs/lab/2026-11-27-analog-misses.md)

    PYTHONPATH=build/python /usr/bin/python3 tools/analysis/table_entropy.py FILE.c3d ...

For each channel with 16 or more distinct finite values, and at most one per two samples (a
rank channel's kind of table): the sorted values t on a lattice of step s and offset o (s the
smallest gap, refined by least squares), each entry after the first coded as FORMAT.md 11.7's
lattice tables code it, a gap m = round((t[i] - t[i-1]) / s) in steps and a correction d from
float32(t[i-1] + m s) in float32 units. Prints the empirical entropies of m and d at order 0,
and of m under the previous gap (capped at 4) and d under m (capped at 3), in bytes, with no
cost for learning the distributions.
"""
import sys

import numpy as np

from analog_takes import analog_takes


def ordered_f32(v):
    b = np.asarray(v, dtype=np.float32).view(np.uint32).astype(np.int64)
    return np.where(b & 0x80000000, 0x7FFFFFFF - (b & 0x7FFFFFFF), b + 0x80000000)


def entropy_bits(x):
    if len(x) == 0:
        return 0.0
    _, c = np.unique(x, return_counts=True)
    p = c / c.sum()
    return float(-(c * np.log2(p)).sum())


def conditional_bits(x, ctx):
    return sum(entropy_bits(x[ctx == v]) for v in np.unique(ctx))


def main(paths):
    for path, a in analog_takes(paths):
        order0 = context = 0.0
        for c in range(a.shape[1]):
            u = np.unique(a[:, c])
            u = u[np.isfinite(u)]
            if len(u) < 16 or len(u) > len(a) // 2:
                continue
            g = np.diff(u)
            k = np.round((u - u[0]) / g[g > 0].min())
            s, o = np.linalg.lstsq(np.vstack([k, np.ones_like(k)]).T, u, rcond=None)[0]
            m = np.diff(np.round((u - o) / s)).astype(int)
            d = ordered_f32(u[1:]) - ordered_f32((u[:-1] + m * s).astype(np.float32))
            order0 += entropy_bits(m) + entropy_bits(d)
            context += conditional_bits(m[1:], np.minimum(m[:-1], 4)) + conditional_bits(
                d, np.minimum(m, 3))
        if order0:
            print(f"{path}: order 0 {order0 / 8:.0f} B, with contexts {context / 8:.0f} B")


if __name__ == "__main__":
    main(sys.argv[1:])
