"""Streams called from several threads: one call at a time on one object, each thread its own object
bit-identical to a serial run (issue: a second thread's call met the Rust object's borrow,
``RuntimeError: Already mutably borrowed``, naming nothing, or ran between the Rust call and the
Python bookkeeping of the first)."""

from __future__ import annotations

import copy
import pickle
import threading
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np
import pytest

import gyrocore
from gyrocore import fixes
from gyrocore import InUseError

IN_USE = r"is in use by another thread \(its {call} runs there\): a stream takes one call at a time"


class _Held:
    """Times whose conversion waits until released: the call that takes them holds its object's turn
    (in Python, before the core) as long as the test wants."""

    def __init__(self, t: np.ndarray) -> None:
        self.t, self.entered, self.release = t, threading.Event(), threading.Event()

    def __array__(self, dtype: Any = None, copy: bool | None = None) -> np.ndarray:
        self.entered.set()
        assert self.release.wait(30)
        return self.t


def _while_held(call: Callable[[_Held], object], held: _Held) -> threading.Thread:
    runner = threading.Thread(target=call, args=(held,))
    runner.start()
    assert held.entered.wait(30)
    return runner


def test_a_second_thread_on_one_pipeline_is_refused_naming_it_and_changes_nothing() -> None:
    t = np.arange(400) * 0.01
    rate = np.full(400, 0.001)
    p = gyrocore.Pipeline("hdr", bias=0.0)
    held = _Held(t[:200])
    runner = _while_held(lambda h: p.process(h, rate[:200]), held)
    try:
        for call in (lambda: p.process(t[200:], rate[200:]), lambda: p.last_time, lambda: p.params,
                     lambda: p.bias, lambda: p.report, p.reset, p.finish, lambda: pickle.dumps(p),
                     lambda: copy.copy(p), lambda: copy.deepcopy(p)):
            with pytest.raises(InUseError, match=r"^this gyrocore\.Pipeline \(preset 'hdr'\) "
                               + IN_USE.format(call=r"Pipeline\.process\(\)")):
                call()
        assert repr(p) == "Pipeline(preset='hdr', in use by another thread)"
    finally:
        held.release.set()
        runner.join()
    # the first call alone went through: the same state as a pipeline given only its chunk
    alone = gyrocore.Pipeline("hdr", bias=0.0)
    alone.process(t[:200], rate[:200])
    assert p.last_time == t[199]
    assert pickle.dumps(p) == pickle.dumps(alone)
    assert "params=" in repr(p)


def test_a_second_thread_on_one_fusion_is_refused_naming_it() -> None:
    t = np.arange(200) * 0.1
    f = fixes.Fusion()
    held = _Held(t)
    runner = _while_held(lambda h: f.process(h, np.zeros(200)), held)
    try:
        for call in (lambda: f.process(t + 100, np.zeros(200)), f.counts, f.settings, lambda: pickle.dumps(f)):
            with pytest.raises(InUseError, match=r"^this gyrocore\.fixes\.Fusion "
                               + IN_USE.format(call=r"Fusion\.process\(\)")):
                call()
    finally:
        held.release.set()
        runner.join()
    assert f.counts()["waiting"] == 0 and len(pickle.dumps(f))


def test_reading_a_pipeline_while_another_thread_runs_its_core_never_meets_the_borrow() -> None:
    # the core runs without the GIL; a read then met its borrow: RuntimeError('Already mutably borrowed')
    n = 4_000_000
    t = np.arange(n) * 0.01
    rate = np.full(n, 0.001)
    p = gyrocore.Pipeline("hdr", bias=0.0)
    runner = threading.Thread(target=lambda: p.process(t, rate, outputs=("heading",)))
    runner.start()
    refused = []
    while runner.is_alive():
        try:
            p.last_time
        except InUseError as e:
            refused.append(e)
    runner.join()
    assert refused and p.last_time == t[-1]


def test_each_thread_with_its_own_stream_gives_the_serial_result() -> None:
    drives = [gyrocore.sim.car_drive(duration=120.0, rate_hz=100.0, seed=s) for s in range(4)]

    def stream(d: Any) -> tuple[np.ndarray, np.ndarray]:
        p = gyrocore.Pipeline("tracked", bias_duration=10.0)
        f = fixes.Fusion()
        heading = [p.process(d.t[i:i + 997], d.rate_measured[i:i + 997]).heading for i in range(0, len(d.t), 997)]
        fused = [f.process(d.t[i:i + 997], d.rate_measured[i:i + 997], (d.t[i:i + 997:100], d.heading_true[i:i + 997:100],
                                                                             0.01)).heading
                 for i in range(0, len(d.t), 997)]
        return np.concatenate(heading), np.concatenate(fused)

    serial = [stream(d) for d in drives]
    with ThreadPoolExecutor(4) as ex:
        parallel = list(ex.map(stream, drives))
    for (a, b), (c, d) in zip(serial, parallel):
        assert np.array_equal(a, c) and np.array_equal(b, d)


def test_a_copy_is_a_stream_of_its_own() -> None:
    t = np.arange(600) * 0.01
    rate = 0.001 + 0.01 * np.sin(t)
    whole = gyrocore.Pipeline("tracked", bias_duration=1.0).process(t, rate).heading
    p = gyrocore.Pipeline("tracked", bias_duration=1.0)
    p.process(t[:300], rate[:300])
    for twin in (copy.copy(p), copy.deepcopy(p), pickle.loads(pickle.dumps(p))):
        assert np.array_equal(twin.process(t[300:], rate[300:]).heading, whole[300:])
        assert p.last_time == t[299]  # the original did not move
