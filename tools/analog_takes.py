"""The analog samples of the takes given to tools/rand_channels.py and tools/code_density.py
(analysis only, not part of capz)."""
import numpy as np

import capz


def analog_takes(paths):
    """Yields (path, analog) for each path capz reads that has analog samples: analog is float64,
    (frames x samples per frame, channels). Prints one line for each other path and goes on."""
    for path in paths:
        try:
            take = capz.read(path)
        except capz.Error as e:
            print(f"{path}: not read ({e})")
            continue
        analog = np.asarray(take.analog, dtype=np.float64)
        if analog.size == 0:
            print(f"{path}: no analog samples")
            continue
        yield path, analog
