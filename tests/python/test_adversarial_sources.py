"""Inputs found by adversarial testing of the heading-fix sources, ROS bags, log folders and the
tune command: each was a bare Python error naming another function, a misleading message or a
value taken without a word, and is now refused or warned about in words that name it."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import fixes

from .conftest import gyrocore_cli

T = np.arange(10.0)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda path: fixes.read_gnss_csv(path / "gnss.csv", min_sped=1.0),
         "unknown option(s) 'min_sped' (did you mean 'min_speed'?) of read_gnss_csv (from_gnss's); choose from "
         "min_speed, speed_sigma, min_sigma_deg"),
        (lambda path: fixes.read_nmea(path / "gnss.nmea", min_sped=1.0),
         "unknown option(s) 'min_sped' (did you mean 'min_speed'?) of read_nmea (from_gnss's)"),
        (lambda path: fixes.from_latlon(T, np.full(10, 45.0), T * 1e-3, speed_sigma=1.0),
         "unknown option(s) 'speed_sigma' of from_latlon (from_positions's); choose from position_sigma, min_speed, "
         "min_sigma_deg"),
        (lambda path: fixes.fuse(T, np.zeros(10), ([3.0], [0.5], [0.1]), gat=3.0),
         "unknown fusion setting(s) gat (did you mean 'gate'?); choose from"),
    ],
    ids=["read_gnss_csv", "read_nmea", "from_latlon", "fuse"],
)
def test_an_unknown_option_passed_on_is_named_with_the_function_called(
    tmp_path: Path, call: object, message: str
) -> None:
    """``read_gnss_csv(path, min_sped=1)`` was ``from_gnss() got an unexpected keyword argument
    'min_sped'`` (``from_latlon``: ``from_positions() ...``), a function the caller never called,
    with no hint; ``fuse(..., gat=3)`` suggested nothing."""
    (tmp_path / "gnss.csv").write_text("t,speed,bearing\n0,5,10\n1,5,20\n")
    (tmp_path / "gnss.nmea").write_text("$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A\n")
    with pytest.raises(TypeError, match="^" + re.escape(message)):
        call(tmp_path)  # type: ignore[operator]


def _bag_with(path: Path, ros1: bool, topics: dict[str, str], messages: int = 3) -> None:
    """A bag whose ``topics`` (name -> message type) hold ``messages`` messages each, an Imu topic
    none: its connection alone, as a recorder leaves a topic it subscribed to that never spoke."""
    typesys = pytest.importorskip("rosbags.typesys")
    store = typesys.get_typestore(typesys.Stores.ROS1_NOETIC if ros1 else typesys.Stores.ROS2_HUMBLE)
    text = store.types["std_msgs/msg/String"]
    if ros1:
        from rosbags.rosbag1 import Writer
    else:
        from rosbags.rosbag2 import Writer  # type: ignore[assignment]
    with (Writer(path) if ros1 else Writer(path, version=9)) as writer:  # type: ignore[call-arg]
        for topic, msgtype in topics.items():
            connection = writer.add_connection(topic, msgtype, typestore=store)
            if msgtype == "std_msgs/msg/String":
                for k in range(messages):
                    data = text(data="x")
                    raw = store.serialize_ros1(data, msgtype) if ros1 else store.serialize_cdr(data, msgtype)
                    writer.write(connection, 10**18 + k, raw)


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
@pytest.mark.parametrize(
    ("topics", "topic", "message"),
    [
        ({}, None, "no sensor_msgs/msg/Imu topic, and gyrocore reads a bag's gyro from one; the bag has no topic at all"),
        ({"/imu": "std_msgs/msg/String"}, None,
         "no sensor_msgs/msg/Imu topic, and gyrocore reads a bag's gyro from one; the bag has /imu (std_msgs/msg/String)"),
        ({"/imu": "std_msgs/msg/String", "/imu/data": "sensor_msgs/msg/Imu"}, "/imu",
         "/imu carries std_msgs/msg/String, not sensor_msgs/msg/Imu (sensor_msgs/msg/Imu topics: /imu/data)"),
        ({"/imu/data": "sensor_msgs/msg/Imu"}, None,
         "the sensor_msgs/msg/Imu topic /imu/data holds no message, so no samples"),
    ],
    ids=["empty-bag", "no-imu-topic", "topic-of-another-type", "imu-topic-without-messages"],
)
def test_a_bag_without_imu_messages_says_what_it_has(
    tmp_path: Path, ros1: bool, topics: dict[str, str], topic: str | None, message: str
) -> None:
    """An empty bag, or one whose only topic is another type's, said ``give the topic (--topic);
    sensor_msgs/msg/Imu topics: none``, which no topic mends; ``--topic /imu`` of a String topic
    said ``no sensor_msgs/msg/Imu messages on /imu``; an Imu topic that never spoke said ``no
    samples``, naming no topic."""
    path = tmp_path / ("drive.bag" if ros1 else "drive")
    _bag_with(path, ros1, topics)
    with pytest.raises(ValueError, match="^" + re.escape(f"{path}: {message}") + "$"):
        gyrocore.read_log(path, topic=topic)


def test_a_topic_without_its_slash_is_suggested(tmp_path: Path) -> None:
    """``--topic imu`` of a bag whose topic is ``/imu`` named the topics but suggested none."""
    from .test_io import STAMPS, Z, write_bag

    path = tmp_path / "drive.bag"
    write_bag(path, STAMPS, Z, ros1=True, topics=("/imu", "/imu2"))
    proc = gyrocore_cli("process", path, "--topic", "imu", "--out", tmp_path / "h.csv", code=2)
    assert "no sensor_msgs/msg/Imu messages on imu (did you mean '/imu'?)" in proc.stderr
    assert not (tmp_path / "h.csv").exists()


def _log_folder(folder: Path, meta: str) -> Path:
    """A small log folder: 60 s at 100 Hz, at rest for its first 10 s, and ``meta`` as its meta.json."""
    folder.mkdir()
    t = np.arange(0.0, 60.0, 0.01)
    rate = 0.002 + np.where((t > 30) & (t < 40), 0.3, 0.0)
    (folder / "gyro.csv").write_text("t,gyro_z\n" + "".join(f"{a:.2f},{b:.6f}\n" for a, b in zip(t, rate)))
    (folder / "meta.json").write_text(meta)
    return folder


@pytest.mark.parametrize("key", ["rate_unit", "time-unit", "Rate_Col"])
def test_a_reading_option_in_meta_json_is_said_to_be_unread(tmp_path: Path, key: str) -> None:
    """``"rate_unit": "deg/s"`` in meta.json, beside a gyro in deg/s, was left unread without a
    word: the rates were read as rad/s (57 times too large), as any key gyrocore does not read."""
    folder = _log_folder(tmp_path / "drive", f'{{"stationary": [0, 10], "{key}": "deg/s"}}')
    option = key.replace("-", "_").lower()
    with pytest.warns(gyrocore.InputWarning, match=re.escape(
            f"meta.json: the key {key!r} is not read: a log folder's meta.json gives its rest window ('stationary') "
            f"and name; {option} is a reading option: give it to the command (--{option.replace('_', '-')}) or to "
            f"read_log ({option}=)")):
        gyrocore.read_log(folder)


def test_a_key_of_the_users_own_in_meta_json_says_nothing(tmp_path: Path) -> None:
    import warnings

    folder = _log_folder(tmp_path / "drive", '{"stationary": [0, 10], "operator": "bob", "units": "SI"}')
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gyrocore.read_log(folder)


@pytest.mark.parametrize("spec", ["", "=", "=1:2", " =1:2"])
def test_tune_param_without_a_name_says_so(tmp_path: Path, spec: str) -> None:
    """``gyrocore tune --param ''`` said ``unknown parameter(s) ; the pipeline's are ...``, an
    empty name shown as nothing."""
    proc = gyrocore_cli("tune", "--sim-table", "II", f"--param={spec}", code=2, timeout=60)
    assert proc.stderr == f"gyrocore: error: --param {spec!r}: give a parameter's name, NAME or NAME=LOW:HIGH (SI bounds)\n"


def test_fixing_a_parameter_the_preset_fits_by_default_says_how_to_fix_it() -> None:
    """``gyrocore tune --set lowpass_tau=0.1`` (``tune(fixed={"lowpass_tau": 0.1})``) said
    ``lowpass_tau cannot be both fitted and fixed``, though nobody asked to fit it: HDR's fit takes
    it unless told otherwise, and nothing said so."""
    from gyrocore import tune

    with pytest.raises(ValueError, match=re.escape(
            "lowpass_tau cannot be both fitted and fixed: hdr's fit takes hdr_increment, lowpass_tau, "
            "hdr_turn_threshold, hdr_c1, hdr_c2 unless told; name the parameters to fit without it (--param NAME, "
            "names=)")):
        tune.search_box("hdr", fixed={"lowpass_tau": 0.1})
    # named to be fitted and fixed, the error is the short one
    with pytest.raises(ValueError, match=r"^lowpass_tau cannot be both fitted and fixed$"):
        tune.search_box("hdr", names=["lowpass_tau"], fixed={"lowpass_tau": 0.1})
    assert set(tune.search_box("hdr", names=["hdr_c1"], fixed={"lowpass_tau": 0.1})) == {"hdr_c1"}


NMEA = "$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A\n"


@pytest.mark.parametrize("command", ["process", "evaluate"])
def test_nmea_sentences_given_as_fixes_are_named_as_such(tmp_path: Path, command: str) -> None:
    """``--fixes gnss.nmea`` was read as a CSV file: ``a fixes file has the columns ...; its header
    has $GPRMC, 003.1, 01131.000, ...`` (and ``process`` put the log's gyro.csv before the fixes
    file, as if the error were the log's)."""
    folder = _log_folder(tmp_path / "drive", '{"stationary": [0, 10]}')
    (folder / "reference.csv").write_text("t,heading\n0,0\n30,0\n59,0\n")
    nmea = tmp_path / "gnss.nmea"
    nmea.write_text(NMEA)
    out = tmp_path / "h.csv"
    extra = ("--out", out) if command == "process" else ()
    proc = gyrocore_cli(command, folder, "--fixes", nmea, *extra, code=2)
    assert proc.stderr == (
        f"gyrocore: error: {nmea}: NMEA 0183 sentences ($GPRMC,...), not a CSV file of fixes; their times are UTC: "
        "read them with gyrocore.fixes.read_nmea, shift the times onto the gyro's clock, and write them as a fixes.csv "
        "(t,heading,sigma) or give them to process (fixes=)\n")
    assert not out.exists()


def test_an_error_of_a_fixes_file_given_to_process_names_that_file_alone(tmp_path: Path) -> None:
    """``gyrocore process drive --fixes bad.csv`` said ``drive/gyro.csv: bad.csv: line 2, ...``: the
    log's file before the fixes file, as if the error were the log's."""
    folder = _log_folder(tmp_path / "drive", '{"stationary": [0, 10]}')
    bad = tmp_path / "bad.csv"
    bad.write_text("t,heading,sigma\n50,nan,0.05\n")
    proc = gyrocore_cli("process", folder, "--fixes", bad, "--out", tmp_path / "h.csv", code=2)
    assert proc.stderr.startswith(f"gyrocore: error: {bad}: line 2, column 2 (heading): fix 0: heading = NaN"), proc.stderr


@pytest.mark.parametrize(
    ("overrides", "message"),
    [({"hdr": 0.0}, "invalid parameter hdr = 0.0: a switch takes True or False (on the command line true or false), "
                    "not float; hdr is run Heuristic Drift Reduction [bool]"),
     ({"integration": 3}, "invalid parameter integration = 3: takes a name, not int; integration is 'trapezoid' or "
                          "'rectangle'")],
    ids=["switch", "name"],
)
def test_a_switch_or_a_name_given_a_number_says_what_it_takes(overrides: dict[str, object], message: str) -> None:
    """``Pipeline("hdr", hdr=0.0)`` (``--param hdr=0``, ``tune --set hdr=0``) said ``'float' object
    is not an instance of 'bool'``, the binding's words on Python's types."""
    with pytest.raises(TypeError, match="^" + re.escape(message) + "$"):
        gyrocore.Pipeline("hdr", **overrides)  # type: ignore[arg-type]


def test_tune_set_takes_a_switch_as_true_or_false(tmp_path: Path) -> None:
    """``gyrocore tune --set delag=false`` was refused (``the value must be a finite number (SI)``),
    though ``--param delag=false`` takes it and the core's error asked for true or false; a switch
    given something else says that it is one."""
    from gyrocore.cli.tune import _parse_fixed

    assert _parse_fixed(["delag=false", "hdr_c1=2"]) == {"delag": False, "hdr_c1": 2.0}
    with pytest.raises(ValueError, match=re.escape("--set delag=yes: the value must be a finite number (SI) (delag is a "
                                                   "switch: true or false)")):
        _parse_fixed(["delag=yes"])


def test_a_simulated_outage_past_the_log_is_reported_as_far_as_the_log_goes(tmp_path: Path) -> None:
    """``gyrocore evaluate --sim-fixes outage=0:1e300`` scored the log alike, and reported the
    outage as ``[0.000, 1000000000000000052504760255204420248704468581108159154915854115511802457988908195786...``
    (300 digits), its JSON as 1e300."""
    import json

    drive = tmp_path / "drive.csv"
    gyrocore_cli("simulate", "--duration", "60", "--out", drive, code=0)
    last = float(drive.read_text().splitlines()[-1].split(",")[0])
    proc = gyrocore_cli("evaluate", drive, "--preset", "hdr", "--sim-fixes", "rate=1,outage=30:1e300", code=0)
    assert f"outage of {drive}: [{30:.3f}, {last:.3f}) s\n" in proc.stdout, proc.stdout
    report = json.loads(gyrocore_cli("evaluate", drive, "--preset", "hdr", "--sim-fixes", "outage=30:1e300", "--json",
                                     code=0).stdout)
    start, end = report[0]["outage"]
    assert start == 30.0 and last < end < last + 1e-9  # just after the last sample, which it holds


@pytest.mark.parametrize(("bad", "shown"), [(np.inf, "inf"), (-np.inf, "-inf"), (1e300, "1e+300")])
@pytest.mark.parametrize("axis", ["x", "y"])
def test_a_position_that_is_infinite_or_huge_is_named(bad: float, shown: str, axis: str) -> None:
    """``from_positions`` left an infinite position out as if unknown (NaN), and 1e300 gave two fixes
    as confident as any (heading 0, then pi): a corrupt value, as an infinite GNSS bearing is."""
    x, y = 5.0 * T, np.zeros(10)
    (x if axis == "x" else y)[3] = bad
    with pytest.raises(ValueError, match=re.escape(f"positions: {axis}[3] is {shown}: beyond +-2^40 m; a position is "
                                                   "in metres (NaN where it is unknown): drop or repair the sample")):
        fixes.from_positions(T, x, y)
    x[3] = y[3] = np.nan  # unknown there: the steps to and from it give no fix
    assert len(fixes.from_positions(T, x, y)) == 7


def test_one_position_is_said_to_give_no_step() -> None:
    """One position was said to give no fix because "every bearing or position is NaN", which it
    is not: a course needs a step between two positions."""
    with pytest.warns(gyrocore.InputWarning, match="^1 position gives no heading fix: a fix is the course of the step"):
        assert len(fixes.from_positions([0.0], [1.0], [2.0])) == 0


def test_a_log_with_its_own_reference_given_as_a_reference_says_so(tmp_path: Path) -> None:
    """``gyrocore calibrate drive.csv --reference drive.csv`` (a file gyrocore simulate wrote) said
    ``drive.csv: missing column(s) heading; it has t, gyro_z, ..., heading_true, ... (drive.csv has
    the columns t, heading, x, y)``: a claim about the file that was not so, and no word that its
    heading_true is read with the log."""
    drive = tmp_path / "drive.csv"
    drive.write_text("t,gyro_z,heading_true\n0,0.01,0\n0.1,0.01,0.001\n0.2,0.01,0.002\n")
    with pytest.raises(ValueError, match="^" + re.escape(
            f"{drive}: no column heading, and its heading_true makes it a log with its own reference (what gyrocore "
            "simulate writes): give it as the log, whose heading_true is read with it; a reference file has the "
            "columns t, heading [rad] and, where known, x, y [m]") + "$"):
        gyrocore.io.read_reference_file(drive)


@pytest.mark.parametrize(
    ("content", "message"),
    [(NMEA.encode("utf-16"), "text in UTF-16 (or UTF-32), not UTF-8: save it as UTF-8"),
     (b"\x1f\x8b\x08\x00" + bytes(200), "not a text NMEA file (binary data on line 1; decompress a .gz file first)"),
     (bytes(range(256)) * 8, "not a text NMEA file (binary data on line 1; decompress a .gz file first)")],
    ids=["utf-16", "gzip", "binary"],
)
def test_an_nmea_file_that_is_not_text_is_named_as_such(tmp_path: Path, content: bytes, message: str) -> None:
    """``read_nmea`` of a UTF-16, gzip or binary file said ``line 1: not an NMEA sentence (('could
    not parse data', '\\x00\\x01\\x02...'))``, echoing up to 4096 of its bytes."""
    path = tmp_path / "gnss.nmea"
    path.write_bytes(content)
    with pytest.raises(ValueError, match="^" + re.escape(f"{path}: {message}") + "$"):
        fixes.read_nmea(path)


def test_a_long_line_of_no_sentence_among_nmea_sentences_is_shown_short(tmp_path: Path) -> None:
    """A line of no sentence filled the error with up to 4096 characters of it, inside pynmea2's
    tuple of words (binary data among sentences, a serial log's, is skipped:
    tests/python/test_fixes_nmea_receivers.py)."""
    path = tmp_path / "gnss.nmea"
    path.write_bytes(NMEA.encode() + bytes(range(33, 51)) * 200 + b"\n")
    with pytest.raises(ValueError, match=r"line 2: not an NMEA sentence \(could not parse data: '.*\.\.\..*\(\d+ "
                                         r"characters\)\); remove or repair the line$") as error:
        fixes.read_nmea(path)
    assert len(str(error.value)) < 300


@pytest.mark.parametrize(
    ("version", "said"),
    [(2, "version 2, written by a newer gyrocore; this one reads version 1: upgrade gyrocore to read it, or write the "
         "file again with this one"),
     (None, 'without a "version" (this gyrocore writes and reads version 1)'),
     (True, "version True; this gyrocore reads version 1")],
    ids=["newer", "missing", "bool"],
)
def test_a_saved_file_of_another_version_says_what_to_do(tmp_path: Path, version: object, said: str) -> None:
    """A parameter file written by a newer gyrocore said ``parameter file version 2; this gyrocore
    reads 1`` (a calibration ``calibration format version 2 is not supported (this is 1)``), and one
    without a version ``version None``; ``"version": true`` was read as version 1 (True == 1)."""
    import json

    from gyrocore.calibration import Calibration
    from gyrocore.tune import ParameterSet

    params = tmp_path / "p.json"
    ParameterSet("hdr_tuned", "hdr", {"hdr_c1": 2.0}).write(params)
    data = json.loads(params.read_text())
    data.pop("version") if version is None else data.update(version=version)
    params.write_text(json.dumps(data))
    with pytest.raises(ValueError, match="^" + re.escape(f"{params}: parameter file {said}") + "$"):
        ParameterSet.read(params)
    saved = Calibration("static_bias", bias=0.01).to_dict()
    saved.pop("version") if version is None else saved.update(version=version)
    with pytest.raises(ValueError, match="^" + re.escape(f"calibration file {said}") + "$"):
        Calibration.from_dict(saved)


@pytest.mark.parametrize("header", ["t [s],speed [m/s],bearing [deg]", "t,speed (m/s),bearing (°)"])
def test_a_gnss_csv_may_state_its_units(tmp_path: Path, header: str) -> None:
    """A gnss.csv whose header states its units was refused: ``missing column(s) t, speed, bearing;
    it has t [s], speed [m/s], bearing [deg] (... a name may leave out its unit, e.g. t)``, where
    a fixes.csv takes ``t [s]``; another unit is refused, not converted."""
    path = tmp_path / "gnss.csv"
    path.write_text(f"{header}\n0,5,10\n1,5,20\n")
    for read in (fixes.read_gnss_csv, fixes.read_fixes_file):
        assert np.allclose(read(path).heading, np.radians([80.0, 70.0]))
    path.write_text("t,speed [km/h],bearing\n0,5,10\n")
    with pytest.raises(ValueError, match=re.escape("column 'speed [km/h]' is in km/h, not m/s: convert it to m/s and "
                                                   "name it speed or speed [m/s]")):
        fixes.read_fixes_file(path)


def test_a_time_column_or_unit_given_for_a_bag_is_said_to_be_unused(tmp_path: Path) -> None:
    """``gyrocore process drive.bag --time-unit ms`` (``time_col=``) was ignored without a word: a
    bag's messages are read at their header.stamp, as a delimiter given for one is said to be."""
    from .test_io import STAMPS, Z, write_bag

    path = tmp_path / "drive.bag"
    write_bag(path, STAMPS, Z, ros1=True)
    with pytest.warns(gyrocore.InputWarning) as said:
        log = gyrocore.read_log(path, time_unit="ms", time_col="t")
    assert [str(w.message) for w in said] == [
        f"{path}: time_col 't' (--time-col) is not used: a ROS bag's messages are read at their header.stamp "
        "(seconds and nanoseconds)",
        f"{path}: time_unit 'ms' (--time-unit) is not used: a ROS bag's messages are read at their header.stamp "
        "(seconds and nanoseconds)",
    ]
    assert np.array_equal(log.t, gyrocore.read_log(path).t)


@pytest.mark.parametrize("rows", [0, -1, 1.5, "10", True, None])
def test_rows_per_chunk_that_are_no_count_are_refused_at_the_call(tmp_path: Path, rows: object) -> None:
    # 1.5 failed at the first chunk with "'float' object cannot be interpreted as an integer", "10"
    # and None with "'<' not supported between instances", and True read chunks of one row
    path = tmp_path / "a.csv"
    np.savetxt(path, np.column_stack([T, T * 0.01]), delimiter=",", header="t,gyro_z", comments="")
    source = gyrocore.io.open_source(path)
    with pytest.raises(ValueError, match=rf"^rows per chunk must be a whole number >= 1, got {re.escape(repr(rows))}$"):
        source.chunks(rows)  # type: ignore[arg-type]
    assert [len(c) for c in source.chunks(np.int64(4))] == [4, 4, 2]
