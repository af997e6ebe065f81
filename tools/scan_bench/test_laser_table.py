#!/usr/bin/python3
"""Checks laser_table.infer on synthetic spinning sweeps with a known table: 16 lasers from
-15 to +15 degrees, z offsets growing with the elevation (as RoboSense's do), 1800 firings a
turn, ranges from a ground plane and a wall, 2 mm range noise; once with a ring field and once
clustered from the elevations. Exits 1 with the first fault; prints '2 passed, 0 failed'."""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import laser_table  # noqa: E402


def sweep(rng, elev, offs, steps=1800):
    az = (np.arange(steps) + 0.5) * 2 * math.pi / steps
    pts, rings = [], []
    for k, (e, z0) in enumerate(zip(elev, offs)):
        d = np.full(steps, 12.0) + 3 * np.sin(3 * az)  # a wavy wall
        if e < 0:
            d = np.minimum(d, 1.8 / -math.tan(e))  # the ground 1.8 m below
        d = d + rng.normal(0, 0.002, steps)
        keep = rng.random(steps) > 0.2  # returns missing at random
        r = d * math.cos(e)
        p = np.stack([r * np.cos(az), r * np.sin(az), z0 + r * math.tan(e)], axis=1)[keep]
        pts.append(p)
        rings.append(np.full(len(p), k))
    return np.concatenate(pts).astype(np.float32), np.concatenate(rings)


def check(table, elev, offs, steps, what):
    if len(table) != len(elev):
        return '%s: %d lasers found, %d made' % (what, len(table), len(elev))
    for e, t, z in zip(table, np.tan(elev), offs):
        if abs(e['tan'] - t) > 2e-4 or abs(e['z'] - z) > 2e-3:
            return '%s: laser (%.5f, %.4f) inferred as (%.5f, %.4f)' % (what, t, z, e['tan'],
                                                                          e['z'])
        if abs(e['points_per_turn'] - steps) > steps * 0.01:
            return '%s: %d points per turn inferred, %d made' % (what, e['points_per_turn'],
                                                                   steps)
    return None


def main():
    rng = np.random.default_rng(7)
    elev = np.radians(np.linspace(-15, 15, 16))
    offs = 0.004 * np.linspace(-1, 1, 16)
    frames, rings = zip(*[sweep(rng, elev, offs) for _ in range(2)])
    faults = [check(laser_table.infer(list(frames), list(rings)), elev, offs, 1800, 'ring field'),
              check(laser_table.infer(list(frames)), elev, offs, 1800, 'clustered')]
    bad = [f for f in faults if f]
    for f in bad:
        print('FAIL ' + f)
    print('%d passed, %d failed' % (len(faults) - len(bad), len(bad)))
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
