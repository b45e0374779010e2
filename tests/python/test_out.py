"""``out=`` of gyrocore.process and Pipeline.process: the caller's arrays are filled, bit for bit
with what fresh arrays get, and returned; a bad array is refused before anything is processed,
with an error naming it."""

from __future__ import annotations

from typing import Any, Callable

import numpy as np
import pytest

import gyrocore
from gyrocore import _gyrocore
from gyrocore.fixes import Fixes

OUTPUT_SETS = [("heading",), ("heading", "rate"), ("drift", "heading"), ("heading", "rate", "drift")]


def _log(n: int = 6000, seed: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """A drive with a rest at the start, so that whole mode finds one when given no bias."""
    rng = np.random.default_rng(seed)
    t = 100.0 + np.arange(n) * 0.01
    moving = t > 115.0
    rate = 0.004 + moving * 0.3 * np.sin(t / 5.0) + rng.normal(0.0, 0.003, n)
    return t, rate


def _bits(a: np.ndarray | None) -> np.ndarray | None:
    return None if a is None else a.view(np.uint64)


def _same(a: gyrocore.HeadingResult, b: gyrocore.HeadingResult) -> None:
    for name in ("heading", "rate", "drift", "heading_sigma"):
        x, y = getattr(a, name), getattr(b, name)
        assert (x is None) == (y is None), name
        if x is not None:
            np.testing.assert_array_equal(_bits(x), _bits(y), err_msg=name)


def _garbage(n: int, k: int) -> list[np.ndarray]:
    """Arrays already holding values (NaN), so that a sample left unwritten would show."""
    return [np.full(n, np.nan) for _ in range(k)]


@pytest.mark.parametrize("outputs", OUTPUT_SETS)
@pytest.mark.parametrize(
    "preset, options",
    [
        ("raw", {}),
        ("hdr", {"bias": 0.004}),
        ("combined", {"bias": 0.004}),
        ("combined", {"bias_duration": 10.0}),
        ("combined", {}),  # whole mode: the bias from the rest it finds
        ("recommended", {"bias_window": (100.0, 110.0)}),
        ("combined", {"bias_duration": 10.0, "mode": "causal"}),
    ],
)
def test_out_arrays_are_filled_bit_for_bit_and_returned(
    outputs: tuple[str, ...], preset: str, options: dict[str, Any]
) -> None:
    t, rate = _log()
    fresh = gyrocore.process(t, rate, preset, outputs=outputs, **options)
    arrays = _garbage(len(t), len(outputs))
    given = gyrocore.process(t, rate, preset, outputs=outputs, out=tuple(arrays), **options)
    _same(given, fresh)
    for name, a in zip(outputs, arrays):
        assert given.output(name) is a, name
    assert given.bias_source == fresh.bias_source


def test_one_array_for_the_heading_alone() -> None:
    t, rate = _log()
    heading = np.empty(len(t))
    r = gyrocore.process(t, rate, "combined", bias=0.004, outputs=("heading",), out=heading)
    assert r.heading is heading and r.rate is None and r.drift is None
    fresh = gyrocore.process(t, rate, "combined", bias=0.004, outputs=("heading",))
    np.testing.assert_array_equal(_bits(heading), _bits(fresh.heading))


@pytest.mark.parametrize("options", [{"bias": 0.004}, {}, {"bias_duration": 10.0, "mode": "causal"}])
def test_with_out_the_result_holds_the_callers_times_read_only(options: dict[str, Any]) -> None:
    # nothing allocated per call: a copy of the times was a quarter of a call on 10^7 samples
    t, rate = _log()
    t_given = t.copy()
    r = gyrocore.process(t, rate, "combined", outputs=("heading",), out=np.empty(len(t)), **options)
    assert np.shares_memory(r.t, t) and not r.t.flags.writeable
    with pytest.raises(ValueError, match="read-only"):
        r.t[:] = r.t - r.t[0]  # a write through the result never reaches the caller's times
    np.testing.assert_array_equal(t, t_given)
    assert t.flags.writeable  # the caller's own array stays writeable
    # without out=, the result's times are its own, as ever
    assert not np.shares_memory(gyrocore.process(t, rate, "combined", outputs=("heading",), **options).t, t)


def test_a_stream_reuses_its_arrays_chunk_after_chunk() -> None:
    t, rate = _log()
    whole = gyrocore.Pipeline("combined", bias_duration=10.0).process(t, rate)
    stream = gyrocore.Pipeline("combined", bias_duration=10.0)
    size = 1000
    arrays = _garbage(size, 3)
    parts: list[list[np.ndarray]] = [[], [], []]
    for start in range(0, len(t), size):
        chunk = slice(start, start + size)
        r = stream.process(t[chunk], rate[chunk], index_offset=start, out=tuple(arrays))
        assert r.heading is arrays[0] and r.rate is arrays[1] and r.drift is arrays[2]
        for kept, a in zip(parts, arrays):
            kept.append(a.copy())
    for name, kept in zip(("heading", "rate", "drift"), parts):
        np.testing.assert_array_equal(_bits(np.concatenate(kept)), _bits(whole.output(name)), err_msg=name)


def _fixes(t: np.ndarray) -> Fixes:
    keep = np.arange(0, len(t), 200)
    return Fixes(t[keep], np.zeros(len(keep)), np.full(len(keep), 0.05))


@pytest.mark.parametrize("mode", ["whole", "causal"])
@pytest.mark.parametrize("outputs", [("heading",), ("heading", "drift"), ("heading", "rate", "drift"),
                                     ("heading", "heading_sigma"), ("heading", "rate", "fusion_bias", "fusion_scale")])
def test_out_with_heading_fixes(mode: str, outputs: tuple[str, ...]) -> None:
    """out= fills the pipeline's outputs asked for; the fix stage's columns asked for come fresh."""
    t, rate = _log()
    fixes = _fixes(t)
    fresh = gyrocore.process(t, rate, "hdr", bias=0.004, fixes=fixes, mode=mode, outputs=outputs)
    filled = [o for o in outputs if o in ("heading", "rate", "drift")]
    arrays = _garbage(len(t), len(filled))
    given = gyrocore.process(t, rate, "hdr", bias=0.004, fixes=fixes, mode=mode, outputs=outputs, out=tuple(arrays))
    _same(given, fresh)
    assert given.fusion is not None
    assert fresh.fusion is not None
    if "fusion_bias" in outputs:
        assert given.fusion.bias is not None and fresh.fusion.bias is not None
        np.testing.assert_array_equal(_bits(given.fusion.bias), _bits(fresh.fusion.bias))
    else:
        assert given.fusion.bias is None
    for name, a in zip(filled, arrays):
        assert given.output(name) is a, name
    assert (given.heading_sigma is None) == ("heading_sigma" not in outputs)


Call = Callable[..., gyrocore.HeadingResult]
ENTRIES: dict[str, Call] = {
    "process": lambda t, rate, **kw: gyrocore.process(t, rate, "combined", bias_duration=10.0, **kw),
    "process causal": lambda t, rate, **kw: gyrocore.process(t, rate, "combined", bias=0.004, mode="causal", **kw),
    "Pipeline.process": lambda t, rate, **kw: gyrocore.Pipeline("combined", bias=0.004).process(t, rate, **kw),
}


def _bad_outs(t: np.ndarray) -> list[tuple[dict[str, Any], type[Exception], str]]:
    n = len(t)
    read_only = np.empty(n)
    read_only.flags.writeable = False
    two = np.empty(2 * n)
    return [
        ({"out": (np.empty(n),)}, ValueError, r"out gives 1 array\(s\) for the 3 output\(s\)"),
        ({"out": np.empty(n)}, ValueError, r"out gives 1 array\(s\) for the 3 output\(s\)"),
        ({"outputs": ("heading",), "out": (np.empty(n), np.empty(n))}, ValueError, r"out gives 2 array\(s\)"),
        ({"outputs": ("heading",), "out": 3.0}, TypeError, "out must be a float64 array, or a tuple"),
        ({"outputs": ("heading",), "out": [list(range(n))]}, TypeError, r"out\[0\] \(heading\) must be a numpy"),
        ({"outputs": ("heading",), "out": np.empty(n, np.float32)}, TypeError, r"out \(heading\) holds float32"),
        ({"outputs": ("heading",), "out": np.empty(n - 1)}, ValueError, rf"out \(heading\) has shape \({n - 1},\)"),
        ({"outputs": ("heading",), "out": np.empty((n, 1))}, ValueError, r"out \(heading\) has shape"),
        ({"outputs": ("heading",), "out": two[::2]}, ValueError, r"out \(heading\) is not C-contiguous"),
        ({"outputs": ("heading",), "out": read_only}, ValueError, r"out \(heading\) is read-only"),
        ({"outputs": ("heading", "rate"), "out": (two[:n], two[n - 1 : 2 * n - 1])}, ValueError,
         r"out\[1\] \(rate\) shares memory with out\[0\] \(heading\)"),
        ({"outputs": ("heading", "heading"), "out": (np.empty(n), np.empty(n))}, ValueError, "names an output twice"),
        ({"outputs": ("rate",), "out": np.empty(n)}, ValueError, "outputs="),
    ]


@pytest.mark.parametrize("entry", ENTRIES)
def test_bad_out_arrays_are_refused_by_name_before_anything_is_processed(entry: str) -> None:
    t, rate = _log(500)
    for kwargs, error, message in _bad_outs(t):
        with pytest.raises(error, match=message):
            ENTRIES[entry](t, rate, **kwargs)


@pytest.mark.parametrize("entry", ENTRIES)
def test_an_out_array_sharing_memory_with_an_input_is_refused(entry: str) -> None:
    t, rate = _log(500)
    n = len(t)
    both = np.concatenate([rate, np.zeros(n)])
    kept = both.copy()
    with pytest.raises(ValueError, match=r"out \(heading\) shares memory with the input rate"):
        ENTRIES[entry](t, both[:n], outputs=("heading",), out=both[:n])
    with pytest.raises(ValueError, match=r"out\[2\] \(drift\) shares memory with the input t"):
        ENTRIES[entry](t, rate, out=(np.empty(n), np.empty(n), t))
    # a strided input the core reads as a copy: the caller's own array is still protected
    strided = np.zeros(2 * n)
    strided[::2] = rate
    with pytest.raises(ValueError, match=r"out \(heading\) shares memory with the input rate"):
        ENTRIES[entry](t, strided[::2], outputs=("heading",), out=strided[:n])
    np.testing.assert_array_equal(both, kept)


def test_a_refused_out_leaves_the_stream_where_it_was() -> None:
    t, rate = _log(500)
    p = gyrocore.Pipeline("combined", bias=0.004)
    read_only = np.empty(len(t))
    read_only.flags.writeable = False
    with pytest.raises(ValueError, match="read-only"):
        p.process(t, rate, outputs=("heading",), out=read_only)
    # the same samples again are not "not increasing": none of them was taken
    again = p.process(t, rate, outputs=("heading",))
    fresh = gyrocore.Pipeline("combined", bias=0.004).process(t, rate, outputs=("heading",))
    np.testing.assert_array_equal(_bits(again.heading), _bits(fresh.heading))


def test_the_extensions_own_checks_name_the_array() -> None:
    """The binding checks what it is given too (for callers of gyrocore._gyrocore)."""
    t, rate = _log(100)
    n = len(t)
    read_only = np.empty(n)
    read_only.flags.writeable = False
    two = np.empty(2 * n)
    cases: list[tuple[tuple[bool, bool], tuple[Any, Any, Any], str]] = [
        ((False, False), (np.empty(n - 1), None, None), r"out\[0\] \(heading\) has 99 elements but t has 100"),
        ((False, False), (two[::2], None, None), r"out\[0\] \(heading\) is not C-contiguous"),
        ((False, False), (None, np.empty(n), None), r"out\[1\] \(rate\) is given, but that output is not asked"),
        ((False, False), (read_only, None, None), r"out\[0\] \(heading\) is read-only"),
        ((False, False), (rate, None, None), r"out\[0\] \(heading\) overlaps an input or another output"),
        ((False, True), (two[:n], None, two[n - 1 : 2 * n - 1]), r"out\[2\] \(drift\) overlaps an input"),
    ]
    for flags, out, message in cases:
        p = _gyrocore.Pipeline("combined", {"bias": 0.004})
        with pytest.raises(ValueError, match=message):
            p.process(t, rate, None, 0, flags, None, None, out)
        assert p.last_time() is None
