#!/usr/bin/env python3
"""Writes data/held_analog.c3d: a small synthetic C3D whose accelerometer channels were written
into the analog block by sample and hold from a slower sensor, as EMG systems with inertial
sensors do (c3d.org's EMG Data Cometa.c3d; issue #13, docs/FORMAT.md 11.5).

12 markers x 60 frames at 100 Hz (a ring turning and bobbing, mm, float32 storage, no gaps) and
5 analog channels at 2000 Hz (20 samples a point frame), written by capz's own C3D writer through
the Python module (capz.Take.from_arrays, capz.write):
  - EMG1 EMG2: float32 bursts of seeded noise;
  - ACCX ACCY ACCZ: a slow motion plus seeded noise on a 1/32 lattice (g), which changes only at
    the rows i with i mod 14 = 9 and is held in between; ACCY also leaves its held value for rows
    500-502, off that phase: two exceptions of the hold (rows 500 and 503).
Seeded (numpy default_rng(17)): running this again writes the same bytes. capz compresses the
file as format 9.2 with a hold field on the three accelerometer channels.

usage: PYTHONPATH=build/python /usr/bin/python3 data/make_held_analog.py [OUT.c3d]
"""
import os
import sys

import numpy as np

from make_repeat_analog import emg_burst, ring, write_take  # data/make_repeat_analog.py

FRAMES, POINTS, S, P, PHASE = 60, 12, 20, 14, 9


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "held_analog.c3d")
    rng = np.random.default_rng(17)
    xyz = ring(FRAMES, POINTS)

    n = FRAMES * S
    ts = np.arange(n) / 2000.0
    analog = np.zeros((n, 5))
    for c in (0, 1):
        analog[:, c] = emg_burst(rng, ts)
    rows = np.arange(n)
    anchor = np.maximum.accumulate(np.where((rows % P == PHASE) | (rows == 0), rows, 0))
    for c in (2, 3, 4):
        slow = np.sin(3 * ts + c) + rng.normal(0, 0.1, n)
        lattice = np.round(slow * 32) / 32
        analog[:, c] = lattice[anchor]
    analog[500:500 + 3, 3] += 1 / 32  # changes at rows 500 and 503, off the phase (mod 14: 10, 13)
    write_take(out, xyz, analog, 2000.0, ["EMG1", "EMG2", "ACCX", "ACCY", "ACCZ"])


if __name__ == "__main__":
    main()
