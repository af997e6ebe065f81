#!/usr/bin/env python3
"""Writes data/repeat_analog.c3d: a small synthetic C3D whose analog channels repeat whole analog
frames, as a wireless device does when a packet comes late (issue #13, docs/FORMAT.md 11.3).

12 markers x 80 frames at 100 Hz (a ring turning and bobbing, mm, float32 storage, no gaps) and
6 analog channels at 1000 Hz (10 samples a point frame), written by capz's own C3D writer through
the Python module (capz.Take.from_arrays, capz.write):
  - FX FY FZ: force-like integer counts (a slow sine, seeded noise); frames 1 .. 79 repeat the
    previous frame's 10 samples with probability 0.6, one set for all three;
  - EMG1 EMG2: float32 bursts of seeded noise; another set, probability 0.4;
  - SYNC: a float32 ramp with noise, never repeated.
Seeded (numpy default_rng(13)): running this again writes the same bytes. capz compresses the
file as format 7.0 (its channels have repeated frames that are not constant).

usage: PYTHONPATH=build/python /usr/bin/python3 data/make_repeat_analog.py [OUT.c3d]
"""
import os
import sys

import numpy as np

import capz

FRAMES, POINTS, S = 80, 12, 10


def ring(frames, points):
    """frames x points x 3 markers at 100 Hz: a ring turning and bobbing, mm, float32 values."""
    t = np.arange(frames)[:, None] / 100.0
    ang = 2 * np.pi * (np.arange(points)[None, :] / points + 0.3 * t)
    height = np.broadcast_to(900 + 40 * np.sin(7 * t), ang.shape)
    xyz = np.stack([300 * np.cos(ang), 300 * np.sin(ang), height], 2)
    return xyz.astype(np.float32).astype(np.float64)


def emg_burst(rng, ts):
    """One EMG-like channel at the times ts: seeded noise in bursts, float32 values."""
    burst = 0.5 + 0.5 * np.sin(9 * ts)
    return (burst * rng.normal(0, 0.2, len(ts))).astype(np.float32)


def write_take(out, xyz, analog, analog_rate, analog_labels):
    """Writes the markers (100 Hz, mm, labels M00 ..) and the analog channels to out as a C3D."""
    take = capz.Take.from_arrays(
        xyz, rate=100.0, units="mm", labels=["M%02d" % i for i in range(xyz.shape[1])],
        analog=analog, analog_rate=analog_rate, analog_labels=analog_labels)
    capz.write(take, out, overwrite=True)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "repeat_analog.c3d")
    rng = np.random.default_rng(13)
    xyz = ring(FRAMES, POINTS)

    n = FRAMES * S
    ts = np.arange(n) / 1000.0
    analog = np.zeros((n, 6))
    for c in range(3):
        analog[:, c] = np.round(800 * (c + 1) * np.sin(2.1 * ts + c) + rng.normal(0, 6, n))
    for c in (3, 4):
        analog[:, c] = emg_burst(rng, ts)
    analog[:, 5] = (ts + rng.normal(0, 1e-3, n)).astype(np.float32)

    def repeat(channels, p):
        for f in range(1, FRAMES):
            if rng.random() < p:
                analog[f * S:(f + 1) * S, channels] = analog[(f - 1) * S:f * S, channels]

    repeat([0, 1, 2], 0.6)
    repeat([3, 4], 0.4)
    write_take(out, xyz, analog, 1000.0, ["FX", "FY", "FZ", "EMG1", "EMG2", "SYNC"])


if __name__ == "__main__":
    main()
