"""Hostile files and command lines for ``process``, ``evaluate``, ``calibrate``, ``allan`` and
``simulate``: one line naming the file (or option) and what to do, exit 2, nothing of the user's
overwritten."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from .conftest import DATA, real_log_path
from .test_batch import synthetic_csv
from .test_errors_named import run_cli
from .test_hostile_inputs import log_folder_with
from .test_hostile_paths import REFERENCE


def mac_line_ends(path: Path) -> Path:
    """``path`` rewritten with classic Mac OS line ends (a bare carriage return)."""
    path.write_bytes(path.read_bytes().replace(b"\n", b"\r"))
    return path


def test_a_csv_with_carriage_return_line_ends_says_so(tmp_path: Path) -> None:
    log = mac_line_ends(synthetic_csv(tmp_path / "mac.csv", 3000))
    message = (f"gyrocore: error: {log}: lines end in a bare carriage return (classic Mac OS line ends), not a line "
               "feed: convert them, e.g. tr '\\r' '\\n' < old.csv > new.csv\n")
    for args in (("process", log, "--out", tmp_path / "h.csv"), ("allan", log), ("calibrate", log)):
        proc = run_cli(*args)
        assert (proc.returncode, proc.stderr) == (2, message)
    assert not (tmp_path / "h.csv").exists()


def test_a_reference_with_carriage_return_line_ends_is_named(tmp_path: Path) -> None:
    folder = log_folder_with(tmp_path, "reference.csv", "t,heading\r1700000000.5,0.1\r1700000010.5,0.2\r")
    proc = run_cli("evaluate", folder, "--preset", "raw")
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"gyrocore: error: {folder / 'reference.csv'}: lines end in a bare carriage return")


def test_windows_line_ends_are_read_as_unix_ones(tmp_path: Path) -> None:
    unix = synthetic_csv(tmp_path / "unix.csv", 3000)
    windows = tmp_path / "windows.csv"
    windows.write_bytes(unix.read_bytes().replace(b"\n", b"\r\n"))
    for log in (unix, windows):
        run_cli("process", log, "--out", tmp_path / f"{log.stem}.out.csv", "--columns", "t,heading", code=0)
    assert (tmp_path / "unix.out.csv").read_bytes() == (tmp_path / "windows.out.csv").read_bytes()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("--duration", "0.001"), "--duration 0.001: a car drive begins with a 20 s rest (its static bias test); "
         "give a longer drive"),
        (("--duration", "20"), "--duration 20: a car drive begins with a 20 s rest"),
        (("--duration", "1e15"), "--duration 1e+15 at --rate-hz 10: 1.000e16 samples requested"),
        (("--duration", "100", "--rate-hz", "1e9"), "--duration 100 at --rate-hz 1e+09: 1.000e11 samples requested"),
        (("--profile", "robot", "--rate-hz", "1e12"), "--rate-hz 1e+12: gyro model: invalid parameter rate_hz"),
    ],
)
def test_simulate_names_the_option_that_does_not_fit(tmp_path: Path, args: tuple[str, ...], message: str) -> None:
    proc = run_cli("simulate", "--out", tmp_path / "s.csv", *args)
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"gyrocore: error: {message}") and proc.stderr.count("\n") == 1, proc.stderr
    assert not (tmp_path / "s.csv").exists()


@pytest.mark.parametrize(
    ("yaml", "where"),
    [
        ("rosbag2_bagfile_information:\n  version: 5\n  bad: [unclosed\n    more: x\n",
         "line 4, column 9: expected ',' or ']', but got ':' (while parsing a flow sequence)"),
        ("a: 1\na: 2\n", 'line 2, column 1: found duplicate key "a" with value "2"'),
    ],
)
def test_a_bag_with_broken_metadata_yaml_is_one_line_naming_the_spot(tmp_path: Path, yaml: str, where: str) -> None:
    pytest.importorskip("rosbags.highlevel")
    bag = tmp_path / "bag"
    bag.mkdir()
    (bag / "metadata.yaml").write_text(yaml)
    for args in (("process", bag, "--out", tmp_path / "h.csv"), ("allan", bag)):
        proc = run_cli(*args)
        assert proc.returncode == 2
        assert proc.stderr.count("\n") == 1, proc.stderr
        assert proc.stderr.startswith(f"gyrocore: error: {bag / 'metadata.yaml'}: {where}")
        assert proc.stderr.endswith(f"not valid YAML, so {bag} is not a readable ROS 2 bag; mend the file, or take it "
                                    "from the bag's recording again\n")


def test_a_damaged_bag_s_message_of_several_lines_is_one(tmp_path: Path) -> None:
    pytest.importorskip("rosbags.highlevel")
    bag = tmp_path / "bag"
    bag.mkdir()
    (bag / "metadata.yaml").write_text('a: "\t\x01')  # a character YAML refuses: no line and column
    proc = run_cli("process", bag, "--out", tmp_path / "h.csv")
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1, proc.stderr
    assert proc.stderr.startswith(f"gyrocore: error: {bag}: not a readable ROS bag (")


def _edit_line(path: Path, line: int, text: str) -> Path:
    """``path`` with its line ``line`` (1 is the header) replaced by ``text``."""
    lines = path.read_text().splitlines()
    lines[line - 1] = text
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda lines: _edit_line(lines, 52, "1700000000.5,nan"),
         "rate[50] is NaN: samples must be finite (drop or fill them first) ({log}, line 52)"),
        (lambda lines: _edit_line(lines, 53, "1700000000.0,0.1"),
         "timestamps must strictly increase: t[51] = 1700000000 follows "),
    ],
)
def test_allan_names_the_file_and_line_of_a_bad_sample(tmp_path: Path, edit: object, message: str) -> None:
    log = edit(synthetic_csv(tmp_path / "log.csv", 3000))  # type: ignore[operator]
    proc = run_cli("allan", log)
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"gyrocore: error: {message.format(log=log)}") and proc.stderr.count("\n") == 1
    assert proc.stderr.rstrip().endswith(f"({log}, line {53 if 'increase' in message else 52})")


def test_allan_names_the_file_of_a_record_it_cannot_analyse(tmp_path: Path) -> None:
    log = tmp_path / "short.csv"
    log.write_text("t,gyro_z\n0,0.1\n0.01,0.1\n")
    proc = run_cli("allan", log)
    assert (proc.returncode, proc.stderr) == (2, f"gyrocore: error: {log}: need at least 3 samples for an Allan "
                                                 "deviation, got 2\n")


@pytest.mark.parametrize(
    ("line", "text", "message"),
    [
        (2900, "1700000028.98,nan", "rate[2898] is NaN: samples must be finite (drop or fill them first)"),
        (2900, "1700000028.98,", "rate[2898] is NaN: samples must be finite"),  # an empty rate
        (53, "1700000000.0,0.1", "timestamps must strictly increase: t[51] = 1700000000 follows "),
    ],
)
def test_calibrate_names_the_file_and_line_of_a_bad_sample(tmp_path: Path, line: int, text: str, message: str) -> None:
    log = _edit_line(synthetic_csv(tmp_path / "log.csv", 3000), line, text)
    proc = run_cli("calibrate", log, "--save", tmp_path / "c.json")
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"gyrocore: error: {message}") and proc.stderr.count("\n") == 1, proc.stderr
    assert proc.stderr.rstrip().endswith(f"({log}, line {line})")
    assert not (tmp_path / "c.json").exists()


def test_a_plot_dir_that_is_a_file_is_refused_before_any_work(tmp_path: Path) -> None:
    folder = log_folder_with(tmp_path, "reference.csv", REFERENCE)
    mine = tmp_path / "notes.txt"
    mine.write_text("the user's own file\n")
    proc = run_cli("evaluate", folder, "--preset", "raw", "--plot-dir", mine)
    assert (proc.returncode, proc.stdout) == (2, "")
    assert proc.stderr == (f"gyrocore: error: --plot-dir {mine}: not a folder; give a folder for the plots (one that "
                           "does not exist is made)\n")
    assert mine.read_text() == "the user's own file\n"


def test_calibrate_never_saves_over_its_reference_file(tmp_path: Path) -> None:
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    reference = tmp_path / "reference.json"  # a CSV reference, whatever its file is called
    reference.write_text("t,heading\n1700000000.5,0.1\n1700000010.5,0.2\n1700000020.5,0.3\n")
    before = reference.read_bytes()
    proc = run_cli("calibrate", log, "--reference", reference, "--save", reference, "--overwrite")
    assert proc.returncode == 2
    assert proc.stderr == (f"gyrocore: error: refusing to write {reference} over or inside the input {reference}; "
                           "write it elsewhere\n")
    assert reference.read_bytes() == before


def test_a_parquet_file_with_a_column_twice_is_refused_without_a_line(tmp_path: Path) -> None:
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    path = tmp_path / "twice.parquet"
    column = pa.array([0.0, 0.01, 0.02])
    pq.write_table(pa.Table.from_arrays([column, column, column], names=["t", "gyro_z", "gyro_z"]), path)
    proc = run_cli("process", path, "--out", tmp_path / "h.csv")
    assert (proc.returncode, proc.stderr) == (2, f"gyrocore: error: {path}: column(s) gyro_z appear more than once\n")


@pytest.mark.parametrize("option", ["meta.json", "--params", "--calibration"])
def test_a_json_key_given_twice_is_refused_not_the_last_taken(tmp_path: Path, option: str) -> None:
    if option == "meta.json":
        folder = log_folder_with(tmp_path, "meta.json", '{"stationary": [1700000000, 1700000010], "stationary": [0, 1]}')
        given, args = folder / "meta.json", ("process", folder, "--out", tmp_path / "h.csv")
    elif option == "--params":
        given = tmp_path / "params.json"
        given.write_text('{"format": "gyrocore-params", "version": 1, "name": "a", "name": "b", "preset": "hdr", '
                         '"overrides": {}}')
        args = ("evaluate", log_folder_with(tmp_path, "reference.csv", REFERENCE), "--params", given)
    else:
        given = tmp_path / "calibration.json"
        given.write_text('{"bias": 0.1, "bias": 0.2}')
        args = ("process", synthetic_csv(tmp_path / "log.csv", 3000), "--out", tmp_path / "h.csv", "--calibration", given)
    proc = run_cli(*args)
    key = {"meta.json": "stationary", "--params": "name", "--calibration": "bias"}[option]
    assert (proc.returncode, proc.stderr) == (
        2, f"gyrocore: error: {given}: the key {key!r} is given twice in one object; keep one\n")
    assert not (tmp_path / "h.csv").exists()


def test_an_odometry_error_names_the_odometry_file_once(tmp_path: Path) -> None:
    folder = log_folder_with(tmp_path, "odometry.csv", "t,speed\n1700000000,0\n1700000010,nan\n")
    proc = run_cli("process", folder, "--out", tmp_path / "h.csv")
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"gyrocore: error: {folder / 'odometry.csv'}: line 3, column 2 (speed): nan; "), proc.stderr


@pytest.mark.parametrize("second", ["1700000000.5", "1700000010.5"])  # back in time; repeated
def test_a_reference_out_of_order_names_its_file_and_line(tmp_path: Path, second: str) -> None:
    text = f"t,heading\n1700000010.5,0.1\n{second},0.2\n1700000020.5,0.3\n"
    folder = log_folder_with(tmp_path, "reference.csv", text)
    (tmp_path / "ref.csv").write_text(text)
    # the gyro as a file of its own: a log folder's gyro.csv given alone warns that the folder is left out
    (tmp_path / "drive.csv").write_bytes((folder / "gyro.csv").read_bytes())
    for args, where in ((("evaluate", folder, "--preset", "raw"), folder / "reference.csv"),
                        (("calibrate", tmp_path / "drive.csv", "--reference", tmp_path / "ref.csv"), tmp_path / "ref.csv")):
        proc = run_cli(*args)
        assert (proc.returncode, proc.stderr) == (2, f"gyrocore: error: {where}: line 3, column 1 (t): {second} does not "
                                                     "come after 1700000010.5 on line 2; a reference's times must strictly "
                                                     "increase: sort the file and drop repeated times\n")


def test_a_file_name_with_a_line_break_keeps_the_error_on_one_line(tmp_path: Path) -> None:
    log = _edit_line(synthetic_csv(tmp_path / "drive\nlog.csv", 3000), 52, "1700000000.5,nan")
    proc = run_cli("process", log, "--out", tmp_path / "h.csv")
    assert proc.returncode == 2
    shown = str(log).replace("\n", "\\n")
    assert proc.stderr == ("gyrocore: error: rate[50] is NaN: samples must be finite (drop or fill them first) "
                           f"({shown}, line 52); or keep the file as it is: nonfinite='hold' (--nonfinite hold) "
                           "uses the last usable reading there, 'skip' leaves the sample out\n")


@pytest.mark.parametrize("kalibr", ["same.out", "sub/../same.out"])
def test_allan_refuses_one_file_for_its_plot_and_its_yaml(tmp_path: Path, kalibr: str) -> None:
    (tmp_path / "sub").mkdir()
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    proc = run_cli("allan", log, "--plot", tmp_path / "same.out", "--kalibr", f"{tmp_path}/{kalibr}")
    assert (proc.returncode, proc.stdout) == (2, "")
    assert proc.stderr == (f"gyrocore: error: --plot {tmp_path / 'same.out'} and --kalibr {tmp_path}/{kalibr} are one "
                           "file; give each its own\n")
    assert not (tmp_path / "same.out").exists()


@pytest.mark.parametrize("content", [b"\xef\xbb\xbf", b"\xef\xbb\xbf\r\n", b"\n\n"])
def test_a_csv_of_a_byte_order_mark_alone_has_no_header(tmp_path: Path, content: bytes) -> None:
    log = tmp_path / "empty.csv"
    log.write_bytes(content)
    for args in (("process", log, "--out", tmp_path / "h.csv"), ("allan", log), ("calibrate", log), ("evaluate", log)):
        proc = run_cli(*args)
        assert (proc.returncode, proc.stderr) == (2, f"gyrocore: error: {log}: line 1: no header line (expected column "
                                                     "names)\n")


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("NaN", "{given}: not a valid calibration: bias must be finite, got nan"),  # no calibration gives it
        ("1e30", "--calibration {given}: invalid parameter bias = 1e30: must be finite"),
    ],
)
def test_a_calibration_value_the_pipeline_refuses_names_the_file(tmp_path: Path, value: str, message: str) -> None:
    from gyrocore.calibration import Calibration

    given = tmp_path / "calibration.json"
    Calibration(method="static_bias", bias=0.001).save(given)
    given.write_text(given.read_text().replace('"bias": 0.001', f'"bias": {value}'))
    for args in (("process", synthetic_csv(tmp_path / "log.csv", 3000), "--out", tmp_path / "h.csv"),
                 ("evaluate", log_folder_with(tmp_path, "reference.csv", REFERENCE), "--preset", "raw")):
        proc = run_cli(*args, "--calibration", given)
        assert proc.returncode == 2
        assert proc.stderr.startswith("gyrocore: error: " + message.format(given=given)), proc.stderr


def test_allan_refuses_kalibr_of_another_kind_before_any_work(tmp_path: Path) -> None:
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    proc = run_cli("allan", log, "--kind", "hadamard", "--kalibr", tmp_path / "k.yaml")
    assert (proc.returncode, proc.stdout) == (2, "")  # no report printed before the error
    assert proc.stderr == ("gyrocore: error: --kalibr needs --kind allan (the noise parameters are read off the Allan "
                           "deviation), not --kind hadamard\n")


def test_allan_names_the_log_and_the_window_too_short_for_noise_parameters(tmp_path: Path) -> None:
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    proc = run_cli("allan", log, "--window", "+0", "+0.02")
    assert (proc.returncode, proc.stderr) == (2, f"gyrocore: error: {log}: the curve has 1 taus; need at least 3 to "
                                                 "read slopes (give a longer --window)\n")


@pytest.mark.parametrize("window", [("+0", "+1000"), ("1699999999", "1700000010")])
@pytest.mark.parametrize(("command", "output"), [("calibrate", ("--save", "c.json")), ("allan", ("--kalibr", "c.yaml"))])
def test_calibrate_and_allan_refuse_a_window_outside_the_log(tmp_path: Path, window: tuple[str, str], command: str,
                                                            output: tuple[str, str]) -> None:
    # allan analysed the part inside the log without a word
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    proc = run_cli(command, log, "--window", *window, output[0], tmp_path / output[1],
                   *(("--rrw", "1e-5") if command == "allan" else ()))
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"gyrocore: error: --window {window[0]} .. {window[1]} s reaches outside the log "
                                  "(the log runs from 1700000000 to ")
    assert proc.stderr.endswith("give a window inside it\n") and not (tmp_path / output[1]).exists()


def test_a_failed_line_of_a_batch_stays_one_line(tmp_path: Path) -> None:
    logs = tmp_path / "logs"
    logs.mkdir()
    bad = _edit_line(synthetic_csv(logs / "drive\nlog.csv", 3000), 52, "1700000000.5,nan")
    synthetic_csv(logs / "good.csv", 3000)
    proc = run_cli("process", logs, "--out", tmp_path / "out")
    assert proc.returncode == 1
    shown = str(bad).replace("\n", "\\n")
    assert (f"FAILED rate[50] is NaN: samples must be finite (drop or fill them first) ({shown}, line 52); or keep "
            "the file as it is: nonfinite='hold' (--nonfinite hold) uses the last usable reading there, 'skip' leaves "
            "the sample out\n" in proc.stdout)


def test_a_csv_given_as_a_json_file_is_said_not_to_be_json(tmp_path: Path) -> None:
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    proc = run_cli("process", log, "--out", tmp_path / "h.csv", "--calibration", log)
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"gyrocore: error: {log}: not valid JSON: line 1 column ")


@pytest.mark.parametrize("degrees", [None, "heading_true", "gyro_z"])
def test_evaluate_warns_of_a_reference_heading_or_a_gyro_in_degrees(tmp_path: Path, degrees: str | None) -> None:
    drive = tmp_path / "drive.csv"
    run_cli("simulate", "--out", drive, "--duration", "120", code=0)
    if degrees:  # a column of a simulated log in degrees: the truth never wraps by 360 between two samples
        lines = drive.read_text().splitlines()
        column = lines[0].split(",").index(degrees)
        rows = [line.split(",") for line in lines[1:]]
        for row in rows:
            row[column] = repr(float(row[column]) * 57.29577951308232)
        drive.write_text("\n".join([lines[0], *(",".join(row) for row in rows)]) + "\n")
    proc = run_cli("evaluate", drive, "--preset", "raw", code=0)
    warned = [line for line in proc.stderr.splitlines() if "57.3: " in line]
    assert len(warned) == (1 if degrees else 0), proc.stderr
    if degrees == "heading_true":
        assert warned[0].startswith(f"gyrocore: warning: {drive}: the reference heading changes ")
        assert warned[0].endswith("times as much as the gyro turns, about 180/pi = 57.3: it looks like degrees, and it "
                                  "is read as radians (convert it with numpy.radians); its scores would be wrong")
    if degrees == "gyro_z":
        assert warned[0].startswith(f"gyrocore: warning: {drive}: the gyro turns ")
        assert warned[0].endswith("times as much as the reference heading changes, about 180/pi = 57.3: its rates look "
                                  "like deg/s, and they are read as rad/s (give --rate-unit deg/s); its scores "
                                  "would be wrong")  # it said to convert them with numpy.radians


def test_evaluate_warns_of_a_gentle_real_drive_in_deg_s(tmp_path: Path) -> None:
    # comma_seg40 on the highway: 99 % of its rates lie below 4.8 deg/s, below the pipeline's
    # check of rates in deg/s (20), so the reference was what could tell
    source = DATA / "real" / "comma_seg40"
    if not source.is_dir():
        pytest.skip("../shared/data/real is not beside the checkout")
    log = tmp_path / "comma_dps"
    log.mkdir()
    for name in ("reference.csv", "meta.json"):
        (log / name).write_text((source / name).read_text())
    lines = (source / "gyro.csv").read_text().splitlines()
    rows = [line.split(",") for line in lines[1:]]
    for row in rows:  # t, rate [rad/s]
        row[1] = repr(math.degrees(float(row[1])))
    (log / "gyro.csv").write_text("\n".join([lines[0], *(",".join(row) for row in rows)]) + "\n")
    proc = run_cli("evaluate", log, "--preset", "raw", code=0)
    assert f"gyrocore: warning: {log}: the gyro turns " in proc.stderr, proc.stderr
    assert "57.3" not in run_cli("evaluate", source, "--preset", "raw", code=0).stderr


@pytest.mark.parametrize(
    ("command", "twice", "message"),
    [
        # process ran b.json alone, tune fitted combined, both without a word
        ("process", ("--params", "a.json", "--params", "b.json"), "argument --params: given twice (a.json, then b.json)"),
        ("process", ("-o", "x.csv", "--out", "y.csv"), "argument -o/--out: given twice (x.csv, then y.csv)"),
        ("tune", ("--preset", "hdr", "--preset", "combined"), "argument --preset: given twice (hdr, then combined)"),
        # one value given twice is refused too: argparse's default may be that very value
        ("tune", ("--max-evals", "5", "--max-evals", "5"), "argument --max-evals: given twice (5, then 5)"),
        ("process", ("--bias-window", "0", "1", "--bias-window", "+0", "+2"),
         "argument --bias-window: given twice (0 1, then +0 +2)"),
    ],
)
def test_an_option_of_one_value_given_twice_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], command: str, twice: tuple[str, ...], message: str
) -> None:
    from gyrocore.cli import main

    out = ("-o", str(tmp_path / "h.csv")) if command == "process" and "-o" not in twice else ()
    with pytest.raises(SystemExit) as info:
        main([command, str(tmp_path / "drive.csv"), *out, *twice])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert f"{message}; give it once" in err, err
    assert list(tmp_path.iterdir()) == []


def test_options_meant_to_be_repeated_are_still_taken(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from gyrocore.cli import main

    log = synthetic_csv(tmp_path / "drive.csv", 3000)
    assert main(["process", str(log), "-o", str(tmp_path / "h.csv"), "--param", "gap_limit=3",
                 "--param", "nonfinite=hold", "--bias-duration", "5"]) == 0
    assert (tmp_path / "h.csv").exists()
    assert main(["evaluate", str(real_log_path("f110_ds1")), "--preset", "static_bias", "--preset", "hdr"]) == 0
    out = capsys.readouterr().out
    assert "static_bias" in out and " hdr " in out
