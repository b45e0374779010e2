"""Long logs and large fleets: work and memory that grow with the log, not faster.

Each test counts memory (tracemalloc peaks) or compares the cost of two stretches of one run, with
margins far from what a defect gives, so that a busy machine does not fail them."""

from __future__ import annotations

import pickle
import time
import tracemalloc
import warnings

import numpy as np

import gyrocore
from gyrocore._motion import WATCHED, WindowWatch


def _stream_per_sample(p: gyrocore.Pipeline, t: np.ndarray, rate: np.ndarray) -> float:
    """Seconds to stream ``(t, rate)`` into ``p`` one sample a call, as a robot's loop does."""
    start = time.perf_counter()
    for i in range(len(t)):
        p.process(t[i:i + 1], rate[i:i + 1], outputs=("heading",))
    return time.perf_counter() - start


def test_a_long_rest_window_streamed_a_sample_a_call_costs_what_the_drive_after_it_costs() -> None:
    # A rest window of 12 s at 1 kHz, one sample a call: each call counted every chunk kept before
    # it (0.44 ms a call 20 s into the window, against 15 us after it: 108 s for an 80 s window)
    # and kept an array per sample (280 bytes a reading).
    hz, window, calls = 1000.0, 12.0, 3000
    inside = int(window * hz)
    n = inside + calls
    t = np.arange(n) / hz
    rate = 0.003 + np.random.default_rng(1).normal(0.0, 0.002, n)
    p = gyrocore.Pipeline("recommended", bias_duration=window)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)
        _stream_per_sample(p, t[:10], rate[:10])  # the unit check's first chunks
        tracemalloc.start()
        try:
            _stream_per_sample(p, t[10:inside - calls], rate[10:inside - calls])
            peak = tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()
        late = _stream_per_sample(p, t[inside - calls:inside], rate[inside - calls:inside])
        after = _stream_per_sample(p, t[inside:], rate[inside:])
    assert p.bias is not None
    # the window's last 3000 calls against the 3000 after it: 5 to 10 times as long with the count
    assert late < 3.0 * after, (late, after)
    # the window's readings, 8 bytes each, in a buffer that doubles, and a chunk's passing arrays
    assert peak < 64 * inside, peak / inside


def test_a_window_watch_keeps_its_readings_in_order_up_to_its_limit_and_through_a_pickle() -> None:
    watch = WindowWatch()
    t = np.arange(10.0)
    for i in range(10):
        watch.add((2.0, 6.0), t[i:i + 1], t[i:i + 1] * 0.1)
    assert watch.readings is not None
    kept = np.concatenate(watch.readings)
    assert np.array_equal(kept, t[2:7] * 0.1)
    again = pickle.loads(pickle.dumps(WindowWatch.restored(watch.readings)))
    assert again.readings is not None and np.array_equal(np.concatenate(again.readings), kept)
    # a pickle of the list of chunks an earlier version kept reads back as one
    old = WindowWatch.restored([np.array([1.0]), np.array([]), np.array([2.0, 3.0])])
    assert old.readings is not None and np.array_equal(np.concatenate(old.readings), [1.0, 2.0, 3.0])
    big = WindowWatch()
    big.add((0.0, np.inf), np.arange(WATCHED + 10.0), np.full(WATCHED + 10, 0.01))
    big.add((0.0, np.inf), np.arange(5.0), np.full(5, 0.01))
    assert big.readings is not None and len(np.concatenate(big.readings)) == WATCHED
    big.close((0.0, 1.0), 0.01)
    assert big.readings is None
