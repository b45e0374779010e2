"""Whole mode checks a log's times once per path (gyrocore.process, a batch file, a tuning case),
and a bad time is named by the pipeline where it is in the log, whatever the rest options."""

from __future__ import annotations

import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.csv as pa_csv
import pytest

import gyrocore
import gyrocore._checks
from gyrocore import tune, wholelog
from gyrocore.batch import process_file

from .test_wholelog import drive, run_cli


def make_log(t: np.ndarray, rate: np.ndarray, stationary: tuple[float, float] | None = None) -> gyrocore.Log:
    # a reference at 10 Hz, a tenth of the gyro's rate: its own times, checked on their own
    t_ref = t[0] + np.arange(0.0, float(np.nanmax(t) - t[0]), 0.1)
    return gyrocore.Log("drive", t, rate, t_ref=t_ref, heading_ref=np.zeros_like(t_ref), stationary=stationary)


PATHS: dict[str, Callable[[np.ndarray, np.ndarray, Path], object]] = {
    "gyrocore.process": lambda t, rate, _: gyrocore.process(t, rate, "recommended"),
    "a batch file": lambda t, rate, folder: process_file(folder / "in.csv", folder / "h.csv", preset="recommended"),
    "a tuning case": lambda t, rate, _: tune.Case.from_log(make_log(t, rate)),
}


@pytest.mark.parametrize("path", PATHS)
def test_each_whole_mode_path_checks_the_logs_times_once(
    path: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    t, rate, _ = drive(150.0, [(10.0, 25.0), (120.0, 135.0)])  # rests found in the log: the plan looks for them
    pa_csv.write_csv(pa.table({"t": t, "gyro_z": rate}), tmp_path / "in.csv")
    checked: list[int] = []  # the length of each series of times checked

    def spy(check: Callable[..., object]) -> Callable[..., object]:
        def counted(*args: object, **kwargs: object) -> object:
            times = next(a for a in args if isinstance(a, np.ndarray))
            checked.append(len(times))
            return check(*args, **kwargs)

        return counted

    monkeypatch.setattr(wholelog, "times_ok", spy(wholelog.times_ok))
    monkeypatch.setattr(gyrocore._checks, "require_increasing", spy(gyrocore._checks.require_increasing))
    PATHS[path](t, rate, tmp_path)
    assert checked.count(len(t)) == 1


def test_a_tuning_case_with_a_bad_time_names_it_where_it_is_in_the_log() -> None:
    # A NaN time inside the log's rest window: the plan takes no bias from it, and the pipeline
    # names the sample by its index in the log (not in the slice of the window).
    t, rate, _ = drive(60.0, [(20.0, 32.0)])
    t[3000] = np.nan
    case = tune.Case.from_log(make_log(t, rate, stationary=(t[0] + 21.0, t[0] + 31.0)))
    assert case.plan is not None and case.plan.source == "none: the log's times are invalid"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)
        with pytest.raises(gyrocore.SampleError, match=r"^t\[3000\] is NaN: samples must be finite") as e:
            case.score("static_bias", {})
    assert e.value.index == 3000


@pytest.mark.parametrize(
    "options", [{"bias_window": (1.7e18 + 20e9, 1.7e18 + 30e9)}, {"bias_duration": 10.0}, {"bias_walk": 1e-3}]
)
def test_a_sample_the_core_refuses_is_named_whatever_the_rest_options(options: dict[str, object], tmp_path: Path) -> None:
    # Nanoseconds read as seconds: the rest's measurement refuses them first, and the pipeline
    # that runs instead with no bias must name the sample, not refuse the options it was given.
    t = 1.7e18 + np.arange(0.0, 60.0, 0.01) * 1e9
    rate = np.where((t > t[0] + 20e9) & (t < t[0] + 30e9), 0.01, 0.3)
    src, out = tmp_path / "ns.csv", tmp_path / "h.csv"
    pa_csv.write_csv(pa.table({"t": t, "gyro_z": rate}), src)
    beyond = r"t\[0\] = 1.7e\+?18 s is beyond"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)
        with pytest.raises(gyrocore.SampleError, match="^" + beyond):
            gyrocore.process(t, rate, "static_bias", **options)  # type: ignore[arg-type]
        # a batch refuses its parameters before any file is read: a window beyond any time, and why
        file_error = (r"bias_window.start = 1.7\d*e\+?18: must be within \+-2\^40 s, the limit of a timestamp \(epoch "
                      r"nanoseconds read as seconds" if "bias_window" in options else beyond + r".*\(.*ns\.csv, line 2\)")
        with pytest.raises(ValueError, match=file_error):
            process_file(src, out, preset="static_bias", **options)
    assert not out.exists()
    if "bias_duration" in options:
        proc = run_cli("process", str(src), "--out", str(out), "--preset", "static_bias", "--bias-duration", "10")
        assert proc.returncode != 0 and "line 2" in proc.stderr and "is beyond" in proc.stderr and not out.exists()
