"""What a user working in a notebook meets: results that become tables, inputs as pandas holds
them, and what ``dir``, ``repr`` and ``help`` show."""

from __future__ import annotations

import datetime
import importlib
import inspect
import re
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore.fixes import Fixes


def _drive(n: int = 3000) -> tuple[np.ndarray, np.ndarray]:
    t = 10.0 + np.arange(n) * 0.01
    return t, 0.002 + (t > 20.0) * 0.2 * np.sin(t / 3.0)


def test_a_result_gives_its_computed_columns_by_name_for_a_table() -> None:
    t, rate = _drive()
    r = gyrocore.process(t, rate, "hdr", bias=0.002)
    columns = r.columns()
    assert list(columns) == ["t", "heading", "rate", "drift"]
    assert columns["heading"] is r.heading and columns["t"] is r.t  # no copies
    assert list(gyrocore.process(t, rate, "hdr", bias=0.002, outputs=("heading",)).columns()) == ["t", "heading"]
    fixes = Fixes(t=np.array([15.0, 25.0]), heading=np.array([0.1, 0.2]), sigma=np.array([0.05, 0.05]))
    fused = gyrocore.process(t, rate, "hdr", bias=0.002, fixes=fixes).columns()
    assert list(fused) == ["t", "heading", "rate", "drift", "heading_sigma", "fusion_bias", "fusion_scale"]
    assert all(len(a) == len(t) for a in fused.values())


@pytest.mark.parametrize("zone", [None, datetime.timezone.utc])
def test_dates_with_or_without_a_time_zone_are_refused_as_dates_with_what_to_give(zone: datetime.tzinfo | None) -> None:
    # pandas' times with a time zone (and Python's datetimes) reach numpy as objects: the error
    # said "give numbers, NaN where a value is missing", as for text or None
    start = datetime.datetime(2024, 5, 1, 12, 0, tzinfo=zone)
    t = [start + datetime.timedelta(seconds=0.01 * i) for i in range(100)]
    with pytest.raises(TypeError, match=r"t holds dates and times: give seconds, e\.g\. \(t - t\.min\(\)\) / "
                                        r"numpy\.timedelta64\(1, 's'\) \(t\[0\] is datetime\.datetime\(2024, 5, 1"):
        gyrocore.process(t, np.zeros(100), "raw")
    with pytest.raises(TypeError, match="t_ref holds dates and times"):
        gyrocore.heading_errors(np.arange(100.0), np.zeros(100), t, np.zeros(100))


def test_tab_completion_of_the_package_offers_its_public_names_and_every_documented_module() -> None:
    import gyrocore.pipeline_input  # noqa: F401  (a part of the pipeline, loaded with it: no public module)

    public = {name for name in dir(gyrocore) if not name.startswith("_")}
    assert public == {name for name in gyrocore.__all__ if not name.startswith("_")}
    assert not public & {"Any", "TYPE_CHECKING", "annotations", "importlib", "pipeline_input"}
    assert {"datasets", "rests", "sim", "evaluate"} <= public  # the modules docs/python.md names
    assert all(getattr(gyrocore, name) is not None for name in public)


def test_help_of_the_package_names_every_public_module_and_where_the_guide_is() -> None:
    doc = gyrocore.__doc__ or ""
    modules = [name for name in gyrocore.__all__ if inspect.ismodule(getattr(gyrocore, name))]
    assert len(modules) >= 10
    assert [m for m in modules if f":mod:`gyrocore.{m}`" not in doc] == []
    assert "docs/python.md" in doc and ":func:`process`" in doc


def test_a_batch_report_shows_as_one_line_however_many_files() -> None:
    from gyrocore.batch import BatchReport, FileReport

    rest = gyrocore.rests.Rest(start=0.0, end=20.0, bias=0.002, bias_std_error=1e-5, noise=0.003, samples=2000,
                               found_by="given")
    files = [FileReport(f"log{i}", f"out/log{i}.csv", 6000, 6000, 0.1, bias_source="rest", rests=(rest,))
             for i in range(200)] + [FileReport("bad", None, 10, 0, 0.01, error="bad: t[3] is NaN")]
    report = BatchReport(tuple(files), 21.0)
    # the totals are the files processed: the failed file's 10 rows are its own report's
    assert repr(report) == ("BatchReport(200 of 201 files processed, 1 failed; 1200000 rows in, 1200000 out, 21.00 s; "
                            "print() it for each file, .files for their reports)")
    assert str(report).count("\n") == 200 * 3 + 1 and str(report).endswith("1200000 out, 21.00 s")  # as before


def test_a_score_shows_as_one_line_of_its_figures() -> None:
    from gyrocore.evaluate import HeadingErrors, Method, Score

    errors = HeadingErrors(e_psi_deg=3.6721, ne_psi_deg_per_min=1.7352, mean_error_deg=3.6721, std_error_deg=1.99,
                           final_error_deg=5.2395, max_error_deg=12.16, duration_min=2.116, n=2735)
    rest = gyrocore.rests.Rest(start=0.0, end=20.0, bias=0.002, bias_std_error=1e-5, noise=0.003, samples=2000,
                               found_by="given")
    score = Score("f110_ds3", Method.from_preset("recommended"), errors, 5.552, "rest [0, 20] s (given): ...",
                  return_error_deg=5.2396, rests=(rest,) * 5, path="logs/f110_ds3")
    assert repr(score) == ("Score('f110_ds3', 'recommended': E_psi 3.672 deg, NE_psi 1.735 deg/min, improvement "
                           "5.55, return error 5.240 deg)")
    assert score.as_dict()["e_psi_deg"] == 3.6721 and len(score.as_dict()["rests"]) == 5  # every field, as before


def test_a_log_built_from_sequences_holds_float64_arrays() -> None:
    t, rate = _drive(2000)
    log = gyrocore.Log("mine", list(t), rate.astype(np.float32), t_ref=t[::10].tolist(), heading_ref=np.zeros(200))
    assert all(type(a) is np.ndarray and a.dtype == np.float64 for a in (log.t, log.rate, log.t_ref, log.heading_ref))
    assert log.x_ref is None and log.speed is None
    assert log.duration == pytest.approx(19.99)
    with pytest.raises(TypeError, match="t_ref holds dates and times"):
        gyrocore.Log("mine", t, rate, t_ref=[datetime.datetime(2024, 5, 1)] * 3, heading_ref=np.zeros(3))


def test_a_log_built_from_a_pandas_table_cut_by_label_reads_by_position() -> None:
    pd = pytest.importorskip("pandas")
    t, rate = _drive(2000)
    df = pd.DataFrame({"t": t, "gyro_z": rate})
    moving = df.iloc[200:]  # index from 200 on: t[0] and t[-1] were label look-ups, a KeyError
    log = gyrocore.Log("mine", moving.t, moving.gyro_z.astype("Float64"), t_ref=moving.t, heading_ref=moving.t * 0.0)
    assert repr(log).startswith("Log('mine': 1800 samples, 17.99 s from t = 12.000 s")
    assert np.array_equal(log.process("hdr", bias=0.002).heading,
                          gyrocore.process(t[200:], rate[200:], "hdr", bias=0.002).heading)


def test_fixes_built_from_sequences_hold_float64_arrays_as_fixes_of_gives() -> None:
    t, rate = _drive()
    fixes = Fixes([15.0, 25.0, 35.0], [0.1, 0.2, 0.3], np.array([5, 5, 5], dtype=np.int64) / 100)
    assert all(type(a) is np.ndarray and a.dtype == np.float64 for a in (fixes.t, fixes.heading, fixes.sigma))
    given = Fixes.of(np.array([15.0, 25.0, 35.0]), np.array([0.1, 0.2, 0.3]), 0.05)
    assert np.array_equal(gyrocore.fuse(t, rate, fixes).heading, gyrocore.fuse(t, rate, given).heading)
    with pytest.raises(TypeError, match="fix sigma must hold real numbers"):
        Fixes([15.0], [0.1], ["0.05"])


@pytest.mark.parametrize("zone", [None, "UTC"])
def test_the_seconds_that_the_error_about_dates_advises_can_be_computed_from_a_pandas_column_cut_by_label(
        zone: str | None) -> None:
    pd = pytest.importorskip("pandas")
    t, rate = _drive(2000)
    df = pd.DataFrame({"time": pd.to_datetime(t, unit="s", utc=zone is not None), "gyro_z": rate}).iloc[500:]
    with pytest.raises(TypeError, match=r"give seconds, e\.g\. \(t - t\.min\(\)\) / numpy\.timedelta64\(1, 's'\)"):
        gyrocore.process(df.time, df.gyro_z, "hdr", bias=0.002)
    seconds = (df.time - df.time.min()) / np.timedelta64(1, "s")  # df.time[0] is a label look-up: a KeyError
    r = gyrocore.process(seconds, df.gyro_z, "hdr", bias=0.002)
    expected = gyrocore.process(t[500:] - t[500], rate[500:], "hdr", bias=0.002).heading  # to the nanosecond
    np.testing.assert_allclose(r.heading, expected, rtol=0, atol=1e-6)


def test_noise_parameters_show_as_one_line_of_their_values() -> None:
    from gyrocore.allan import NoiseParameter, NoiseParameters

    arw = NoiseParameter(1.3115544864194923e-4, "rad/s/sqrt(Hz)", 0.4508792200397109, "deg/sqrt(h)",
                         (0.0035000000000025, 0.22400000000016007), "line of slope -1/2 read at tau = 1 s")
    noise = NoiseParameters(arw, None, None, 0.0035000000000025, ("no stretch of slope +1/2", "no minimum"))
    assert repr(noise) == ("NoiseParameters(N 0.0001312 rad/s/sqrt(Hz), B not found, K not found; 2 note(s): print() it "
                           "for where each was read and the notes)")
    assert str(noise).startswith("angle random walk N: 0.0001312 rad/s/sqrt(Hz) (0.4509 deg/sqrt(h)), tau 0.0035 ..")


@pytest.mark.parametrize("name", ["fixes", "allan", "evaluate", "calibration", "io", "batch", "tune", "wholelog", "motion",
                                  "paper", "pipeline"])
def test_tab_completion_of_a_public_module_offers_its_public_names(name: str) -> None:
    module = importlib.import_module(f"gyrocore.{name}")
    public = {n for n in dir(module) if not n.startswith("_")}
    assert public == set(module.__all__)
    assert not public & {"np", "math", "Any", "annotations", "dataclass", "TYPE_CHECKING", "public_dir"}


def test_tab_completion_of_the_fixes_module_leaves_out_the_pipelines_helpers() -> None:
    from gyrocore import fixes

    assert {"fuse", "Fixes", "read_gnss_csv", "from_positions"} <= set(dir(fixes))
    assert not set(dir(fixes)) & {"say_how_to_wait", "refuse_behind_waiting", "warn_outside", "stage_settings",
                                  "smoothed_stage", "warn_far_ahead"}


def test_a_fusion_result_gives_its_computed_columns_by_name() -> None:
    t, rate = _drive()
    fixes = Fixes(np.array([15.0, 25.0]), np.array([0.1, 0.2]), np.array([0.05, 0.05]))
    fused = gyrocore.fuse(t, rate, fixes, mode="smoothed")
    columns = fused.columns()
    assert list(columns) == ["t", "heading", "heading_sigma", "bias", "scale"] and columns["bias"] is fused.bias
    streamed = gyrocore.Pipeline("hdr", bias=0.002).process(t, rate, fixes=fixes, outputs=("heading", "fusion_bias"))
    assert streamed.fusion is not None and list(streamed.fusion.columns()) == ["t", "heading", "bias"]
    assert list(streamed.columns()) == ["t", "heading", "fusion_bias"]


def test_a_tuning_result_shows_as_one_line_of_what_was_fitted_and_its_scores() -> None:
    from gyrocore.tune import CaseScore, ParameterSet, TuningResult

    def scores(ne_psi: float) -> tuple[CaseScore, ...]:
        return tuple(CaseScore(f"drive {i}", 2.0, ne_psi, 20.0, 2.5, 3.0) for i in range(18))

    params = ParameterSet("hdr_tuned", "hdr", {"hdr_increment": 1.2345678e-4, "hdr_turn_threshold": 0.0637})
    result = TuningResult(params, {"hdr_increment": 7.4e-4}, {"hdr_increment": (1e-5, 1e-2)}, scores(1.5), scores(0.75),
                          scores(0.1), scores(0.1), 0.5, 1.6, 0.8, 2000, "differential_evolution", 0)
    assert repr(result) == ("TuningResult('hdr_tuned' of 'hdr': hdr_increment=0.0001235, hdr_turn_threshold=0.0637; "
                            "mean NE_psi 1.5000 -> 0.7500 deg/min on 18 drive(s), harm within 0.5 deg on 18; "
                            "2000 evaluations)")


class _Labelled:
    """A column indexed by label, as a pandas Series cut from a table: ``[i]`` looks up the label
    ``i``, numpy reads it by position."""

    def __init__(self, values: list[float], labels: list[int]) -> None:
        self.values, self.labels = values, labels

    def __array__(self, dtype: object = None, copy: object = None) -> np.ndarray:
        return np.asarray(self.values, dtype=dtype)  # type: ignore[call-overload]

    def __len__(self) -> int:
        return len(self.values)

    def __getitem__(self, label: int) -> float:
        return self.values[self.labels.index(label)]  # a KeyError-like ValueError for a label not there


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_a_rest_window_given_as_a_column_indexed_by_label_is_read_by_position(mode: str) -> None:
    t, rate = _drive()
    window = _Labelled([10.0, 19.0], [0, 900])  # as df.t.iloc[[0, 900]]: its [1] was a failed look-up
    r = gyrocore.process(t, rate, "hdr", bias_window=window, mode=mode)
    assert np.array_equal(r.heading, gyrocore.process(t, rate, "hdr", bias_window=(10.0, 19.0), mode=mode).heading)
    assert gyrocore.Pipeline("hdr", bias_window=window).params["bias_window"] == (10.0, 19.0)


def test_a_rest_window_given_as_a_pandas_series_is_read_by_position() -> None:
    pd = pytest.importorskip("pandas")
    t, rate = _drive()
    window = pd.Series(t).iloc[[0, 900]]
    assert gyrocore.process(t, rate, "hdr", bias_window=window).bias_source.startswith("rest [10.000, 19.000] s (given)")


def test_numpy_durations_given_as_numbers_are_refused_by_name_with_what_to_give() -> None:
    t, rate = _drive()
    # float() of them was a bare "float() argument must be a string or a real number, not 'datetime.timedelta'"
    dt = np.timedelta64(10, "ms")  # numpy 1.x shows it as numpy.timedelta64(...), numpy 2 as np.timedelta64(...)
    with pytest.raises(TypeError, match=r"^dt must be a number \[s\], got " + re.escape(repr(dt))):
        gyrocore.allan.deviation(rate, dt)
    duration = np.timedelta64(20, "s")
    with pytest.raises(TypeError, match=rf"^invalid parameter bias_duration = {re.escape(repr(duration))}: give seconds"):
        gyrocore.process(t, rate, "hdr", bias_duration=duration)
    window = np.array([10, 19], dtype="timedelta64[ns]")  # tolist() gave nanoseconds as ints: a window in ns
    with pytest.raises(TypeError, match=r"^invalid parameter bias_window = array\(\[10, 19\], dtype='timedelta64"):
        gyrocore.Pipeline("hdr", bias_window=window)


def test_read_log_given_samples_in_memory_says_where_they_go() -> None:
    t, rate = _drive()
    for table in (np.column_stack([t, rate]), {"t": t, "gyro_z": rate}):
        with pytest.raises(TypeError, match=r"^read_log reads a file or log folder by its path, got (ndarray|dict): "
                                            r"samples in memory go to gyrocore\.process\(t, rate\), or with their "
                                            r"reference to gyrocore\.Log\(name, t, rate"):
            gyrocore.read_log(table)  # type: ignore[arg-type]


def test_tab_completion_of_a_log_and_of_fixes_offers_no_helper_of_the_package() -> None:
    t, rate = _drive()
    log = gyrocore.Log("mine", t, rate)
    fixes = Fixes.of(np.array([15.0]), np.array([0.1]), 0.05)
    assert "naming_stationary" not in dir(log) and {"process", "reference", "duration"} <= set(dir(log))
    assert "warn_if_vague" not in dir(fixes) and "of" in dir(fixes)


def test_the_plot_of_a_log_is_written_to_a_path_given_as_text(tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    t, rate = _drive()
    log = gyrocore.Log("mine", t, rate, t_ref=t[::10], heading_ref=gyrocore.integrate(t, rate - 0.002)[::10])
    results = {p: log.process(p, bias=0.002) for p in ("raw", "hdr")}
    gyrocore.evaluate.plot_log(str(tmp_path / "plots" / "mine.png"), log, results)
    assert (tmp_path / "plots" / "mine.png").read_bytes()[:4] == b"\x89PNG"


def test_help_of_process_says_the_units_of_its_arrays() -> None:
    # help(gyrocore.process), where a user with a gyro in deg/s looks first, named no unit
    doc = " ".join((gyrocore.process.__doc__ or "").split())
    assert "``t`` [s] and ``rate`` [rad/s, counter-clockwise positive; deg/s: ``numpy.radians(rate)``]" in doc


def test_a_pipeline_under_way_shows_where_its_stream_stands() -> None:
    # its repr was the same before and after a chunk: the time the next chunk must start after went unseen
    t = np.arange(0.0, 30.0, 0.01)
    p = gyrocore.Pipeline("hdr", bias=0.0)
    fresh = repr(p)
    assert fresh.startswith("Pipeline(preset='hdr', params={") and "last_time" not in fresh
    p.process(t, np.zeros_like(t))
    assert repr(p) == fresh[:-1] + f", last_time={float(t[-1])!r})"
    p.reset()
    assert repr(p) == fresh


def test_a_fix_filter_shows_its_settings_and_what_its_fixes_did() -> None:
    # it printed as a bare object: <gyrocore.fixes.Fusion object at 0x...>
    f = gyrocore.fixes.Fusion(arw=2e-3)
    t = np.arange(0.0, 10.0, 0.01)
    f.process(t, np.zeros_like(t), gyrocore.fixes.Fixes(np.array([5.0]), np.array([0.1]), np.array([0.02])))
    assert repr(f) == f"Fusion(settings={f.settings()!r}, counts={f.counts()!r})"
    assert "'arw': 0.002" in repr(f) and "'applied': 1" in repr(f)


@pytest.mark.parametrize("given", ["drive.csv", "logs/drive1", "gyro.npz"])
def test_a_file_given_to_process_is_told_to_be_read_first(given: str) -> None:
    """As the command line takes a file, a first try in Python gives one: it was told the preset's
    name after it is no number (``rate must hold real numbers, got dtype <U3``), of files nothing."""
    said = (rf"t = '{given}': a file's name, not a sequence of numbers; gyrocore\.process takes t \[s\] "
            r"and rate \[rad/s\]; a log file or folder is read with gyrocore\.read_log\(path\), then processed with "
            r"its \.process\(preset\) \(on the command line: gyrocore process FILE\)$")
    with pytest.raises(TypeError, match=said):
        gyrocore.process(given, "hdr")
    on_pipeline = said.replace(f"'{given}'", rf"PosixPath\('{given}'\)").replace("gyrocore\\.process", "gyrocore\\.Pipeline\\.process", 1)
    with pytest.raises(TypeError, match=on_pipeline):
        gyrocore.Pipeline("raw").process(Path(given), [0.0])
    # alone, as the command line takes a file, or with a preset's name by keyword: Python's own
    # "process() missing 1 required positional argument: 'rate'" said nothing of files
    for alone in (lambda: gyrocore.process(given), lambda: gyrocore.process(given, preset="hdr"),
                  lambda: gyrocore.process(t=given)):
        with pytest.raises(TypeError, match=said):
            alone()
    with pytest.raises(TypeError, match=on_pipeline):
        gyrocore.Pipeline("raw").process(Path(given))
    with pytest.raises(TypeError, match=r"t must hold real numbers, got dtype <U3"):  # a number as text is none
        gyrocore.process("1.5", [0.0])
