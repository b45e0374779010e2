"""Reading logs, adversarially: what a file or log folder says, read as it says it, by the Python
API and the command line alike."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import gyrocore

from .conftest import gyrocore_cli


def _drive(n: int = 3000) -> dict[str, np.ndarray]:
    """A 30 s drive: 10 s at rest (speed 0), then a turn at 5 m/s, with its true heading."""
    t = np.arange(n) * 0.01
    rate = np.where(t > 10, 0.2, 0.001)
    return {"t": t, "gyro_z": rate, "speed": np.where(t > 10, 5.0, 0.0), "heading_true": np.cumsum(rate) * 0.01,
            "x": t, "y": 0 * t}


def _write_csv(path: Path, header: list[str], columns: dict[str, np.ndarray]) -> Path:
    rows = zip(*columns.values())
    path.write_text(",".join(header) + "\n" + "".join(",".join(f"{v:.6f}" for v in row) + "\n" for row in rows))
    return path


@pytest.mark.parametrize("kind", ["csv", "parquet"])
def test_a_speed_and_reference_with_their_units_in_the_header_are_read(tmp_path: Path, kind: str) -> None:
    drive = _drive()
    units = ["t [s]", "gyro_z [rad/s]", "speed [m/s]", "heading_true [rad]", "x [m]", "y [m]"]
    if kind == "csv":
        plain = _write_csv(tmp_path / "plain.csv", list(drive), drive)
        stated = _write_csv(tmp_path / "stated.csv", units, drive)
    else:
        pa, pq = pytest.importorskip("pyarrow"), pytest.importorskip("pyarrow.parquet")
        plain, stated = tmp_path / "plain.parquet", tmp_path / "stated.parquet"
        pq.write_table(pa.table(drive), plain)
        pq.write_table(pa.table(dict(zip(units, drive.values()))), stated)
    a, b = gyrocore.read_log(plain), gyrocore.read_log(stated)
    for name in ("speed", "t_odometry", "heading_ref", "x_ref", "y_ref"):
        assert getattr(b, name) is not None, name  # left out without a word
        np.testing.assert_array_equal(getattr(b, name), getattr(a, name))
    # the command line takes its stops as rests, as with the plain names
    for log in (plain, stated):
        proc = gyrocore_cli("process", log, "--out", tmp_path / f"{log.stem}-heading.csv", code=0)
        assert "(speed)" in proc.stdout
    assert "E_psi" in gyrocore_cli("evaluate", stated, code=0).stdout


def test_a_speed_in_another_unit_is_refused(tmp_path: Path) -> None:
    drive = _drive()
    path = _write_csv(tmp_path / "kmh.csv", ["t", "gyro_z", "speed [km/h]"],
                      {k: drive[k] for k in ("t", "gyro_z", "speed")})
    message = f"{path}: column 'speed [km/h]' is in km/h, not m/s: convert it to m/s and name it speed or speed [m/s]"
    with pytest.raises(ValueError) as raised:
        gyrocore.read_log(path)
    assert str(raised.value) == message
    proc = gyrocore_cli("process", path, "--out", tmp_path / "h.csv", code=2)
    assert proc.stderr.strip() == f"gyrocore: error: {message}"


def test_gyro_columns_named_x_y_are_no_track(tmp_path: Path) -> None:
    """A three-axis gyro's columns named x, y, z with their unit are no reference positions."""
    drive = _drive()
    columns = {"t": drive["t"], "x": 0 * drive["t"], "y": 0 * drive["t"], "z": drive["gyro_z"]}
    path = _write_csv(tmp_path / "xyz.csv", ["t", "x [rad/s]", "y [rad/s]", "z [rad/s]"], columns)
    log = gyrocore.read_log(path, rate_col="z")
    assert log.t_ref is None and log.speed is None


NOTES = "# exported by a phone app\n# device: test\n\n"


def test_blank_lines_after_comment_lines_before_the_header_are_skipped(tmp_path: Path) -> None:
    """A logger's notes, a blank line, then the header: the notes were read as the header
    (``missing column(s) t, gyro_z; it has # device: test``)."""
    path = tmp_path / "notes.csv"
    path.write_text(NOTES + "t,gyro_z\n0,0.1\n0.01,0.2\n0.02,abc\n")
    message = f"{path}: line 7, column 2 (gyro_z): 'abc' is not a number"  # the file's own line
    with pytest.raises(ValueError) as raised:
        gyrocore.read_log(path)
    assert str(raised.value) == message
    proc = gyrocore_cli("process", path, "--out", tmp_path / "h.csv", code=2)
    assert proc.stderr.strip() == f"gyrocore: error: {message}"
    path.write_text(NOTES + "\r\n# more\n\nt,gyro_z\n0,0.1\n0.01,0.2\n")
    np.testing.assert_array_equal(gyrocore.read_log(path).rate, [0.1, 0.2])
    # a log folder's other files are read alike
    folder = tmp_path / "drive"
    folder.mkdir()
    drive = _drive()
    _write_csv(folder / "gyro.csv", ["t", "gyro_z"], {k: drive[k] for k in ("t", "gyro_z")})
    (folder / "reference.csv").write_text(NOTES + "t,heading\n0,0\n10,0.5\n20,1.5\n")
    np.testing.assert_array_equal(gyrocore.read_log(folder).heading_ref, [0, 0.5, 1.5])


def test_an_empty_gnss_bearing_is_no_course_as_nan_is(tmp_path: Path) -> None:
    """A receiver at rest logs no course: an empty bearing was an error (``line 3, column 5
    (bearing): empty value``) where ``nan`` is dropped, as :func:`gyrocore.fixes.from_gnss` drops it."""
    from gyrocore.fixes import read_fixes_file, read_gnss_csv

    rows = "0,48.1,11.5,5,90\n1,48.1,11.5,0,{}\n2,48.1,11.5,5,90\n"
    empty, nan = tmp_path / "empty" / "gnss.csv", tmp_path / "nan" / "gnss.csv"
    for path, missing in ((empty, ""), (nan, "nan")):
        path.parent.mkdir()
        path.write_text("t,lat,lon,speed,bearing\n" + rows.format(missing))
    for read in (read_gnss_csv, read_fixes_file):
        a, b = read(empty), read(nan)
        np.testing.assert_array_equal(a.t, [0.0, 2.0])
        np.testing.assert_array_equal(a.heading, b.heading)
    drive = _drive(300)
    log = _write_csv(tmp_path / "drive.csv", ["t", "gyro_z"], {k: drive[k] for k in ("t", "gyro_z")})
    proc = gyrocore_cli("process", log, "--out", tmp_path / "h.csv", "--preset", "raw", "--fixes", empty, code=0)
    assert "fixes from" in proc.stdout


@pytest.mark.parametrize("suffix", [".npy", ".npz"])
def test_npy_and_npz_names_that_state_units_are_honoured(tmp_path: Path, suffix: str) -> None:
    """A field or array named ``gyro_z_dps`` was read as rad/s (57 times too large, and under the
    20 rad/s check: not a word), ``t_ms`` as seconds, and the default ``t`` did not find ``t_ms``."""
    t, rate_dps = np.arange(3000) * 10.0, np.where(np.arange(3000) > 1000, 10.0, 0.0)
    names = {"t_ms": t, "gyro_z_dps": rate_dps}
    path = tmp_path / f"drive{suffix}"
    if suffix == ".npy":
        table = np.zeros(len(t), dtype=[(name, "f8") for name in names])
        for name, values in names.items():
            table[name] = values
        np.save(path, table)
    else:
        np.savez(path, **names)
    for options in ({}, {"time_col": "t_ms", "rate_col": "gyro_z_dps"}, {"time_col": "t", "rate_col": "gyro_z"}):
        log = gyrocore.read_log(path, **options)
        np.testing.assert_allclose(log.t, t / 1e3)
        np.testing.assert_allclose(log.rate, np.radians(rate_dps))
    out = tmp_path / "h.csv"
    gyrocore_cli("process", path, "--out", out, "--preset", "raw", code=0)
    heading = np.loadtxt(out, delimiter=",", skiprows=1, usecols=1)
    assert heading[-1] == pytest.approx(np.radians(10.0) * 19.99, rel=1e-3)


def test_a_parquet_reference_or_fixes_file_is_named_as_parquet(tmp_path: Path) -> None:
    """A reference or fixes file must be CSV text; one in Parquet was told to decompress a .gz file."""
    pa, pq = pytest.importorskip("pyarrow"), pytest.importorskip("pyarrow.parquet")
    from gyrocore.fixes import read_fixes_file

    drive = _drive()
    log = _write_csv(tmp_path / "drive.csv", ["t", "gyro_z", "heading_true"],
                     {k: drive[k] for k in ("t", "gyro_z", "heading_true")})
    ref = tmp_path / "ref.parquet"
    pq.write_table(pa.table({"t": drive["t"], "heading": drive["heading_true"]}), ref)
    message = f"{ref}: not a text CSV file (it is a Parquet file)"
    for read in (gyrocore.io.read_reference_file, read_fixes_file):
        with pytest.raises(ValueError) as raised:
            read(ref)
        assert str(raised.value) == message
    proc = gyrocore_cli("evaluate", log, "--reference", ref, code=2)
    assert proc.stderr.strip() == f"gyrocore: error: {message}"


def test_a_spreadsheet_line_naming_the_delimiter_is_read(tmp_path: Path) -> None:
    """Excel's first line ``sep=;`` was read as the header, and the delimiter it named then left
    ``missing column(s) t, gyro_z; it has sep=, ``: a dead end."""
    path = tmp_path / "excel.csv"
    path.write_bytes(b"\xef\xbb\xbfsep=;\r\nt;gyro_z\r\n0;0.1\r\n0.01;0.2\r\n0.02;abc\r\n")
    message = f"{path}: line 1: 'sep=;' names the file's delimiter, ';', and it is read with ',': give delimiter=';' (--delimiter ';')"
    with pytest.raises(ValueError) as raised:
        gyrocore.read_log(path)
    assert str(raised.value) == message
    assert gyrocore_cli("process", path, "--out", tmp_path / "h.csv", code=2).stderr.strip() == f"gyrocore: error: {message}"
    with pytest.raises(ValueError, match=r"line 5, column 2 \(gyro_z\): 'abc' is not a number"):  # the file's lines
        gyrocore.read_log(path, delimiter=";")
    path.write_text("sep=;\nt;gyro_z\n0;0.1\n0.01;0.2\n")
    np.testing.assert_array_equal(gyrocore.read_log(path, delimiter=";").rate, [0.1, 0.2])
    gyrocore_cli("process", path, "--out", tmp_path / "h.csv", "--delimiter", ";", code=0)


def test_columns_aligned_with_runs_of_spaces_are_named_as_such(tmp_path: Path) -> None:
    """The hint for a one-field header was --delimiter ' ', which splits aligned columns into
    empty ones: ``line 2: 4 fields, but the header has 7``, a dead end."""
    path = tmp_path / "aligned.csv"
    path.write_text("t      gyro_z\n0.00   0.1\n0.01   0.2\n")
    convert = "convert the file, e.g. awk -v OFS=, '{$1=$1; print}' old.csv > new.csv"
    for options, args in (({}, ()), ({"delimiter": " "}, ("--delimiter", " "))):
        with pytest.raises(ValueError) as raised:
            gyrocore.read_log(path, **options)
        assert str(raised.value).endswith(f"{convert})")
        assert "aligned with runs of spaces" in str(raised.value)
        proc = gyrocore_cli("process", path, "--out", tmp_path / "h.csv", *args, code=2)
        assert proc.stderr.strip() == f"gyrocore: error: {raised.value}"


def test_a_last_line_cut_off_is_named_as_such(tmp_path: Path) -> None:
    """A logger stopped mid-line (power lost): the line count alone left the cause to guess."""
    cut = "(the file's last line, cut off: a log whose writing stopped mid-line; delete the line)"
    path = tmp_path / "cut.csv"
    path.write_text("t,gyro_z\n0,0.1\n0.01,0.2\n0.0")
    message = f"{path}: line 4: 1 field, but the header has 2 {cut}"
    with pytest.raises(ValueError) as raised:
        gyrocore.read_log(path)
    assert str(raised.value) == message
    assert gyrocore_cli("process", path, "--out", tmp_path / "h.csv", code=2).stderr.strip() == f"gyrocore: error: {message}"
    path.write_text("t,gyro_z\n0,0.1\n0.0\n0.02,0.2\n")  # a short line among others is no cut
    with pytest.raises(ValueError) as raised:
        gyrocore.read_log(path)
    assert str(raised.value) == f"{path}: line 3: 1 field, but the header has 2"


def test_a_reference_of_a_header_alone_is_not_blamed_on_its_clock(tmp_path: Path) -> None:
    """``gyrocore calibrate`` of a log folder whose reference.csv holds a header and no sample asked
    whether gyro and reference are in the same time base."""
    folder = tmp_path / "drive"
    folder.mkdir()
    drive = _drive()
    _write_csv(folder / "gyro.csv", ["t", "gyro_z"], {k: drive[k] for k in ("t", "gyro_z")})
    (folder / "reference.csv").write_text("t,heading\n")
    proc = gyrocore_cli("calibrate", folder, code=0)
    assert "need at least 3 (the reference has 0 in all)" in proc.stdout, proc.stdout
    assert "time base" not in proc.stdout


@pytest.mark.parametrize("options", [{}, {"rate_col": "gyro_z_deg_s"}, {"rate_col": "gyro_z"}])
def test_a_unit_of_two_words_after_an_underscore_is_read(tmp_path: Path, options: dict[str, str]) -> None:
    """``gyro_z_deg_s`` was split at its last underscore, as ``gyro_z_deg`` in ``s``: by its whole
    name it was read as rad/s (10 deg/s as 10 rad/s, under the 20 rad/s check: not a word), and
    the error of the default column said its name without the unit was ``gyro_z_deg``."""
    drive = _drive()
    dps = np.where(drive["t"] > 10, 10.0, 0.0)
    path = _write_csv(tmp_path / "suffix.csv", ["t", "gyro_z_deg_s"], {"t": drive["t"], "gyro_z_deg_s": dps})
    np.testing.assert_allclose(gyrocore.read_log(path, **options).rate, np.radians(dps), atol=1e-9)
    args = [f"--{k.replace('_', '-')}={v}" for k, v in options.items()]
    gyrocore_cli("process", path, "--out", tmp_path / "h.csv", "--preset", "raw", *args, code=0)
    heading = np.loadtxt(tmp_path / "h.csv", delimiter=",", skiprows=1, usecols=1)
    assert heading[-1] == pytest.approx(np.radians(10.0) * 19.99, rel=1e-3)


def test_a_header_name_of_two_lines_is_named(tmp_path: Path) -> None:
    """A spreadsheet cell of two lines in the header (``"gyro_z<line break>(rad/s)"``): the rest of
    the name was read as the first sample, ``line 2: 1 field, but the header has 2``."""
    path = tmp_path / "cell.csv"
    path.write_text('t,"gyro_z\n(rad/s)"\n0,0.1\n0.01,0.2\n')
    message = (f"{path}: line 1: a quoted column name goes on past the line's end (a line break in a name, as a "
               "spreadsheet cell of two lines writes it): write the header on one line")
    with pytest.raises(ValueError) as raised:
        gyrocore.read_log(path)
    assert str(raised.value) == message
    assert gyrocore_cli("process", path, "--out", tmp_path / "h.csv", code=2).stderr.strip() == f"gyrocore: error: {message}"
    path.write_text('t,gyro_z,"note ""5"""\n0,0.1,x\n0.01,0.2,y\n')  # quotes that close on the line are read
    np.testing.assert_array_equal(gyrocore.read_log(path).rate, [0.1, 0.2])


@pytest.mark.parametrize("spelling", ["NA", "null", "#N/A", "None"])
def test_another_tools_spelling_of_a_missing_value_says_how_to_write_one(tmp_path: Path, spelling: str) -> None:
    # pandas', R's and spreadsheets' spellings of a missing value were "'NA' is not a number" and
    # no more: a missing reading is an empty field or NaN here, which the input policy then takes
    src = tmp_path / "log.csv"
    src.write_text(f"t,gyro_z\n0,0.1\n0.01,{spelling}\n0.02,0.1\n")
    with pytest.raises(ValueError, match=rf"line 3, column 2 \(gyro_z\): '{spelling}' is not a number \(a spelling of "
                       r"a missing reading: leave the field empty or write NaN.*nonfinite='hold' or 'skip'"):
        gyrocore.read_log(src)
    src.write_text(f"t,gyro_z\n0,0.1\n{spelling},0.1\n0.02,0.1\n")
    with pytest.raises(ValueError, match=r"column 1 \(t\): .* \(a spelling of a missing value, and a timestamp cannot "
                       r"be missing: drop the row\)"):
        gyrocore.read_log(src)
    src.write_text("t,gyro_z\n0,0.1\n0.01,\n0.02,0.1\n")  # the empty field, as the message says
    assert np.isnan(gyrocore.read_log(src).rate[1])


@pytest.mark.parametrize(("close_on", "reach"), [(None, "to the end of the file, line 400"), (205, "to line 205")])
def test_a_quote_left_open_is_named_and_the_lines_it_joins_are_not_shown(tmp_path: Path, close_on: int | None,
                                                                         reach: str) -> None:
    # the value shown was the rest of the file, joined by the open quote: 12 kB of one line here
    lines = ["t,gyro_z"] + [f"{0.01 * i:.2f},0.00{i % 10}" for i in range(399)]
    lines[200] = lines[200].replace(",", ',"')
    if close_on is not None:
        lines[close_on - 1] += '"'
    path = tmp_path / "gyro.csv"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError) as e:
        gyrocore.read_log(path)
    said = str(e.value)
    assert said.startswith(f"{path}: line 201, column 2 (gyro_z): a value in quotes runs over the line ends that follow, "
                           f"{reach}: '0.009\\n2.00,0.000\\n")
    assert "a quote left open joins the lines after it into one value: close or delete it" in said
    assert len(said) < 400


def test_a_long_value_that_is_not_a_number_is_shown_by_its_start(tmp_path: Path) -> None:
    path = tmp_path / "gyro.csv"
    path.write_text("t,gyro_z\n0,0\n0.01," + "x" * 5000 + "\n0.02,0\n")
    with pytest.raises(ValueError, match=rf"line 3, column 2 \(gyro_z\): '{'x' * 60}'\.\.\. \(5000 characters\) is not a number$"):
        gyrocore.read_log(path)
