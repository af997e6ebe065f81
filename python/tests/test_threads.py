"""Separate takes coded from several threads at once give what one thread gives."""
import threading
import time

import numpy as np

import capz
from conftest import synthetic_xyz


def test_two_threads_compressing_at_once():
    takes = [capz.Take.from_arrays(synthetic_xyz(frames=3000, points=40, seed=s)) for s in (1, 2)]
    serial = [capz.compress(t, max_error="0.1mm") for t in takes]
    results = [None, None]
    errors = []
    barrier = threading.Barrier(2)

    def work(i):
        try:
            barrier.wait()
            for _ in range(3):
                data = capz.compress(takes[i], max_error="0.1mm")
                assert data == serial[i]
                back = capz.decompress(data)
                np.testing.assert_array_equal(back.valid, takes[i].valid)
            results[i] = data
        except Exception as e:  # reported below: a thread's assertion does not fail the test
            errors.append(e)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    assert results == serial


def test_gil_is_released_while_coding():
    # A Python thread keeps running while another thread compresses: the longest pause between
    # its steps stays far below the compression's time. With the GIL held through the call it
    # would be the whole call. The take grows until one call takes long enough to tell.
    frames = 8000
    while True:
        take = capz.Take.from_arrays(synthetic_xyz(frames=frames, points=60, seed=5))
        t0 = time.perf_counter()
        capz.compress(take, max_error="0.1mm")
        if time.perf_counter() - t0 > 0.15 or frames >= 128000:
            break
        frames *= 2
    done = threading.Event()
    pauses = []

    def counter():
        last, longest = time.perf_counter(), 0.0
        while not done.is_set():
            now = time.perf_counter()
            longest, last = max(longest, now - last), now
        pauses.append(longest)

    c = threading.Thread(target=counter)
    c.start()
    t0 = time.perf_counter()
    capz.compress(take, max_error="0.1mm")
    took = time.perf_counter() - t0
    done.set()
    c.join()
    assert took > 0.1, "the take is too small to tell"
    assert pauses[0] < 0.5 * took, (pauses[0], took)
