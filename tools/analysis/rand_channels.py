#!/usr/bin/env python3
"""Is a C3D take's analog block the output of C's rand()?
(analysis only, not part of capz; the findings are in docs/lab/2026-11-27-analog-misses.md)

    PYTHONPATH=build/python /usr/bin/python3 tools/analysis/rand_channels.py FILE.c3d ...

Reads each take with the capz package, maps every analog sample x (row-major: frame by frame,
channel by channel) to k = round(|x| * 32767), and tries two rand() generators of the form
state = a * state + c (mod 2^32), output (state >> 16) & 0x7FFF: Microsoft's (a = 214013,
c = 2531011) and the C standard's example (a = 1103515245, c = 12345). The state before the
first sample is found from the first outputs (its 17 hidden bits by brute force); the take's line
then says how many samples the generator gives back exactly, and how many of the float32
samples equal -float32(k / 32767).
"""
import sys

import numpy as np

from analog_takes import analog_takes

GENERATORS = {"msvc": (214013, 2531011), "ansi": (1103515245, 12345)}
MASK = (1 << 32) - 1


def first_state(k, a, c):
    """The 32-bit state whose output is k[0] and whose next outputs are k[1..7], or None."""
    if not 0 <= k[0] < 32768:
        return None
    low = np.arange(1 << 16, dtype=np.uint64)
    for top in (0, 1):
        s = np.uint64((top << 31) | (int(k[0]) << 16)) | low
        ok = np.ones(len(s), bool)
        st = s.copy()
        for j in range(1, min(len(k), 8)):
            st = (st * np.uint64(a) + np.uint64(c)) & np.uint64(MASK)
            ok &= ((st >> np.uint64(16)) & np.uint64(0x7FFF)) == np.uint64(int(k[j]) & MASK)
            if not ok.any():
                break
        if ok.any():
            return int(s[ok][0])
    return None


def outputs(state, a, c, n):
    out = np.empty(n, np.int64)
    for i in range(n):
        out[i] = (state >> 16) & 0x7FFF
        state = (state * a + c) & MASK
    return out


def main(paths):
    for path, analog in analog_takes(paths):
        x = analog.reshape(-1)
        k = np.round(np.abs(x) * 32767).astype(np.int64)
        for name, (a, c) in GENERATORS.items():
            s = first_state(k, a, c)
            if s is None:
                continue
            gen = outputs(s, a, c, x.size)
            back = (-(gen.astype(np.float32) / np.float32(32767))).astype(np.float64)
            print(f"{path}: {name} rand() from state {s:#010x}: {int((gen == k).sum())} of "
                  f"{x.size} samples' k, {int((back == x).sum())} samples exactly")
            break
        else:
            print(f"{path}: not rand() output")


if __name__ == "__main__":
    main(sys.argv[1:])
