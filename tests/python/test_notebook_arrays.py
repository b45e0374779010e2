"""Array inputs as a notebook hands them over: results own their arrays, and odd array-likes
are refused with a message saying what to give."""

from __future__ import annotations

import datetime
import decimal
import threading
import warnings

import numpy as np
import pytest

import gyrocore
from gyrocore import SampleError, _arrays, fixes


@pytest.fixture(scope="module")
def drive() -> tuple[np.ndarray, np.ndarray]:
    d = gyrocore.sim.car_drive(duration=60.0, rate_hz=50.0, seed=3)
    return np.array(d.t), np.array(d.rate_measured)


def _fixes(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    ft = t[::250].copy()
    return ft, np.zeros(len(ft)), np.full(len(ft), 0.05)


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_result_times_are_not_the_callers_array(drive: tuple[np.ndarray, np.ndarray], mode: str) -> None:
    t, rate = drive
    t_given = t.copy()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = gyrocore.process(t, rate, "recommended", bias_window=(t[0], t[0] + 10.0), mode=mode)
    assert not np.shares_memory(r.t, t)
    r.t[:] = r.t - r.t[0]  # times from the start, for a plot
    np.testing.assert_array_equal(t, t_given)


def test_pipeline_and_fusion_results_own_their_times(drive: tuple[np.ndarray, np.ndarray]) -> None:
    t, rate = drive
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        results = [
            gyrocore.Pipeline("recommended", bias_duration=10.0).process(t, rate),
            fixes.fuse(t, rate, fixes.Fixes.of(*_fixes(t))),
            fixes.Fusion().process(t, rate, fixes.Fixes.of(*_fixes(t))),
            gyrocore.process(t, rate, "recommended", bias_window=(t[0], t[0] + 10.0), fixes=fixes.Fixes.of(*_fixes(t))),
        ]
    for r in results:
        assert not np.shares_memory(r.t, t), type(r).__name__


def test_results_own_the_data_an_array_like_hands_over(drive: tuple[np.ndarray, np.ndarray]) -> None:
    t, rate = drive

    class Column:  # a Series-like object: __array__ hands over the data it holds
        def __init__(self, a: np.ndarray) -> None:
            self.a = a

        def __array__(self, dtype: object = None, copy: object = None) -> np.ndarray:
            return self.a

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = gyrocore.process(Column(t), Column(rate), "recommended", bias_window=(t[0], t[0] + 10.0))
    assert not np.shares_memory(r.t, t)


def test_fixes_keep_their_own_arrays(drive: tuple[np.ndarray, np.ndarray]) -> None:
    t, _ = drive
    ft, heading, sigma = _fixes(t)
    for f in (fixes.Fixes(ft, heading, sigma), fixes.Fixes.of(ft, heading, sigma)):
        heading[0] = 1e9  # beyond MAX_HEADING: refused when the fixes are built, so never seen by the filter
        assert f.heading[0] == 0.0
        heading[0] = 0.0
        assert not any(np.shares_memory(a, b) for a in (f.t, f.heading, f.sigma) for b in (ft, heading, sigma))


@pytest.mark.parametrize("given", [
    {"bias": np.ma.masked},
    {"bias": np.ma.array([0.01, 0.02], mask=[True, True]).mean()},  # the mean of a rest all masked
    {"bias": 0.0, "hdr_increment_dps": np.ma.masked},
    {"bias_window": np.ma.array([0.0, 10.0], mask=[False, True])},
])
def test_a_masked_parameter_is_refused(drive: tuple[np.ndarray, np.ndarray], given: dict[str, object]) -> None:
    t, rate = drive
    key = next(k for k, v in given.items() if np.ma.is_masked(v))
    with pytest.raises(TypeError, match=f"invalid parameter {key} = .*a masked value holds no number"):
        gyrocore.process(t, rate, "hdr", **given)  # type: ignore[arg-type]


def test_a_masked_option_is_refused(drive: tuple[np.ndarray, np.ndarray]) -> None:
    t, rate = drive
    with pytest.raises(TypeError, match=r"interval must be a number \[s\], got masked"):
        gyrocore.downsample(t, rate, np.ma.masked)  # type: ignore[arg-type]


def test_a_masked_value_that_is_given_is_taken(drive: tuple[np.ndarray, np.ndarray]) -> None:
    t, rate = drive
    r = gyrocore.process(t, rate, "hdr", bias=np.ma.array([0.01, 0.5], mask=[False, True])[0])
    assert "0.57296 deg/s" in r.bias_source


@pytest.mark.parametrize("given, message", [
    ((x for x in range(3)), r"^t must be a sequence of numbers \(a list or array\), got generator: give numpy.fromiter\(t, float\)$"),
    (None, r"^t must be a sequence of numbers \(a list or array\), got NoneType$"),
])
def test_what_is_no_sequence_is_named(given: object, message: str) -> None:
    with pytest.raises(TypeError, match=message):
        gyrocore.integrate(given, [0.0, 0.1, 0.2])  # type: ignore[arg-type]


def test_numbers_as_text_say_how_to_convert(drive: tuple[np.ndarray, np.ndarray]) -> None:
    t, rate = drive
    text = [str(x) for x in rate]  # a column read with the csv module
    with pytest.raises(TypeError, match=r"rate must hold real numbers, got dtype <U\d+ \(text: give numbers, e\.g\. "
                       r"numpy\.asarray\(rate, dtype=float\)\)"):
        gyrocore.process(t, text, "hdr", bias=0.0)
    r = gyrocore.process(t, np.asarray(text, dtype=float), "hdr", bias=0.0)  # the conversion the message gives
    np.testing.assert_array_equal(r.heading, gyrocore.process(t, rate, "hdr", bias=0.0).heading)


@pytest.mark.filterwarnings("ignore::PendingDeprecationWarning")  # numpy's of numpy.matrix
@pytest.mark.parametrize("shape", ["column", "row", "matrix"])
def test_a_column_or_row_says_how_to_flatten(drive: tuple[np.ndarray, np.ndarray], shape: str) -> None:
    t, rate = drive
    given = {"column": t[:, None], "row": t[None, :], "matrix": np.matrix(t)}[shape]
    with pytest.raises(ValueError, match=r"^t must be one-dimensional, got shape \(\d+, \d+\): give one column, "
                       r"e\.g\. numpy\.ravel\(t\)$"):
        gyrocore.process(given, rate, "hdr", bias=0.0)
    with pytest.raises(ValueError, match=r"^t must be one-dimensional, got shape \(2, 3\)$"):  # no axis is plainly time
        gyrocore.process(np.zeros((2, 3)), rate, "hdr", bias=0.0)


def test_python_durations_are_seconds(drive: tuple[np.ndarray, np.ndarray]) -> None:
    t, rate = drive
    start = datetime.datetime(2024, 5, 1, 12, 0, 0)
    stamps = [start + datetime.timedelta(seconds=float(x)) for x in t]
    durations = [s - start for s in stamps]  # a notebook's times from the first sample
    np.testing.assert_array_equal(gyrocore.integrate(durations, rate), gyrocore.integrate(np.round(t, 6), rate))
    with pytest.raises(SampleError, match=r"t\[0\] = 86399999913600 s is beyond"):  # no wrap past int64 microseconds
        gyrocore.integrate([datetime.timedelta(days=999_999_999)] * 2, [0.0, 0.0])


def test_decimals_say_how_to_convert() -> None:
    given = [decimal.Decimal("0.01")] * 3
    with pytest.raises(TypeError, match=r"rate\[0\] is Decimal\('0.01'\) \(give numpy\.asarray\(rate, dtype=float\), "):
        gyrocore.integrate([0.0, 0.1, 0.2], given)
    np.testing.assert_allclose(gyrocore.integrate([0.0, 0.1, 0.2], np.asarray(given, dtype=float)), [0.0, 0.001, 0.002])


def test_complex_numbers_are_not_said_to_convert() -> None:
    with pytest.raises(TypeError, match=r"rate\[0\] is 1j \(give numbers, NaN where a value is missing\)"):
        gyrocore.integrate([0.0, 0.1, 0.2], np.array([1j, 0.1, 0.2], dtype=object))


def test_a_bias_table_from_arrays() -> None:
    from gyrocore.calibration import BiasTable

    given = [np.array([10.0, 30.0]), np.array([0.01, 0.02]), np.array([1e-4, 1e-4]), np.array([10, 10])]
    table = BiasTable(*given)  # type: ignore[arg-type]
    assert table == BiasTable((10.0, 30.0), (0.01, 0.02), (1e-4, 1e-4), (10, 10))
    assert table(20.0) == pytest.approx(0.015)
    given[1][0] = 1.0  # the caller's array, changed later, is not the table's
    assert table(10.0) == 0.01
    with pytest.raises(ValueError, match=r"bias table temperatures\[1\] = 10 degC does not come after 30 degC"):
        BiasTable(np.array([30.0, 10.0]), *given[1:])  # type: ignore[arg-type]


def test_a_reference_keeps_its_own_arrays(drive: tuple[np.ndarray, np.ndarray]) -> None:
    from gyrocore.evaluate import Reference

    t, rate = drive
    t_ref, heading_ref = t.copy(), np.cumsum(rate) / 50.0
    reference = Reference(t_ref, heading_ref)
    before = reference.e_psi(t, 1.01 * heading_ref)
    t_ref[10], heading_ref[:] = t_ref[5], 0.0  # out of order, and another heading: checked when it was built
    assert reference.e_psi(t, 1.01 * np.cumsum(rate) / 50.0) == before
    assert not any(np.shares_memory(a, b) for a in (reference.t, reference.given) for b in (t_ref, heading_ref))


def test_a_stream_from_one_buffer_keeps_each_chunks_times(drive: tuple[np.ndarray, np.ndarray]) -> None:
    t, rate = drive
    p = gyrocore.Pipeline("hdr", bias=0.0)
    buffer_t, buffer_rate = np.empty(500), np.empty(500)  # a reader's buffer, filled again for each chunk
    chunks = []
    for start in range(0, len(t), 500):
        buffer_t[:], buffer_rate[:] = t[start:start + 500], rate[start:start + 500]
        chunks.append(p.process(buffer_t, buffer_rate))
    np.testing.assert_array_equal(np.concatenate([c.t for c in chunks]), t)


@pytest.mark.parametrize("entry", ["process", "Pipeline.process"])
def test_long_times_are_copied_beside_the_core_whole_and_apart(entry: str) -> None:
    # long times are copied on another thread while the core runs: the copy is whole, the
    # result's own, and no thread outlives the call, also one the core refused
    n = _arrays.COPIED_BESIDE + 12345
    t = 1000.0 + np.arange(n) * 0.01
    rate = np.full(n, 0.01)
    run = (lambda r: gyrocore.process(t, r, "raw")) if entry == "process" else (
        lambda r: gyrocore.Pipeline("raw").process(t, r))
    result = run(rate)
    np.testing.assert_array_equal(result.t.view(np.uint64), t.view(np.uint64))
    assert not np.shares_memory(result.t, t) and result.t.flags.writeable
    assert not [th for th in threading.enumerate() if th.name == "gyrocore-copy"]
    bad = rate.copy()
    bad[-1] = np.nan
    with pytest.raises(SampleError, match=rf"rate\[{n - 1}\] is NaN"):
        run(bad)
    assert not [th for th in threading.enumerate() if th.name == "gyrocore-copy"]
