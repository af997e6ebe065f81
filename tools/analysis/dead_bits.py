#!/usr/bin/env python3
"""Which bits never change in the magnitude of a take's integer analog samples?
(analysis only, not part of capz; the findings are in docs/lab/2026-11-27-analog-misses.md)

    PYTHONPATH=build/python /usr/bin/python3 tools/analysis/dead_bits.py [--squeeze] FILE.c3d ...

For each finite channel of integers, or of floats on a lattice k s (analog_takes.lattice_ints),
with 8 or more distinct values: m = k for k >= 0, else -k - 1 (the ones' complement magnitude,
so that -1 and 0 are alike). A bit is dead when every sample has the same value there, some bit
below it changes (the lowest bits that never change are FLAC's "wasted bits", which a step
removes), and it lies below the highest bit of the samples' range (the bits above it that never
change are an offset's, which prediction removes). A line names each channel with a dead bit.

--squeeze: also compresses the take (capz's defaults) as it is and with the dead bits squeezed
out of those channels' k (the channel then holds float32(k' s), k' the magnitude without them,
with k's sign), both through capz.Take.from_arrays so that only the analog differs, and prints
the two sizes.
"""
import sys

import numpy as np

import capz
from analog_takes import analog_takes, lattice_channels


def dead_bits(k):
    """The dead bits of k (ints) as a list of bit numbers, and the ones' complement magnitude."""
    m = np.where(k >= 0, k, -k - 1)
    any_set = int(np.bitwise_or.reduce(m))
    all_set = int(np.bitwise_and.reduce(m))
    live = any_set & ~all_set
    if live == 0:
        return [], m
    lowest = (live & -live).bit_length() - 1
    span = int(m.max() - m.min()).bit_length() - 1
    return [b for b in range(lowest + 1, span) if not (live >> b) & 1], m


def squeezed(k, m, dead):
    """k with the dead bits taken out of its magnitude (kept bits moved down), sign kept."""
    keep = [b for b in range(int(m.max()).bit_length()) if b not in dead]
    out = np.zeros_like(m)
    for i, b in enumerate(keep):
        out |= ((m >> b) & 1) << i
    return np.where(k >= 0, out, -out - 1)


def main(argv):
    squeeze = "--squeeze" in argv
    paths = [a for a in argv if a != "--squeeze"]
    for path, a in analog_takes(paths):
        b = a.copy()
        found = []
        for c, k, step in lattice_channels(a, 8):
            dead, m = dead_bits(k)
            if not dead:
                continue
            found.append((c, dead))
            b[:, c] = (squeezed(k, m, dead) * step).astype(np.float32)
        if not found:
            continue
        print(f"{path}: " + ", ".join(f"channel {c} bits {d}" for c, d in found))
        if squeeze:
            t = capz.read(path)

            def take_with(analog):
                return capz.Take.from_arrays(np.asarray(t.xyz), np.asarray(t.valid), t.rate,
                                             t.units, list(t.labels), t.first_frame, analog,
                                             t.analog_rate, list(t.analog_labels))

            print(f"  compressed: {len(capz.compress(take_with(a)))} B as it is, "
                  f"{len(capz.compress(take_with(b)))} B squeezed")


if __name__ == "__main__":
    main(sys.argv[1:])
