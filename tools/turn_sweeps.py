#!/usr/bin/env python3
"""Makes a turning sensor's sweeps from a still sensor's: sweep f of a scan folder turned about
the sensor's z axis by f x DEGREES (a sensor on a platform turning at DEGREES a sweep, seeing a
still scene). A multiple of the sensor's azimuth step keeps every point on its firing column
(pandar64-factory20: 0.1 degree, so 1.2 is 12 columns a sweep). Writes binary PCD frames of
x y z (float32) under the sources' names (docs/lab/2026-11-30-moving-sensor.md).

Usage (numpy and capz's Python module; /usr/bin/python3):
    PYTHONPATH=build/python /usr/bin/python3 tools/turn_sweeps.py \\
        ../shared/data/scan/pandar64-factory20 OUT [--degrees 1.2]
"""
import argparse
import os

import numpy as np

import capz
from make_scan_sequences import write_pcd


def read_sweeps(source):
    """A folder of PCD sweeps of their own counts: (take, the frames' file names, frame offsets,
    x y z as (points, 3) float64). Also tools/move_sweeps.py's."""
    take = capz.read(source)
    if not take.ragged:
        raise SystemExit(f"{source}: not a folder of sweeps of their own counts")
    names = sorted(n for n in os.listdir(source) if n.lower().endswith(".pcd"))
    offsets = np.asarray(take.frame_offsets)
    if len(names) != len(offsets) - 1:
        raise SystemExit(f"{source}: {len(names)} PCD files, {len(offsets) - 1} frames")
    return take, names, offsets, np.asarray(take.xyz, dtype=np.float64).reshape(-1, 3)


def write_xyz(path, p):
    """Points p ((n, 3)) as a binary PCD of x y z float32."""
    q = np.asarray(p, dtype=np.float32)
    write_pcd(path, len(q), 1, [("x", "F", 4, 1), ("y", "F", 4, 1), ("z", "F", 4, 1)],
              [q[:, 0], q[:, 1], q[:, 2]])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("source")
    ap.add_argument("out")
    ap.add_argument("--degrees", type=float, default=1.2)
    a = ap.parse_args()
    _, names, offsets, xyz = read_sweeps(a.source)
    os.makedirs(a.out, exist_ok=True)
    for f, name in enumerate(names):
        p = xyz[offsets[f]:offsets[f + 1]]
        th = np.radians(a.degrees * f)
        c, s = np.cos(th), np.sin(th)
        turned = np.stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1], p[:, 2]], axis=1)
        write_xyz(os.path.join(a.out, name), turned)


if __name__ == "__main__":
    main()
