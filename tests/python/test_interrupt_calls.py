"""Ctrl-C during a long call of the core from Python (issue: the core runs without the GIL, and Python
runs its signal handlers only between bytecodes: a pipeline of 10^8 samples went on 3.5 s after
Ctrl-C, a modified Allan deviation of them 28 s), and the stream as before the call afterwards."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

# Runs CALL (a stream's twice: the first gives the whole result), with SIGINT sent to itself once its
# main thread is in the call of the core; prints how long after the signal KeyboardInterrupt came and
# whether the stream (a pipeline, a fix filter) is then as before the call.
_SCRIPT = textwrap.dedent(r"""
    import json, linecache, os, pickle, re, signal, sys, threading, time, warnings
    import numpy as np, gyrocore
    from gyrocore import _checks, _gyrocore, fixes, sim

    warnings.simplefilter("ignore")
    # Python's own Ctrl-C, also where the runner was started in the background (a shell without
    # job control starts it with SIGINT ignored, which the child inherits: no signal came)
    signal.signal(signal.SIGINT, signal.default_int_handler)
    n = int(sys.argv[2])
    t = np.arange(n) * 0.01
    rate = 0.001 + 0.001 * np.random.default_rng(0).standard_normal(n)
    fixed = (t[1500::1000], np.zeros(len(t[1500::1000])), 0.01)
    stream = {"pipeline": gyrocore.Pipeline("hdr", bias=0.0), "fusion": fixes.Fusion()}.get(sys.argv[1])
    if stream is not None:
        stream.process(t[:1000], rate[:1000])
        before = pickle.dumps(stream)
    calls = {
        "pipeline": lambda: stream.process(t[1000:], rate[1000:], outputs=("heading",)),
        "fusion": lambda: stream.process(t[1000:], rate[1000:], fixed),
        "allan": lambda: gyrocore.allan.deviation(rate, 0.01, kind="modified", taus="log"),
        "smoothed": lambda: fixes.fuse(t, rate, fixed, mode="smoothed"),
        "integrate": lambda: gyrocore.integrate(t, rate),
        "downsample": lambda: gyrocore.downsample(t, rate, 1.0),
        "check": lambda: _checks.require_times(t),
        "project_up": lambda: _gyrocore.project_up(rate, rate, rate, [0.0, 0.0, 1.0]),
        "measure": lambda: sim.measure(sim.sensor("xv3500"), t, rate, seed=1),
        "sample_times": lambda: sim.sample_times(sim.GyroSpec(jitter_s=1e-4), 0.0, n / 100, seed=1),
        "csv": lambda: _gyrocore.format_csv_rows([t, rate]),
        "static_bias": lambda: _gyrocore.static_bias_test(t, rate, 0.0, t[-1]),
        # one long averaging time: the modified variance's blocks are then the whole record
        "allan_long": lambda: gyrocore.allan.deviation(rate, 0.01, kind="modified", taus=[2**18 * 0.01]),
    }
    call = calls[sys.argv[1]]
    if stream is not None:
        whole = call()
        stream = pickle.loads(before)
    durations = []  # the whole call, timed where asked: the better of two
    for _ in range(2 if len(sys.argv) > 3 else 0):
        started = time.perf_counter()
        call()
        durations.append(time.perf_counter() - started)
    direct = call.__code__ if sys.argv[1] in ("project_up", "csv", "static_bias") else None
    main, sent = threading.main_thread().ident, []
    core = re.compile(r"_gyrocore\.\w+\(|inner\.process\(")

    def interrupt():
        # once the main thread's innermost frame is the line that calls the core
        while True:
            frame = sys._current_frames()[main]
            # the package's call of the core, or this script's own (a call of _gyrocore itself)
            if "gyrocore" in frame.f_code.co_filename and core.search(
                    linecache.getline(frame.f_code.co_filename, frame.f_lineno)) or frame.f_code is direct:
                break
            time.sleep(0.0005)
        time.sleep(0.05)  # well inside
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    threading.Thread(target=interrupt, daemon=True).start()
    try:
        call()
        print(json.dumps({"latency": None}))
    except KeyboardInterrupt:
        latency = time.perf_counter() - sent[-1]
        same = None
        if stream is not None:
            same = pickle.dumps(stream) == before and np.array_equal(call().heading, whole.heading)
        print(json.dumps({"latency": latency, "same": same, "whole": min(durations, default=None)}))
""")


# each long enough for about a second in the core (a 2-core Xeon shared with other work)
@pytest.mark.parametrize(("call", "n"), [("pipeline", 50_000_000), ("fusion", 10_000_000), ("allan", 5_000_000),
                                         ("smoothed", 10_000_000)])
def test_ctrl_c_stops_a_long_call_of_the_core_within_a_poll(call: str, n: int) -> None:
    run = subprocess.run([sys.executable, "-c", _SCRIPT, call, str(n)], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    assert got["latency"] is not None, got  # the call was interrupted
    # most of the core's second was left when the signal came: it stopped within a poll (20 ms)
    # and a piece (before, at the call's end)
    assert got["latency"] < 0.25, got
    if call in ("pipeline", "fusion"):
        assert got["same"], got  # as before the call, pickle for pickle; then the same heading


# Calls of the core that ran to their end after a Ctrl-C (check held the GIL, so the signal was not
# even handled until it returned; allan_long summed a block as long as the record between looks), each
# long enough for a second or so here
@pytest.mark.parametrize(("call", "n"), [("integrate", 100_000_000), ("downsample", 50_000_000),
                                         ("check", 100_000_000), ("project_up", 100_000_000),
                                         ("measure", 10_000_000), ("sample_times", 30_000_000),
                                         ("csv", 10_000_000), ("static_bias", 100_000_000),
                                         ("allan_long", 20_000_000)])
def test_ctrl_c_stops_every_long_call_of_the_core_with_most_of_it_left(call: str, n: int) -> None:
    run = subprocess.run([sys.executable, "-c", _SCRIPT, call, str(n), "timed"], capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    assert got["latency"] is not None, got  # the call was interrupted
    # within a poll (20 ms) and a piece, and well before the call would have ended: on a fast
    # machine the whole call lasts a few tenths of a second, and the signal comes 0.05 s in
    assert got["latency"] < min(0.25, got["whole"] / 4), got


# A long block goes through the core piece by piece (65536 samples), so that a Ctrl-C is looked for
# between pieces: still one block to the caller, as its errors and the state after one say.
_LONG = 300_000


def test_a_long_block_refused_in_a_later_piece_names_its_sample_and_changes_nothing() -> None:
    import pickle

    import numpy as np

    import gyrocore

    t = np.arange(_LONG) * 0.01
    rate = np.full(_LONG, 0.001)
    rate[200_003] = np.nan
    p = gyrocore.Pipeline("tracked", bias_duration=5.0)
    p.process(t[:10] - 1.0, rate[:10])
    before = pickle.dumps(p)
    with pytest.raises(gyrocore.SampleError, match=r"rate\[200013\] is NaN") as e:
        p.process(t, rate, index_offset=10)
    assert e.value.index == 200_013
    assert pickle.dumps(p) == before


@pytest.mark.filterwarnings("ignore::gyrocore.InputWarning")  # a gate that re-admits: not the point here
def test_a_long_fused_block_is_the_stream_of_its_pieces_and_a_late_bad_fix_changes_nothing() -> None:
    import pickle

    import numpy as np

    import gyrocore

    t = np.arange(_LONG) * 0.01
    rate = 0.002 + 0.01 * np.sin(t / 50)
    fix_t = t[50::1000]
    fixes = (fix_t, 0.2 * np.sin(fix_t / 50), np.full(len(fix_t), 0.02))
    whole = gyrocore.Pipeline("hdr", bias=0.0, fusion={}).process(t, rate, fixes=fixes)
    streamed = gyrocore.Pipeline("hdr", bias=0.0, fusion={})
    cuts = [0, 7, 70_001, 150_000, _LONG]
    parts = [streamed.process(t[a:b], rate[a:b], fixes=tuple(f[(fix_t >= t[a]) & (fix_t <= t[b - 1])] for f in fixes))
             for a, b in zip(cuts, cuts[1:])]
    assert np.array_equal(whole.heading, np.concatenate([r.heading for r in parts]))
    assert np.array_equal(whole.heading_sigma, np.concatenate([r.heading_sigma for r in parts]))
    bad = tuple(np.array(f, copy=True) for f in fixes)
    bad[2][250] = -1.0  # the fix at t = 2500.5 s, in the block's fourth piece
    p = gyrocore.Pipeline("hdr", bias=0.0, fusion={})
    p.process(t[:2] - 1.0, rate[:2])
    before = pickle.dumps(p)
    with pytest.raises(ValueError, match=r"^fix 250: sigma = -1 must be > 0"):
        p.process(t, rate, fixes=bad)
    assert pickle.dumps(p) == before


def test_a_first_chunk_refused_or_interrupted_leaves_the_pipeline_as_before(monkeypatch: pytest.MonkeyPatch) -> None:
    # the unit check of the first chunk was done before the core refused it, or a Ctrl-C stopped it:
    # the pickle differed from the one before, and the chunk sent again was not judged
    import pickle

    import numpy as np

    import gyrocore

    t = np.arange(100) * 0.01
    rate = np.full(100, 0.001)
    bad = rate.copy()
    bad[50] = np.nan
    p = gyrocore.Pipeline("hdr", bias=0.0)
    before = pickle.dumps(p)
    with pytest.raises(gyrocore.SampleError, match=r"rate\[50\] is NaN"):
        p.process(t, bad)
    assert pickle.dumps(p) == before

    def interrupted(*args: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(gyrocore.Pipeline, "_run", interrupted)
    with pytest.raises(KeyboardInterrupt):
        p.process(t * 1000, rate)  # in ms: judged, and warned of, once the chunk is taken
    assert pickle.dumps(p) == before
    monkeypatch.undo()
    with pytest.warns(gyrocore.InputWarning, match="timestamps look like ms"):
        p.process(t * 1000, rate)


def test_a_long_block_is_checked_piece_by_piece_as_a_pipeline_checks_it() -> None:
    # the checks named a bad reading anywhere in the block before a bad time earlier in it, where a
    # pipeline, which checks a long block piece by piece, named the time
    import numpy as np

    import gyrocore
    from gyrocore import _gyrocore

    t = np.arange(_LONG) * 0.01
    rate = np.full(_LONG, 0.001)
    t[1000] = t[999]
    rate[250_000] = np.nan
    with pytest.raises(gyrocore.SampleError, match=r"t\[1000\] = ") as checked:
        _gyrocore.check_samples(t, rate)
    with pytest.raises(gyrocore.SampleError) as processed:
        gyrocore.Pipeline("raw").process(t, rate)
    assert (checked.value.index, checked.value.what) == (processed.value.index, processed.value.what) == (1000, "t")
