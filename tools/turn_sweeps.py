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


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("source")
    ap.add_argument("out")
    ap.add_argument("--degrees", type=float, default=1.2)
    a = ap.parse_args()
    take = capz.read(a.source)
    if not take.ragged:
        raise SystemExit(f"{a.source}: not a folder of sweeps of their own counts")
    names = sorted(n for n in os.listdir(a.source) if n.lower().endswith(".pcd"))
    offsets = np.asarray(take.frame_offsets)
    xyz = np.asarray(take.xyz, dtype=np.float64).reshape(-1, 3)
    if len(names) != len(offsets) - 1:
        raise SystemExit(f"{a.source}: {len(names)} PCD files, {len(offsets) - 1} frames")
    os.makedirs(a.out, exist_ok=True)
    fields = [("x", "F", 4, 1), ("y", "F", 4, 1), ("z", "F", 4, 1)]
    for f, name in enumerate(names):
        p = xyz[offsets[f]:offsets[f + 1]]
        th = np.radians(a.degrees * f)
        c, s = np.cos(th), np.sin(th)
        x = (c * p[:, 0] - s * p[:, 1]).astype(np.float32)
        y = (s * p[:, 0] + c * p[:, 1]).astype(np.float32)
        write_pcd(os.path.join(a.out, name), len(p), 1, fields, [x, y, p[:, 2].astype(np.float32)])


if __name__ == "__main__":
    main()
