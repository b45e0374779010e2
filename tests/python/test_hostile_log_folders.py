"""A log folder's files under hostile input: each bad value named by its file, line and column,
each file's source named where its value is refused, and a reference that scores only part of
the log said so."""

from __future__ import annotations

import json
import re
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import deadreckon

from .test_errors_named import run_cli
from .test_hostile_inputs import log_folder_with

#: Odometry samples inside the synthetic drive of :func:`log_folder_with` (1.7e9 s on, 30 s).
ODOMETRY = ["1700000000.5,0", "1700000010.5,1", "1700000020.5,2"]


@pytest.mark.parametrize(
    ("line", "value", "message"),
    [
        (3, "1700000010.5,nan", "line 3, column 2 (speed): nan; the odometry's t and speed must be finite numbers"),
        (4, "inf,2", "line 4, column 1 (t): inf; the odometry's t and speed must be finite numbers"),
        (4, "1700000010.5,2", "line 4, column 1 (t): 1700000010.5 does not come after 1700000010.5 on line 3; "
                              "the odometry's times must strictly increase"),
        (3, "1700000000.25,1", "line 3, column 1 (t): 1700000000.25 does not come after 1700000000.5 on line 2; "
                               "the odometry's times must strictly increase"),
    ],
)
def test_a_bad_odometry_sample_is_named_by_its_file_line_and_column(
    tmp_path: Path, line: int, value: str, message: str
) -> None:
    # it was "odometry speed: speed[1] is nan", an index, read as the log's
    rows = list(ODOMETRY)
    rows[line - 2] = value
    folder = log_folder_with(tmp_path, "odometry.csv", "t,speed\n" + "\n".join(rows) + "\n")
    where = folder / "odometry.csv"
    with pytest.raises(ValueError, match=f"^{re.escape(f'{where}: {message}')}"):
        gyrocore.read_log(folder)


def test_a_meta_json_with_a_byte_order_mark_is_read(tmp_path: Path) -> None:
    # Windows editors write one; it was "not valid JSON: line 1 column 1: Unexpected UTF-8 BOM"
    folder = log_folder_with(tmp_path, "meta.json", "")
    (folder / "meta.json").write_text('{"name": "drive", "stationary": [1700000001, 1700000010]}', encoding="utf-8-sig")
    log = gyrocore.read_log(folder)
    assert (log.name, log.stationary) == ("drive", (1700000001.0, 1700000010.0))
    # a byte that is not UTF-8 is still named at its offset in the file, the mark counted
    (folder / "meta.json").write_bytes(b'\xef\xbb\xbf{"name": "caf\xe9"}')
    with pytest.raises(ValueError, match=r"meta.json: not UTF-8 text \(at byte offset 16: invalid continuation byte\)"):
        gyrocore.read_log(folder)
    # every JSON file is read so: a parameter file too
    params = tmp_path / "params.json"
    gyrocore.tune.ParameterSet("mine", "hdr", {"hdr_c2": 0.5}).write(params)
    params.write_bytes(b"\xef\xbb\xbf" + params.read_bytes())
    assert gyrocore.tune.ParameterSet.read(params).overrides == {"hdr_c2": 0.5}


@pytest.mark.parametrize(("key", "meant"), [("stationery", "stationary"), ("Stationary", "stationary"), ("Name", "name")])
def test_a_misspelled_meta_json_key_is_named_and_the_users_own_keys_are_not(tmp_path: Path, key: str, meant: str) -> None:
    # the log was read without its rest window, without a word
    folder = log_folder_with(tmp_path, "meta.json", json.dumps({key: [1700000001, 1700000010], "notes": "mine"}))
    with pytest.warns(gyrocore.InputWarning, match=rf"meta\.json: the key '{key}' is not read \(did you mean "
                      rf"'{meant}'\?\); gyrocore reads 'name' and 'stationary'"):
        gyrocore.read_log(folder)
    (folder / "meta.json").write_text(json.dumps({"stationary": [1700000001, 1700000010], "stops": [], "source": "x",
                                                  "notes": "", "stationary_note": "parked", "station": "KOUR",
                                                  "s": 100, "n": 5}))
    with warnings.catch_warnings():  # a key beside the one it resembles is the user's
        warnings.simplefilter("error")
        assert gyrocore.read_log(folder).stationary == (1700000001.0, 1700000010.0)


@pytest.mark.parametrize(
    ("content", "got"),
    [
        ("[1, 2]", "an array: [1, 2]"),
        ("12.5", "a number: 12.5"),
        ('"drive"', 'a string: "drive"'),
        ("null", "null"),
        ("[" + ", ".join(["1000"] * 100) + "]", "an array: [" + "1000, " * 10 + "..."),  # its start
    ],
)
def test_a_meta_json_that_is_no_object_says_what_it_holds(tmp_path: Path, content: str, got: str) -> None:
    folder = log_folder_with(tmp_path, "meta.json", content)
    message = f'{folder / "meta.json"}: expected a JSON object ({{"stationary": ..., "name": ...}}), got {got}'
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        gyrocore.read_log(folder)


#: A reference over the whole synthetic drive of :func:`log_folder_with`.
REFERENCE = "t,heading\n" + "".join(f"{1700000000 + i},0\n" for i in range(31))


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_a_rest_window_outside_the_log_names_meta_json_as_its_source(tmp_path: Path, mode: str) -> None:
    # a window in another time base ([0, 1e12] for a log in epoch seconds) was blamed on the log
    # alone in evaluate ("drive: the bias window ..."), and named meta.json only at its end in process
    folder = log_folder_with(tmp_path, "reference.csv", REFERENCE)
    (folder / "meta.json").write_text('{"stationary": [0, 1e12]}')
    message = (f"{folder / 'meta.json'} (stationary): the bias window [0.0, 1000000000000.0] s starts before the "
               "first sample (t[0] = 1700000000")
    with pytest.raises(gyrocore.RestWindowError, match=f"^{re.escape(message)}"):
        gyrocore.read_log(folder).process("static_bias", mode=mode)
    with pytest.raises(ValueError, match=f"^{re.escape(message)}"):
        gyrocore.evaluate.compare([folder], ["static_bias"], mode=mode)
    # tune planned (whole) or took (causal) the window itself, and named neither meta.json nor the log
    with pytest.raises(gyrocore.RestWindowError, match=f"^{re.escape(message)}"):
        gyrocore.tune.Case.from_log(gyrocore.read_log(folder), mode=mode)
    causal = ("--causal",) if mode == "causal" else ()
    for args in (("evaluate", folder, "--preset", "static_bias"), ("process", folder, "--out", tmp_path / "h.csv"),
                 ("tune", folder, "--no-harm")):
        proc = run_cli(*args, *causal)
        assert proc.returncode == 2 and proc.stderr.startswith(f"gyrocore: error: {message}"), proc.stderr
        assert "give a rest window inside the log, in its own time base" in proc.stderr


#: A rest window from 10 s into the synthetic drive of :func:`log_folder_with` to 70 s past its end.
PAST_THE_END = (1700000010, 1700000100)


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_a_rest_window_past_the_end_is_told_the_clock_it_is_written_in(tmp_path: Path, mode: str) -> None:
    # "write a bound as +T for T seconds after the first sample" was said of meta.json's window
    # too, whose stationary takes plain seconds only
    folder = log_folder_with(tmp_path, "reference.csv", REFERENCE)
    (folder / "meta.json").write_text('{"stationary": [%d, %d]}' % PAST_THE_END)
    span = "the log runs from 1700000000 to 1700000030 s"
    in_clock = f"({span} in its own clock, the one a window in plain seconds is written in); "
    log = gyrocore.read_log(folder)
    meta = f"{folder / 'meta.json'} (stationary): "
    refused = [
        (meta, lambda: log.process("static_bias", mode=mode)),
        (meta, lambda: gyrocore.tune.Case.from_log(log, mode=mode)),
        ("log log: ", lambda: replace(log, path=None).process("static_bias", mode=mode)),  # built in memory
    ]
    for source, run in refused:
        with pytest.raises(gyrocore.RestWindowError) as error:
            run()
        assert str(error.value).startswith(source) and in_clock in str(error.value), str(error.value)
        assert "+T" not in str(error.value)
    # the same window given as bias_window= is told how to write one after the first sample: in
    # Python as two numbers (it refuses "+T", which it was told to write), on the command line as +T
    plus_t = "+0 .. +29."  # the synthetic drive's times jitter
    with pytest.raises(gyrocore.RestWindowError, match=re.escape(f"({span} ({plus_t}")) as error:
        log.process("static_bias", mode=mode, bias_window=PAST_THE_END)
    assert "; a window after the first sample is (t[0] + start, t[0] + end))" in str(error.value)
    assert "+T" not in str(error.value)
    causal = ("--causal",) if mode == "causal" else ()
    given = ("--bias-window", *map(str, PAST_THE_END))
    plus_hint = "; write a bound as +T for T seconds after the first sample)"
    for args, told in ((causal, in_clock), ((*causal, *given), f"({span} ({plus_t}"), ((*causal, *given), plus_hint)):
        proc = run_cli("process", folder, "--out", tmp_path / "h.csv", *args)
        assert proc.returncode == 2 and told in proc.stderr, proc.stderr


def test_a_reference_over_part_of_the_log_warns_naming_both_spans(tmp_path: Path) -> None:
    # it was scored over the overlap alone, and the table showed those scores as the log's
    part = "t,heading\n" + "".join(f"{1700000000 + i},0\n" for i in range(5))  # 4 s of a 30 s drive
    folder = log_folder_with(tmp_path, "reference.csv", part)
    message = re.escape(f"{folder / 'reference.csv'}: the reference covers 4 s of the log's 30 s (13.3 %): it runs from "
                        "t = 1700000000.000 to 1700000004.000 s, the gyro from t = 1700000000.00")
    message += r"\d to 1700000029\.99\d s"  # the synthetic drive's times jitter by up to 1 ms
    with pytest.warns(gyrocore.InputWarning, match=f"^{message}"):
        gyrocore.evaluate.compare([folder], ["raw"])
    proc = run_cli("evaluate", folder, "--preset", "raw")
    assert proc.returncode == 0, proc.stderr
    # named once: by its file, not by the folder again before it
    assert re.match(f"gyrocore: warning: {message}.*; only that part is scored\n", proc.stderr), proc.stderr
    # over half of the log: scored without a word
    (folder / "reference.csv").write_text(REFERENCE.splitlines()[0] + "\n" + "\n".join(REFERENCE.splitlines()[1:17]) + "\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error", gyrocore.InputWarning)
        gyrocore.evaluate.compare([folder], ["raw"])


def test_a_reference_of_two_samples_is_scored_without_numpys_warnings(tmp_path: Path) -> None:
    # the clock-offset check took the mean of no rate steps: "Mean of empty slice" and "invalid
    # value encountered in scalar divide" reached the user beside the span's warning
    folder = log_folder_with(tmp_path, "reference.csv", "t,heading\n1700000001,0\n1700000001.1,0\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        gyrocore.evaluate.compare([folder], ["raw"])
    said = [str(w.message) for w in caught]
    assert not [w for w in caught if not issubclass(w.category, gyrocore.InputWarning)], said
    assert len(said) == 1 and "the reference covers 0.1 s of the log's 30 s" in said[0], said


def test_positions_apart_in_time_name_both_spans() -> None:
    # "the reference has fewer than two samples inside the track's time span" said neither span
    track = deadreckon.dead_reckon(np.array([0.0, 10.0]), np.array([1.0, 1.0]), np.array([0.0, 10.0]), np.zeros(2))
    with pytest.raises(ValueError, match=re.escape(
        "the reference has fewer than two samples inside the track's time span: the reference runs from "
        "t = 1700000000.000 to 1700000010.000 s, the track from t = 0.000 to 10.000 s; give both on the same clock"
    )):
        deadreckon.position_errors(track, [1.7e9, 1.7e9 + 10], [0.0, 1.0], [0.0, 0.0])


@pytest.mark.parametrize(
    ("name", "bare", "stated"),
    [("reference.csv", "t,heading,x,y", "t [s],heading [rad],x [m],y (m)"), ("odometry.csv", "t,speed", "t_s,speed [m/s]")],
)
def test_a_reference_or_odometry_may_state_its_units_as_the_gyro_csv_does(
    tmp_path: Path, name: str, bare: str, stated: str
) -> None:
    """``t [s],heading [rad]`` was ``missing column(s) t, heading; ... (a name may leave out its unit,
    e.g. t)``, where the gyro.csv beside it, a fixes.csv and a gnss.csv take a unit in a name."""
    rows = ["1700000000.5,0.1,0,0", "1700000010.5,0.2,1,0", "1700000020.5,0.3,2,0"] if name == "reference.csv" else ODOMETRY
    scores = []
    for k, header in enumerate((bare, stated)):
        (tmp_path / str(k)).mkdir()
        folder = log_folder_with(tmp_path / str(k), name, header + "\n" + "\n".join(rows) + "\n")
        if name == "odometry.csv":
            (folder / "reference.csv").write_text("t,heading\n1700000000.5,0.1\n1700000020.5,0.3\n")
        proc = run_cli("evaluate", folder, "--preset", "static_bias", "--json")
        assert proc.returncode == 0, proc.stderr
        scores.append(json.loads(proc.stdout)[0]["e_psi_deg"])
    assert scores[0] == scores[1]


def test_a_reference_heading_in_degrees_is_refused_by_its_unit(tmp_path: Path) -> None:
    # it was a missing column heading, with the hint to name it heading: its degrees then read as radians
    folder = log_folder_with(tmp_path, "reference.csv", "t,heading [deg]\n1700000000.5,10\n1700000020.5,20\n")
    proc = run_cli("evaluate", folder, "--preset", "raw")
    assert proc.returncode == 2
    assert proc.stderr == (f"gyrocore: error: {folder / 'reference.csv'}: column 'heading [deg]' is in deg, not rad: "
                           "convert it to rad (numpy.radians for degrees) and name it heading or heading [rad]\n")


@pytest.mark.parametrize(("name", "text"), [("reference.csv", "t;heading\n1700000000.5;0.1\n"),
                                            ("odometry.csv", "t;speed\n1700000000.5;0\n")])
def test_a_reference_or_odometry_of_another_delimiter_is_not_sent_to_the_gyros_option(
    tmp_path: Path, name: str, text: str
) -> None:
    # it said "give the file's delimiter (--delimiter ';')", an option of the gyro's file alone:
    # given, the gyro.csv beside it failed, and this file was still read comma-separated
    folder = log_folder_with(tmp_path, name, text)
    proc = run_cli("evaluate", folder, "--preset", "raw")
    assert proc.returncode == 2
    assert proc.stderr.endswith("the header line is one field, with ';' in it: such a file is read comma-separated: "
                                "separate its fields with ',' (not ';'))\n")
    assert "--delimiter" not in proc.stderr
