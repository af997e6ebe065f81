#!/usr/bin/env python3
"""How much mains hum is left in the residuals of a take's integer analog channels?
(analysis only, not part of capz; the findings are in docs/lab/2026-11-27-analog-misses.md)

    PYTHONPATH=build/python /usr/bin/python3 tools/analysis/mains_hum.py FILE.c3d ...

For each integer channel (or float channel on a lattice) of at least 1000 samples: the
residuals of a whole-channel least-squares predictor of order 8 (tools/analysis/cross_magnitude.py), and
their correlation rho with themselves one, two and three mains periods back (50 and 60 Hz at
ANALOG:RATE, lags rounded down and up). A long-term predictor at the best lag would save at
most 0.5 log2(1 / (1 - rho^2)) bits a sample (Gaussian residuals): printed per take in bytes,
with the channels whose |rho| is above 0.1.
"""
import sys

import numpy as np

import capz
from analog_takes import analog_takes, lattice_channels
from cross_magnitude import residuals


def main(paths):
    for path, analog in analog_takes(paths):
        rate = capz.read(path).analog_rate
        saved, strong, channels = 0.0, [], 0
        for c, k, _ in lattice_channels(analog, 8):
            r = residuals(k).astype(np.float64)
            n = len(r)
            if n < 1000 or rate <= 0:
                continue
            channels += 1
            best_rho, best_lag = 0.0, 0
            for hz in (50.0, 60.0):
                period = rate / hz
                for lag in sorted({int(np.floor(m * period)) for m in (1, 2, 3)} |
                                  {int(np.ceil(m * period)) for m in (1, 2, 3)}):
                    if lag < 1 or lag >= n // 4:
                        continue
                    x, y = r[:-lag], r[lag:]
                    rho = float(np.dot(x, y) / np.sqrt(np.dot(x, x) * np.dot(y, y) + 1e-12))
                    if abs(rho) > abs(best_rho):
                        best_rho, best_lag = rho, lag
            saved += 0.5 * np.log2(1 / (1 - best_rho * best_rho)) * n / 8
            if abs(best_rho) > 0.1:
                strong.append(f"{c}:{best_rho:.2f}@{best_lag}")
        print(f"{path}: {channels} channels at {rate:g} Hz, at most {saved:.0f} B saved; "
              f"|rho| > 0.1: {' '.join(strong) or 'none'}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
