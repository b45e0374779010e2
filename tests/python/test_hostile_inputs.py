"""Inputs a hostile user gives: each refused with one line naming the file or parameter and what
to do, never a traceback, a silent wrong result or an overwritten input."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import fixes
from gyrocore.calibration import Calibration, static_bias

from .conftest import real_log_path
from .test_batch import synthetic_csv
from .test_errors_named import run_cli

#: JSON that Python's parser cannot read without running out of recursion.
DEEP_JSON = "[" * 100_000 + "]" * 100_000


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (DEEP_JSON, "JSON nested too deeply to read"),
        ('{"stationary": [0, 1' + "0" * 400 + "]}", "stationary must be [t0, t1] in seconds"),
    ],
    # pytest 7 named the test by the 200,000 characters, and its PYTEST_CURRENT_TEST made every
    # subprocess fail to start ("Argument list too long")
    ids=["deep", "huge-number"],
)
def test_a_hostile_meta_json_is_named(tmp_path: Path, content: str, message: str) -> None:
    folder = tmp_path / "log"
    folder.mkdir()
    synthetic_csv(folder / "gyro.csv", 3000)
    (folder / "meta.json").write_text(content)
    for args in (("process", folder, "--out", tmp_path / "h.csv"), ("allan", folder)):
        proc = run_cli(*args)
        assert proc.returncode == 2
        assert proc.stderr.startswith(f"gyrocore: error: {folder / 'meta.json'}: {message}")


@pytest.mark.parametrize("option", ["--calibration", "--params"])
def test_a_deeply_nested_json_file_is_named(tmp_path: Path, option: str) -> None:
    path = tmp_path / "deep.json"
    path.write_text(DEEP_JSON)
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    args = ("process", log, "--out", tmp_path / "h.csv") if option == "--calibration" else ("evaluate", tmp_path)
    proc = run_cli(*args, option, path)
    assert proc.returncode == 2
    assert proc.stderr == f"gyrocore: error: {path}: JSON nested too deeply to read (arrays or objects inside each other)\n"


@pytest.mark.parametrize("option", ["--fixes", "--calibration"])
def test_a_file_an_option_names_is_never_the_output(tmp_path: Path, option: str) -> None:
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    given = tmp_path / "given.csv"  # a calibration is JSON whatever its file is called
    if option == "--fixes":
        given.write_text("t,heading,sigma\n1700000001,0.1,0.05\n")
    else:
        Calibration(method="static_bias", bias=0.001).save(given)
    before = given.read_bytes()
    proc = run_cli("process", log, "--out", given, option, given)
    assert proc.returncode == 2
    assert proc.stderr == f"gyrocore: error: refusing to write {given} over or inside the input {given}; write it elsewhere\n"
    assert given.read_bytes() == before


@pytest.mark.parametrize("mode", ["whole", "causal"])
@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        ({"bias_window": (1, 2, 3)}, "invalid parameter bias_window = (1, 2, 3): expected tuple of length 2, but got "
         "tuple of length 3; bias_window is (start, end) rest window"),
        ({"bias_window": (1,)}, "invalid parameter bias_window = (1,): expected tuple of length 2"),
        ({"bias_window": "ab"}, "invalid parameter bias_window = 'ab': 'str' object is not an instance of 'tuple'"),
        ({"bias_duration": 0}, "invalid parameter bias_duration = 0: must be > 0"),
        ({"bias_duration": -1}, "invalid parameter bias_duration = -1: must be > 0"),
        ({"bias_duration": "5"}, "invalid parameter bias_duration = '5': must be real number, not str"),
    ],
)
def test_a_bad_rest_window_is_named_in_either_mode(mode: str, overrides: dict[str, object], message: str) -> None:
    t = np.arange(0.0, 60.0, 0.01)
    with pytest.raises((TypeError, ValueError)) as info:
        gyrocore.process(t, np.full_like(t, 0.002), "recommended", mode=mode, **overrides)
    assert str(info.value).startswith(message)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("--param", "bias_window=1,2,3"), "invalid parameter bias_window = (1.0, 2.0, 3.0): expected tuple of length 2"),
        (("--param", "bias_window=abc"), "invalid parameter bias_window = 'abc': 'str' object is not an instance"),
    ],
)
def test_the_command_line_names_a_bad_rest_window(tmp_path: Path, args: tuple[str, ...], message: str) -> None:
    assert refused_process(tmp_path, *args).startswith(f"gyrocore: error: {message}")


def refused_process(tmp_path: Path, *args: str) -> str:
    """``gyrocore process`` of a synthetic log with ``args``, which it refuses (exit status 2)
    without writing its output: the error it printed."""
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    proc = run_cli("process", log, "--out", tmp_path / "h.csv", *args)
    assert proc.returncode == 2, proc.stderr
    assert not (tmp_path / "h.csv").exists()
    return proc.stderr


@pytest.mark.parametrize(
    "args",
    [("demo", "--duration", "1e12"), ("simulate", "--duration", "1e12", "--out", "drive.csv"),
     ("tune", "--sim-drive", "city:1e12")],
)
def test_a_drive_too_long_to_simulate_is_refused_at_once(tmp_path: Path, args: tuple[str, ...]) -> None:
    # the route of such a drive was built manoeuvre by manoeuvre before the sample count was checked
    proc = run_cli(*(str(tmp_path / a) if a.endswith(".csv") else a for a in args))
    assert proc.returncode == 2
    assert "samples requested" in proc.stderr and "more than 1e9; is the duration in seconds?" in proc.stderr
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("profile", ["square", "rotary"])
def test_too_many_runs_to_simulate_are_refused_at_once(tmp_path: Path, profile: str) -> None:
    # a billion runs were built one by one before the sample count was checked (not ended in 120 s)
    out = tmp_path / "drive.csv"
    proc = run_cli("simulate", "--profile", profile, "--runs", "1000000000", "--out", out)
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"gyrocore: error: --runs 1000000000 of the {profile} profile: ")
    assert "samples requested" in proc.stderr and "Traceback" not in proc.stderr
    assert not out.exists()
    # a sensible count still runs
    assert run_cli("simulate", "--profile", profile, "--runs", "2", "--out", out).returncode == 0
    assert out.exists()


@pytest.mark.parametrize(
    ("args", "message"),
    [(("--profile", "robot", "--duration", "100"), "--duration applies to the car profile only, not to --profile robot"),
     (("--profile", "square", "--mix", "city"), "--mix applies to the car profile only, not to --profile square"),
     (("--profile", "car", "--runs", "3"),
      "--runs applies to the square and rotary profiles only, not to --profile car")],
)
def test_an_option_the_simulated_profile_does_not_take_is_refused(
    tmp_path: Path, args: tuple[str, ...], message: str
) -> None:
    # it was ignored without a word: a robot run of 100 s came out as the paper's 160 s
    out = tmp_path / "drive.csv"
    proc = run_cli("simulate", *args, "--out", out)
    assert proc.returncode == 2
    assert proc.stderr == f"gyrocore: error: {message}\n"
    assert not out.exists()


def test_a_rate_random_walk_without_a_kalibr_file_is_refused() -> None:
    # --rrw only goes into --kalibr's YAML; alone it was accepted and did nothing
    proc = run_cli("allan", real_log_path("broad_10"), "--rrw", "1e-5")
    assert proc.returncode == 2
    assert proc.stderr == ("gyrocore: error: --rrw is the rate random walk written by --kalibr: give --kalibr FILE "
                           "too, or leave --rrw out\n")


def test_simulated_fixes_at_an_absurd_rate_are_refused_at_once() -> None:
    # 1e9 Hz over the log's two minutes asked numpy for 1.3e11 fixes, and the command did not end
    proc = run_cli("evaluate", real_log_path("f110_ds3"), "--sim-fixes", "rate=1e9")
    assert proc.returncode == 2
    assert re.fullmatch(rf"gyrocore: error: {re.escape(str(real_log_path('f110_ds3')))}: \S+ fixes requested \(\S+ s at 1e\+09 Hz\): more than "
                        r"1e\+07; is the rate in Hz\?\n", proc.stderr)


@pytest.mark.filterwarnings("ignore:the fixes' sigma is 1 rad")  # a sigma of 1 rad is the point here, not its size
def test_fixes_of_one_int_sigma_are_fused() -> None:
    # one sigma given as an int made an int64 array, which the core refused as "type mismatch"
    t = np.arange(0.0, 10.0, 0.01)
    as_int = fixes.fuse(t, np.zeros_like(t), fixes.Fixes.of([1.0, 2.0], [0.1, 0.2], 1))
    as_float = fixes.fuse(t, np.zeros_like(t), fixes.Fixes.of([1.0, 2.0], [0.1, 0.2], 1.0))
    assert np.array_equal(as_int.heading, as_float.heading)
    with pytest.raises(TypeError, match="fix sigma must hold real numbers, got dtype bool"):
        fixes.Fixes.of([1.0, 2.0], [0.1, 0.2], True)
    # a (t, heading, sigma) tuple, as gyrocore.process takes it
    assert np.array_equal(fixes.fuse(t, np.zeros_like(t), ([1.0, 2.0], [0.1, 0.2], [1.0, 1.0])).heading, as_float.heading)


@pytest.mark.parametrize("value", ["abc", None, True])
def test_a_fusion_setting_that_is_no_number_is_named(value: object) -> None:
    t = np.arange(0.0, 10.0, 0.01)
    with pytest.raises(TypeError, match=rf"^fusion setting arw = {re.escape(repr(value))}: must be a number"):
        fixes.fuse(t, np.zeros_like(t), fixes.Fixes.empty(), arw=value)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="^fusion setting arw"):
        gyrocore.process(t, np.zeros_like(t), "raw", fixes=fixes.Fixes.empty(), fusion={"arw": value})


def test_a_masked_array_is_not_processed_as_if_unmasked() -> None:
    t = np.arange(0.0, 60.0, 0.01)
    rate = np.ma.masked_array(np.full_like(t, 0.002), mask=t >= 30.0)
    with pytest.raises(ValueError, match=r"^rate is a masked array with 3000 masked value\(s\), the first at index "
                       r"3000: give rate.filled\(numpy.nan\)"):
        gyrocore.process(t, rate, "hdr")
    # nothing masked: the values as they are
    assert np.array_equal(gyrocore.process(t, np.ma.masked_array(rate.data), "hdr").heading,
                          gyrocore.process(t, rate.data, "hdr").heading)


def test_the_static_bias_of_no_samples_is_named() -> None:
    with pytest.raises(ValueError, match=r"^the rest window \[0.0, 1.0\] s of the log \(which has no sample\) holds 0 reading\(s\)"):
        static_bias([], [], (0.0, 1.0))


@pytest.mark.parametrize(("key", "value"), [("threshold_dps", "0.1"), ("bias_dps", (1, 2)), ("initial_heading_deg", "x")])
def test_a_parameter_in_degrees_that_is_no_number_is_named(key: str, value: object) -> None:
    t = np.arange(0.0, 10.0, 0.01)
    with pytest.raises(TypeError, match=rf"^invalid parameter {key} = {re.escape(repr(value))}: must be a number of degrees"):
        gyrocore.process(t, np.zeros_like(t), "hdr", **{key: value})


@pytest.mark.parametrize("args", [("--time-col", "t", "--rate-col", "t"), ("--rate-col", "t"), ("--time-col", "gyro_z")])
def test_the_time_column_read_as_the_rate_is_refused(tmp_path: Path, args: tuple[str, ...]) -> None:
    # the times were read as rates too, with only a warning that the rates looked like deg/s
    error = refused_process(tmp_path, *args)
    assert error.startswith("gyrocore: error: the time column ")
    assert "is also a rate column (rate_col, --rate-col; gyro_cols, --gyro-cols): give each its own column" in error


def log_folder_with(tmp_path: Path, name: str, text: str) -> Path:
    """A log folder of a synthetic drive whose file ``name`` holds ``text``."""
    folder = tmp_path / "log"
    folder.mkdir()
    synthetic_csv(folder / "gyro.csv", 3000)
    (folder / name).write_text(text)
    return folder


def test_a_reference_with_no_samples_is_named(tmp_path: Path) -> None:
    folder = log_folder_with(tmp_path, "reference.csv", "t,heading,x,y\n")
    proc = run_cli("evaluate", folder)
    assert proc.returncode == 2
    assert proc.stderr == (f"gyrocore: error: {folder}: reference: 0 sample(s); a heading error needs at least two "
                           "reference samples\n")


def test_a_reference_without_positions_is_evaluated(tmp_path: Path) -> None:
    # the heading is all E_psi needs; x and y were required in a log folder, not in --reference
    folder = log_folder_with(tmp_path, "reference.csv", "t,heading\n1700000000.5,0.1\n1700000010.5,0.2\n1700000020.5,0.3\n")
    proc = run_cli("evaluate", folder, "--preset", "raw", "--json")
    assert proc.returncode == 0, proc.stderr
    assert '"preset": "raw"' in proc.stdout


def test_infinite_times_get_the_one_error_that_names_them(tmp_path: Path) -> None:
    # numpy's "invalid value encountered in subtract" came before it, from the unit check
    log = tmp_path / "inf.csv"
    log.write_text("t,gyro_z\n" + "inf,0.1\n" * 50)
    proc = run_cli("process", log, "--out", tmp_path / "h.csv")
    assert proc.returncode == 2
    assert proc.stderr == f"gyrocore: error: t[0] is inf: samples must be finite (drop or fill them first) ({log}, line 2)\n"


def test_a_reference_with_x_but_no_y_says_its_positions_are_left_out(tmp_path: Path) -> None:
    folder = log_folder_with(tmp_path, "reference.csv",
                             "t,heading,x\n1700000000.5,0.1,0\n1700000010.5,0.2,1\n1700000020.5,0.3,2\n")
    with pytest.warns(UserWarning, match="reference.csv: column x without y: the reference's positions are left out"):
        log = gyrocore.io.read_log(folder)
    assert log.x_ref is None and log.heading_ref is not None
    # a file with its truth in columns: the same rule, the same words
    rows = "".join(f"{i * 0.01:.2f},0.01,0.0,{i}\n" for i in range(500))
    single = tmp_path / "drive.csv"
    single.write_text("t,gyro_z,heading_true,y\n" + rows)
    with pytest.warns(UserWarning, match="drive.csv: column y without x"):
        log = gyrocore.io.read_log(single)
    assert log.x_ref is None and log.heading_ref is not None


def test_a_missing_column_of_a_log_folder_file_says_which_it_needs(tmp_path: Path) -> None:
    folder = log_folder_with(tmp_path, "odometry.csv", "t,v\n1700000000.5,1\n")
    proc = run_cli("process", folder, "--out", tmp_path / "h.csv")
    assert proc.returncode == 2
    # no reading option (--time-col, --rate-col) names the columns of odometry.csv
    assert proc.stderr.endswith("odometry.csv: missing column(s) speed; it has t, v (an odometry file needs the columns "
                                "t, speed)\n")
    # a file given as a reference says what a reference needs, not that it has columns it lacks
    # ("it has t, speed (odometry.csv has the columns t, heading)")
    proc = run_cli("calibrate", folder / "gyro.csv", "--reference", folder / "odometry.csv")
    assert proc.returncode == 2
    assert proc.stderr.endswith("odometry.csv: missing column(s) heading; it has t, v (a reference needs the columns "
                                "t, heading)\n")


@pytest.mark.parametrize("rrw", ["-1", "nan", "0"])
def test_a_rate_random_walk_that_is_no_density_is_not_written(tmp_path: Path, rrw: str) -> None:
    # Kalibr's gyroscope_random_walk was written as -1 or nan
    rng = np.random.default_rng(0)
    log = tmp_path / "rest.csv"
    log.write_text("t,gyro_z\n" + "".join(f"{i * 0.01:.2f},{v:.6f}\n" for i, v in enumerate(rng.normal(0.0, 0.01, 20_000))))
    proc = run_cli("allan", log, "--kalibr", tmp_path / "imu.yaml", "--rrw", rrw)
    assert proc.returncode == 2
    assert proc.stderr.endswith(f"error: argument --rrw: must be a finite number > 0, got {rrw!r}\n")
    assert not (tmp_path / "imu.yaml").exists()


@pytest.mark.parametrize("offset", [-1, "a", 1.5, True])
def test_a_bad_index_offset_is_named_and_changes_nothing(offset: object) -> None:
    t = np.arange(0.0, 10.0, 0.01)
    pipeline, fresh = gyrocore.Pipeline("hdr", bias=0.0), gyrocore.Pipeline("hdr", bias=0.0)
    with pytest.raises(ValueError, match=rf"^index_offset = {re.escape(repr(offset))}: give the index"):
        pipeline.process(t, np.zeros_like(t), index_offset=offset)  # type: ignore[arg-type]
    assert np.array_equal(pipeline.process(t, np.ones_like(t)).heading, fresh.process(t, np.ones_like(t)).heading)


def test_an_output_folder_that_is_a_file_is_named(tmp_path: Path) -> None:
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    taken = tmp_path / "notes.txt"  # not .csv or .parquet: --out names a folder
    taken.write_text("mine")
    proc = run_cli("process", log, "--out", taken)
    assert proc.returncode == 2
    assert proc.stderr == (f"gyrocore: error: {taken}: not a folder, so no outputs can go into it; give a folder, "
                           "or one output file ending in .csv or .parquet\n")
    assert taken.read_text() == "mine"


@pytest.mark.parametrize("t", [[[0.0, 0.01], [0.02]], [0.0, [0.01, 0.02]]], ids=["rows", "a-list-among-numbers"])
def test_a_ragged_list_is_named(t: list[object]) -> None:
    # numpy before 1.24 made it an array of lists: "t must hold real numbers, got dtype object", a
    # TypeError where later numpy gives this ValueError
    with pytest.raises(ValueError, match=r"^t must be one flat sequence of numbers \(setting an array element"):
        gyrocore.process(t, [0.1, 0.2])


@pytest.mark.parametrize(
    ("args", "message"),
    [
        # a bag's topic, given for a CSV file, was ignored without a word
        (("--topic", "/imu"), "topic '/imu' (--topic) picks a ROS bag's Imu topic, and this is a CSV file"),
        # 1e400 reads as infinity, which became a NaN vector and a message about its length
        (("--up", "1e400,0,0"), "up '1e400,0,0': its components must be finite numbers"),
        # a quote cannot separate fields: the whole header was one column, reported as missing ones
        (("--delimiter", '"'), "delimiter '\"' cannot separate fields (it quotes a field or ends a line)"),
        # a wrong delimiter leaves the header one field: say so
        (("--delimiter", ";"), "the header line is one field, with ',' in it: give the file's delimiter "
                               "(delimiter=',', --delimiter ',')"),
    ],
)
def test_a_reading_option_that_does_not_fit_the_input_is_named(
    tmp_path: Path, args: tuple[str, ...], message: str
) -> None:
    error = refused_process(tmp_path, *args)
    assert error.startswith("gyrocore: error: ") and message in error, error


def test_an_odometry_with_a_header_only_is_scored_without_dead_reckoning(tmp_path: Path) -> None:
    # the warning that no odometry sample lies inside the heading indexed the first of none
    folder = log_folder_with(tmp_path, "odometry.csv", "t,speed\n")
    (folder / "reference.csv").write_text("t,heading,x,y\n1700000000.5,0.1,0,0\n1700000010.5,0.2,1,0\n1700000020.5,0.3,2,0\n")
    proc = run_cli("evaluate", folder, "--preset", "raw", "--json")
    assert proc.returncode == 0, proc.stderr
    assert "0 odometry sample(s) (the odometry has none) lie inside the heading's" in proc.stderr
    assert '"position_mean_error_m"' not in proc.stdout


def test_tab_separated_values_are_read_from_a_tsv_file_and_with_delimiter_tab(tmp_path: Path) -> None:
    # a .tsv was "unknown kind of file"; --delimiter '\t' (as a shell passes it) and tab were refused
    # as more than one character, and a tab cannot be typed on a command line
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    tabbed = log.read_text().replace(",", "\t")
    (tmp_path / "log.tsv").write_text(tabbed)
    (tmp_path / "tabs.csv").write_text(tabbed)
    runs = {
        "comma": (log,),
        "tsv": (tmp_path / "log.tsv",),
        "backslash-t": (tmp_path / "tabs.csv", "--delimiter", "\\t"),
        "tab": (tmp_path / "tabs.csv", "--delimiter", "tab"),
    }
    for name, (src, *args) in runs.items():
        proc = run_cli("process", src, "--out", tmp_path / f"{name}.csv", "--preset", "raw", *args)
        assert proc.returncode == 0, (name, proc.stderr)
    assert len({(tmp_path / f"{name}.csv").read_text() for name in runs}) == 1
    # a .tsv whose fields are not tab-separated says which delimiter its header holds
    (tmp_path / "commas.tsv").write_text(log.read_text())
    proc = run_cli("process", tmp_path / "commas.tsv", "--out", tmp_path / "x.csv")
    assert proc.returncode == 2 and "with ',' in it: give the file's delimiter" in proc.stderr, proc.stderr
    (tmp_path / "semi.csv").write_text(log.read_text().replace(",", ";"))
    proc = run_cli("process", tmp_path / "semi.csv", "--out", tmp_path / "x.csv")
    assert "the header line is one field, with ';' in it: give the file's delimiter (delimiter=';', --delimiter ';')" in (
        proc.stderr
    ), proc.stderr


def test_a_space_separated_file_is_told_its_delimiter(tmp_path: Path) -> None:
    # "missing column(s) t, gyro_z; it has t gyro_z" named no delimiter: a space was not among those looked for
    src = tmp_path / "spaces.csv"
    src.write_text("t gyro_z\n0 0.1\n0.01 0.1\n0.02 0.1\n")
    proc = run_cli("process", src, "--out", tmp_path / "o.csv", "--preset", "raw")
    assert "the header line is one field, with ' ' in it: give the file's delimiter (delimiter=' ', --delimiter ' ')" in (
        proc.stderr
    ), proc.stderr
    assert run_cli("process", src, "--out", tmp_path / "o.csv", "--preset", "raw", "--delimiter", " ").returncode == 0
    (tmp_path / "one.csv").write_text("yaw rate \n0.1\n")  # one column, a name with a space in it
    proc = run_cli("process", tmp_path / "one.csv", "--out", tmp_path / "p.csv", "--preset", "raw")
    assert "with ' ' in it" in proc.stderr  # one field never holds both columns of a log


def test_a_decimal_comma_is_named_as_such(tmp_path: Path) -> None:
    # '0,005' is not a number, with no word of why: numbers written with a decimal comma
    src = tmp_path / "komma.csv"
    src.write_text("t;gyro_z\n0,000;0,010\n0,005;0,010\n")
    proc = run_cli("process", src, "--out", tmp_path / "o.csv", "--delimiter", ";")
    assert proc.returncode == 2
    assert ("line 2, column 1 (t): '0,000' is not a number (a decimal comma: write numbers with a decimal point, "
            "e.g. tr ',' '.' < old.csv > new.csv)") in proc.stderr, proc.stderr
    src.write_text("t;gyro_z\n0;1,2,3\n")  # not a decimal comma
    proc = run_cli("process", src, "--out", tmp_path / "o.csv", "--delimiter", ";")
    assert "'1,2,3' is not a number\n" in proc.stderr, proc.stderr


def test_a_delimiter_given_for_a_file_that_is_no_csv_is_said_once_naming_it(tmp_path: Path) -> None:
    # --delimiter for a Parquet or .npy file was ignored without a word; the reader's warnings that
    # name their file (a Parquet timestamp's own unit) were printed with its name twice
    pq = pytest.importorskip("pyarrow.parquet")
    import pyarrow as pa

    t = np.arange(0.0, 30.0, 0.01)
    src = tmp_path / "log.parquet"
    pq.write_table(pa.table({"t": (t * 1e9).astype("datetime64[ns]"), "gyro_z": 0.01 + 0 * t}), src)
    proc = run_cli("process", src, "--out", tmp_path / "h.csv", "--delimiter", ";", "--time-unit", "ms")
    assert proc.returncode == 0, proc.stderr
    said = [line for line in proc.stderr.splitlines() if "is not used" in line or "--delimiter" in line]
    assert sorted(said) == [  # each once, in the order sorted() gives
        f"gyrocore: warning: {src}: column t is a timestamp[ns] with its own unit (ns): time_unit 'ms' "
        "(--time-unit) is not used",
        f"gyrocore: warning: {src}: delimiter ';' (--delimiter) separates a CSV file's fields, and this is a "
        "Parquet file: it is read without one",
    ], proc.stderr
    with pytest.warns(gyrocore.InputWarning, match=r"delimiter '\\t' \(--delimiter\) separates a CSV file's fields"):
        gyrocore.read_log(src, delimiter="\t")


def test_out_dash_is_refused_not_made_a_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # `--out -`, standard output on most command lines, made a folder named "-" with the output in it
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    monkeypatch.chdir(tmp_path)
    proc = run_cli("process", log, "--out", "-")
    assert proc.returncode == 2
    assert proc.stderr == ("gyrocore: error: --out -: the headings go to a file (the report goes to standard output): "
                           "give a .csv or .parquet file, or a folder for several inputs\n")
    assert not (tmp_path / "-").exists()
    # a name of spaces (an empty shell variable with a space) made a folder " "; "" wrote into "."
    for blank in (" ", ""):
        proc = run_cli("process", log, "--out", blank)
        assert proc.returncode == 2 and proc.stderr.endswith(
            f"gyrocore process: error: argument -o/--out: {blank!r}: no name (an empty shell variable?); give a .csv "
            "or .parquet file, or a folder for several inputs\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["log.csv"]


@pytest.mark.parametrize("name", ["heading.tsv", "heading.txt", "h.npy"])
def test_an_output_named_like_a_file_of_another_kind_is_refused(tmp_path: Path, name: str) -> None:
    # it became a folder holding log.csv
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    out = tmp_path / name
    proc = run_cli("process", log, "--out", out)
    assert proc.returncode == 2 and not out.exists()
    assert proc.stderr == (f"gyrocore: error: --out {out}: gyrocore writes the headings to a .csv or .parquet file, "
                           f"not {out.suffix}; give one of those, or a folder for the outputs (a folder named {name}: "
                           f"--out {out}/)\n")
    assert run_cli("process", log, "--out", f"{out}/").returncode == 0 and (out / "log.csv").is_file()
