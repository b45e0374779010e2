"""The rest window must fit the log: an empty window is refused before its chunk changes anything,
and a window (or bias_duration) reaching past the log's end is an error naming both, through the
API, the command line and a log folder's meta.json."""

from __future__ import annotations

import json
import pickle
import re
import warnings
from functools import partial
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import Pipeline, RestWindowError

from . import conftest
from .test_batch import synthetic_csv

STEP = 0.1


def span(t0: float, t1: float) -> np.ndarray:
    return np.round(np.arange(t0, t1, STEP), 9)


def rate(t: np.ndarray) -> np.ndarray:
    return 0.01 + 0.2 * np.sin(t / 7.0)


@pytest.mark.filterwarnings("ignore:the rest window")  # its synthetic rate turns in the window
def test_a_chunk_that_closes_an_empty_window_changes_nothing() -> None:
    before_gap, after_gap, rest = span(0, 30), span(130, 160), span(30, 70)
    pipeline = Pipeline("hdr", bias_window=(50.0, 60.0))
    first = pipeline.process(before_gap, rate(before_gap))
    state = pickle.dumps(pipeline)
    for _ in range(2):  # sent again, it fails the same way, not as "timestamps must strictly increase"
        with pytest.raises(RestWindowError) as e:
            pipeline.process(after_gap, rate(after_gap))
        assert str(e.value).startswith(
            f"the bias window [50.0, 60.0] s holds no sample of the log, which jumps from t = {before_gap[-1]} "
            "to t = 130.0 s (index 0 of this chunk)"
        )
        assert pickle.dumps(pipeline) == state
    # the next valid chunk continues as if the rejected one had never been sent
    fresh = Pipeline("hdr", bias_window=(50.0, 60.0))
    fresh.process(before_gap, rate(before_gap))
    expected = fresh.process(rest, rate(rest))
    got = pipeline.process(rest, rate(rest))
    assert np.array_equal(got.heading, expected.heading) and np.array_equal(got.drift, expected.drift)
    assert pipeline.bias == fresh.bias != 0.0 and len(first) == len(before_gap)


@pytest.mark.parametrize("nonfinite", ["error", "hold", "skip"])
@pytest.mark.parametrize("window", [(4.95, 5.05), (5.0, 5.0), (5.05, 5.09), (4.0, 6.0), (-1.0, -0.5)])
def test_the_check_before_processing_agrees_with_the_core(nonfinite: str, window: tuple[float, float]) -> None:
    """Whatever the readings in the window (NaN ones are not measured under skip), a chunk is refused
    exactly when the core would have closed the window with no reading in it."""
    t = span(0, 10)
    for bad in ([], [50], list(range(40, 61))):  # no NaN, one at t = 5, all readings in [4, 6]
        r = rate(t)
        r[bad] = np.nan
        if nonfinite == "error" and bad:
            continue
        pipeline = Pipeline("hdr", bias_window=window, nonfinite=nonfinite)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", gyrocore.InputWarning)
            try:
                pipeline.process(t, r)
            except RestWindowError:
                refused = True
            else:
                refused = False
        _, count, learning = pipeline._inner.bias()
        if refused:
            assert pipeline._inner.last_time() is None  # nothing of the chunk went through
            probe = gyrocore._gyrocore.Pipeline("hdr", {"bias_window": window, "nonfinite": nonfinite})
            with pytest.raises(ValueError, match="holds no sample"):  # the core refuses it too
                probe.process(t, r, None, 0)
            assert probe.bias()[1:] == (0, True) and probe.last_time() is None, (window, bad)
        else:
            assert count > 0 or learning, (window, bad)


@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        (
            {"bias_window": (1000.0, 2000.0)},
            "the bias window [1000.0, 2000.0] s reaches past the end of the log (the log runs from 0 to 29.9 s ",
        ),
        ({"bias_window": (20.0, 40.0)}, "the bias window [20.0, 40.0] s reaches past the end of the log"),
        (
            {"bias_duration": 100.0},
            "bias_duration = 100.0 s is longer than the log (the log runs from 0 to 29.9 s ",
        ),
    ],
)
@pytest.mark.filterwarnings("ignore:the rest window")  # the synthetic rate turns throughout
def test_a_rest_window_past_the_end_of_the_log_is_an_error(overrides: dict[str, object], message: str) -> None:
    t = span(0, 30)
    with pytest.raises(RestWindowError) as e:
        gyrocore.process(t, rate(t), "hdr", **overrides)
    assert str(e.value).startswith(message)
    # a window that ends at the last sample is complete
    end = {"bias_window": (0.0, 29.9)} if "bias_window" in overrides else {"bias_duration": 29.9}
    assert len(gyrocore.process(t, rate(t), "hdr", **end)) == len(t)


gyrocore_cli = partial(conftest.gyrocore_cli, timeout=120)


def test_the_command_line_refuses_a_window_after_the_log(tmp_path: Path) -> None:
    src = synthetic_csv(tmp_path / "in.csv", 3000)  # 30 s from t = 1.7e9
    out = tmp_path / "h.csv"
    proc = gyrocore_cli("process", src, "--out", out, "--bias-window", "1700001000", "1700002000")
    assert proc.returncode == 2
    assert proc.stderr.startswith(
        f"gyrocore: error: {src}: the bias window [1700001000.0, 1700002000.0] s reaches past the end of the log "
        "(the log runs from 1700000000 to 1700000030 s "
    )
    assert len(proc.stderr.splitlines()) == 1 and not out.exists()
    proc = gyrocore_cli("process", src, "--out", out, "--bias-duration", "60")
    assert proc.returncode == 2 and "bias_duration = 60.0 s is longer than the log" in proc.stderr


STATIONARY = "stationary must be [t0, t1] in seconds (finite, t0 < t1) or null"


@pytest.fixture
def log_folder(tmp_path: Path) -> Path:
    folder = tmp_path / "drive"
    folder.mkdir()
    synthetic_csv(folder / "gyro.csv", 3000)
    return folder


def test_a_meta_json_window_after_the_log_names_meta_json(log_folder: Path, tmp_path: Path) -> None:
    (log_folder / "meta.json").write_text(json.dumps({"stationary": [1700005000.0, 1700005010.0]}))
    proc = gyrocore_cli("process", log_folder, "--out", tmp_path / "h.csv")
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"gyrocore: error: {log_folder / 'meta.json'} (stationary): the bias window "
                                  "[1700005000.0, 1700005010.0] s reaches past the end of the log")
    message = re.escape(f"{log_folder / 'meta.json'} (stationary): the bias window [1700005000.0, 1700005010.0] s")
    with pytest.raises(RestWindowError, match=f"^{message}"):
        gyrocore.read_log(log_folder).process("hdr")


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (b'{"stationary": [NaN, 5]}', f"{STATIONARY}, got [nan, 5]"),
        (b'{"stationary": [5, 1]}', f"{STATIONARY}, got [5, 1]"),
        (b'{"stationary": [5, 5]}', f"{STATIONARY}, got [5, 5]"),
        (b'{"name": "caf\xe9"}', "not UTF-8 text (at byte offset 13: invalid continuation byte); save it as UTF-8"),
    ],
)
def test_a_bad_meta_json_is_named(log_folder: Path, tmp_path: Path, content: bytes, message: str) -> None:
    (log_folder / "meta.json").write_bytes(content)
    proc = gyrocore_cli("process", log_folder, "--out", tmp_path / "h.csv")
    assert proc.returncode == 2
    assert proc.stderr.strip() == f"gyrocore: error: {log_folder / 'meta.json'}: {message}"
    with pytest.raises(ValueError) as raised:  # the Python API says the same
        gyrocore.read_log(log_folder)
    assert str(raised.value) == f"{log_folder / 'meta.json'}: {message}"


@pytest.mark.parametrize("mode", ["whole", "causal"])
@pytest.mark.parametrize(("overrides", "message"), [
    ({"bias_window": (5.0, 5.0)}, r"the bias window \[5.0, 5.0\] s holds 1 reading\(s\): the bias needs at least 3"),
    ({"bias_duration": 0.015}, r"bias_duration = 0.015 s holds 2 reading\(s\): the bias needs at least 3"),
    ({"bias_window": (-100.0, 1.0)}, r"the bias window \[-100.0, 1.0\] s starts before the first sample \(t\[0\] = 0.0\): "
                                     r"the bias would be measured over \[0.0, 1.0\] s only"),
])
def test_a_rest_window_too_short_or_partly_before_the_log_is_refused(
    mode: str, overrides: dict[str, object], message: str
) -> None:
    t = np.arange(0.0, 60.0, 0.01)
    with pytest.raises(gyrocore.RestWindowError, match=message):
        gyrocore.process(t, 0.01 + 0.1 * np.sin(t), "hdr", mode=mode, **overrides)


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_a_temperature_without_a_temperature_model_warns_that_it_is_not_used(mode: str) -> None:
    t = np.arange(0.0, 10.0, 0.01)
    with pytest.warns(gyrocore.InputWarning, match=r"temperature is given but no temperature model \(temp_slope, temp_offset\)"):
        gyrocore.process(t, np.zeros_like(t), "hdr", bias=0.0, mode=mode, temperature=np.full_like(t, 20.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gyrocore.process(t, np.zeros_like(t), "hdr", bias=0.0, mode=mode, temperature=np.full_like(t, 20.0), temp_slope=1e-4)


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_a_window_before_an_epoch_log_spells_it_out_in_the_logs_time_base(mode: str) -> None:
    # "give the window in the log's own time base" left the sum to the user, whose window was
    # most often in seconds after the first sample
    t = 1.7e9 + np.arange(0.0, 120.0, 0.01)
    with pytest.raises(gyrocore.RestWindowError, match=re.escape(
            "give the window in the log's own time base (as times after its first sample: (1700000040.0, "
            "1700000060.0), t[0] + start and t[0] + end)")):
        gyrocore.process(t, np.zeros_like(t), "static_bias", bias_window=(40.0, 60.0), mode=mode)


PYTHON_HINT = "a window after the first sample is (t[0] + start, t[0] + end)"
PLUS_T_HINT = "write a bound as +T for T seconds after the first sample"


@pytest.mark.parametrize("mode", ["whole", "causal"])
@pytest.mark.parametrize("given", [{"bias_window": (1050.0, 1070.0)}, {"bias_duration": 100.0}])
def test_the_python_api_hints_at_the_window_it_takes_and_a_batch_at_plus_t(
    tmp_path: Path, mode: str, given: dict[str, object]
) -> None:
    # the Python API told its callers to "write a bound as +T", which it refuses
    t = np.arange(1000.0, 1060.0, 0.01)
    with pytest.raises(RestWindowError) as python:
        gyrocore.process(t, np.full_like(t, 0.01), "static_bias", mode=mode, **given)
    assert PYTHON_HINT in str(python.value) and "+T" not in str(python.value)
    stream = Pipeline("static_bias", **given)  # type: ignore[arg-type]
    stream.process(t, np.full_like(t, 0.01))
    with pytest.raises(RestWindowError, match=re.escape(PYTHON_HINT)):
        stream.finish()
    # a batch, whose windows take +T (gyrocore.window.Window), says so
    src = synthetic_csv(tmp_path / "in.csv", 6000)
    late = {"bias_window": (1.7e9 + 50, 1.7e9 + 70)} if "bias_window" in given else given
    with pytest.raises(ValueError, match=re.escape(PLUS_T_HINT)) as batch:
        gyrocore.batch.process_file(src, tmp_path / "out.csv", preset="static_bias", mode=mode, **late)  # type: ignore[arg-type]
    assert PYTHON_HINT not in str(batch.value)


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_a_window_object_is_refused_by_name_with_the_tuple_to_give(mode: str) -> None:
    # "'Window' object is not subscriptable"
    window = gyrocore.window.Window.parse(["+0", "+20"], "--bias-window")
    said = (r"^invalid parameter bias_window = Window\(\+0 \.\. \+20 s\): a gyrocore.window.Window is the command "
            r"line's and a batch's; here give the tuple \(t\[0\] \+ 0, t\[0\] \+ 20\), t\[0\] the log's first time \[s\]$")
    t = span(0, 60)
    with pytest.raises(TypeError, match=said):
        gyrocore.process(t, rate(t), "static_bias", mode=mode, bias_window=window)
    with pytest.raises(TypeError, match=said):
        Pipeline("static_bias", bias_window=window)


@pytest.mark.parametrize("chunks", [1, 2])
def test_a_window_whose_readings_were_all_skipped_is_said_so_in_causal_mode_as_in_whole(chunks: int) -> None:
    # causal mode said "holds no sample of the log, which jumps from t = 61.99 to t = 62.0 s"
    t = np.arange(0.0, 120.0, 0.01)
    r = 0.01 + np.where((t > 50) & (t < 62), 0.0, 0.3 * np.sin(t / 3))
    r[5000:6200] = np.nan  # every reading of the window
    said = "the bias window [50.5, 61.5] s holds no usable reading (finite, within +-2^20 rad/s) of the log (the log "
    options = {"nonfinite": "skip", "bias_window": (50.5, 61.5)}
    with pytest.raises(RestWindowError, match=re.escape(said)):
        gyrocore.process(t, r, "static_bias", mode="whole", **options)  # type: ignore[arg-type]
    stream = Pipeline("static_bias", **options)  # type: ignore[arg-type]
    if chunks == 2:  # the window's samples came in the chunk before
        stream.process(t[:6100], r[:6100])
    with pytest.raises(RestWindowError, match=re.escape(said)) as causal:
        stream.process(t[6100:] if chunks == 2 else t, r[6100:] if chunks == 2 else r)
    assert "jumps" not in str(causal.value) and str(causal.value).endswith("; nothing of this chunk was processed")
