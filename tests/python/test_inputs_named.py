"""Bad input named where it is, in the Python API as on the command line: a bad sample by its file
and line, a log folder's files by their folder, a file given twice, an option by the name the
command takes (not the library's keyword), a path given as text; and outputs written whole."""

from __future__ import annotations

import dataclasses
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import gyrocore

from .conftest import gyrocore_cli, real_log_path


def _write_log(path: Path, t: np.ndarray, rate: np.ndarray) -> Path:
    """A CSV log ``t,gyro_z``, a NaN written as an empty field (as a logger leaves it)."""
    rows = (f"{a!r},{'' if np.isnan(b) else repr(b)}\n" for a, b in zip(t.tolist(), rate.tolist()))
    path.write_text("t,gyro_z\n" + "".join(rows))
    return path


@pytest.mark.parametrize("mode", ["whole", "causal"])
@pytest.mark.parametrize(
    ("bad", "said"),
    [("nan", r"^rate\[498\] is NaN: samples must be finite \(drop or fill them first\) \(.*bad\.csv, line 500\); or "
      r"keep the file as it is: nonfinite='hold' \(--nonfinite hold\) uses the last usable reading there, 'skip' "
      r"leaves the sample out$"),
     ("back", r"^timestamps must strictly increase: t\[600\] = 5 follows 5\.99 \(sort the log and drop duplicate "
      r"timestamps\) \(.*bad\.csv, line 602\)$")],
    ids=["nan", "time-back"],
)
def test_log_process_names_the_file_and_line_of_a_bad_sample(tmp_path: Path, mode: str, bad: str, said: str) -> None:
    """``read_log(FILE).process()`` of a file with a NaN reading or a time going back raised the
    core's error with an index alone (``rate[498] is NaN ...``), where ``gyrocore process FILE``
    names the file and its line: the same words now, from the same code."""
    t, rate = np.arange(1000) * 0.01, np.full(1000, 0.001)
    if bad == "nan":
        rate[498] = np.nan
    else:
        t[600] = 5.0
    log = gyrocore.read_log(_write_log(tmp_path / "bad.csv", t, rate))
    with pytest.raises(gyrocore.SampleError, match=said) as raised:
        log.process(mode=mode)
    assert raised.value.index == (498 if bad == "nan" else 600)
    proc = gyrocore_cli("process", tmp_path / "bad.csv", "--out", tmp_path / "h.csv", code=2, timeout=60)
    assert proc.stderr == f"gyrocore: error: {raised.value}\n"
    # a log built from it with other samples names no line (they are not the file's)
    with pytest.raises(gyrocore.SampleError, match=r"\)$" if bad == "back" else r"leaves the sample out$") as again:
        dataclasses.replace(log, t=log.t[100:], rate=log.rate[100:]).process(mode=mode)
    assert "bad.csv" not in str(again.value)


def test_a_log_folders_bad_sample_is_named_at_its_gyro_csv_line(tmp_path: Path) -> None:
    """A log folder's ``gyro.csv`` is the file named, also with heading fixes (the fused run)."""
    rate = np.full(1000, 0.001)
    rate[10] = np.inf
    folder = tmp_path / "drive"
    folder.mkdir()
    _write_log(folder / "gyro.csv", np.arange(1000) * 0.01, rate)
    log = gyrocore.read_log(folder)
    with pytest.raises(gyrocore.SampleError, match=r"\(.*drive/gyro\.csv, line 12\); or keep the file as it is"):
        log.process(fixes=[(1.0, 0.0, 0.01)])


def _turns_after_the_head(folder: Path) -> Path:
    """A 1 kHz log folder in deg/s (30 and 90 while turning) without reference.csv, whose turns come
    after its first 65,536 samples (:data:`gyrocore.io.units.HEAD_SAMPLES`, 65 s)."""
    t = np.arange(80_000) * 0.001
    rate = np.full(len(t), 0.2)
    for start, level in ((68.0, 30.0), (71.0, 90.0), (74.0, -45.0)):
        rate[(t >= start) & (t < start + 2.0)] = level
    folder.mkdir()
    _write_log(folder / "gyro.csv", t, rate)
    return folder


def test_a_log_folder_in_deg_s_without_reference_is_told_its_unit(tmp_path: Path) -> None:
    """A log folder whose gyro.csv holds deg/s and which has no reference.csv was read without a word
    once its turns came after the first 65,536 samples (the reader judged large rates on those
    alone; ``gyrocore evaluate`` with a reference compared it with the reference and warned): the
    rate alone is judged over the whole log now, as :func:`gyrocore.process` judges an array."""
    folder = _turns_after_the_head(tmp_path / "drive")
    said = ("rates look like deg/s, not rad/s: 99 % of |rate| are below 90, which is 5.16e+03 deg/s if read as rad/s "
            "(convert with numpy.radians); or use rate_unit='deg/s' (--rate-unit deg/s)")
    with pytest.warns(gyrocore.InputWarning, match=f"^{re.escape(f'{folder}/gyro.csv: {said}')}$"):
        log = gyrocore.read_log(folder)
    with pytest.warns(gyrocore.InputWarning, match="rates look like deg/s"):
        gyrocore.process(log.t, log.rate, "raw")  # the check it reuses, on the arrays
    proc = gyrocore_cli("process", folder, "--out", tmp_path / "h.csv", "--bias-duration", "10", code=0, timeout=60)
    assert f"gyrocore: warning: {folder}: {said}\n" in proc.stderr
    # in deg/s it says nothing of the unit
    proc = gyrocore_cli("process", folder, "--out", tmp_path / "h2.csv", "--bias-duration", "10", "--rate-unit", "deg/s",
                        code=0, timeout=60)
    assert "look like" not in proc.stderr


def _gnss_note(folder: Path, apart: str = "") -> str:
    return (f"gyrocore: note: {folder}: the log folder has a gnss.csv, which is not used: --fixes {folder}/gnss.csv "
            f"fuses its course over ground with the gyro as heading fixes{apart}; --no-fixes runs without them and "
            "says nothing of it\n")


def test_a_log_read_in_deg_s_keeps_no_subset_of_its_rates(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The rates' subset a reader keeps to tell a log in deg/s read as rad/s was kept of a log read
    in deg/s too, where nothing is judged on it; it is kept of a log read in rad/s alone."""
    from gyrocore.io import units

    kept: list[int] = []
    keep = units.UnitCheck._keep_subset

    def counted(self: units.UnitCheck, rate: np.ndarray) -> None:
        kept.append(len(rate))
        keep(self, rate)

    monkeypatch.setattr(units.UnitCheck, "_keep_subset", counted)
    t = np.arange(3000) * 0.01
    log = _write_log(tmp_path / "turns.csv", t, 30 * np.sin(t))
    assert len(gyrocore.read_log(log, rate_unit="deg/s").process("raw").heading) == 3000
    assert kept == []
    with pytest.warns(gyrocore.InputWarning, match="rates look like deg/s, not rad/s"):
        gyrocore.read_log(log)
    assert sum(kept) == 3000


def test_a_log_folders_gnss_csv_is_named_with_the_option_that_fuses_it(tmp_path: Path) -> None:
    """``gyrocore evaluate DIR`` and ``gyrocore process DIR`` of a log folder with a gnss.csv and no
    fixes.csv (comma_seg40) ignored its GNSS without a word, though ``--fixes DIR/gnss.csv`` takes
    its E_psi from 116 to 0.9 deg: a note names the option, once per such log, and the scores are
    those of ``--no-fixes``."""
    comma = real_log_path("comma_seg40")
    proc = gyrocore_cli("evaluate", comma, "--preset", "raw", "--json", code=0, timeout=120)
    assert proc.stderr.count("gyrocore: note:") == 1 and _gnss_note(comma) in proc.stderr
    quiet = gyrocore_cli("evaluate", comma, "--preset", "raw", "--json", "--no-fixes", code=0, timeout=120)
    assert "note" not in quiet.stderr and quiet.stdout == proc.stdout  # nothing computed otherwise
    out = tmp_path / "h.csv"
    proc = gyrocore_cli("process", comma, "--out", out, code=0, timeout=120)
    assert proc.stderr.count("gyrocore: note:") == 1 and _gnss_note(comma) in proc.stderr
    proc = gyrocore_cli("process", comma, "--out", tmp_path / "fused.csv", "--fixes", comma / "gnss.csv", code=0,
                        timeout=120)
    assert "note" not in proc.stderr
    # several logs: the option takes one per run, which the note says
    f110 = real_log_path("f110_ds1")
    proc = gyrocore_cli("evaluate", comma, f110, "--preset", "raw", code=0, timeout=120)
    assert proc.stderr.count("gyrocore: note:") == 1
    assert _gnss_note(comma, f" (in a run of {comma} alone)") in proc.stderr
    proc = gyrocore_cli("process", comma, f110, "--out", tmp_path / "outs", code=0, timeout=120)
    assert _gnss_note(comma, f" (in a run of {comma} alone, into one .csv or .parquet file)") in proc.stderr
    assert proc.stderr.count("gyrocore: note:") == 1


def test_a_log_folder_with_fixes_csv_beside_its_gnss_csv_gets_no_note(tmp_path: Path) -> None:
    """The folder's fixes.csv is fused by default: its gnss.csv goes unused with reason."""
    folder = tmp_path / "drive"
    folder.mkdir()
    t = np.arange(3000) * 0.01
    _write_log(folder / "gyro.csv", t, np.full(len(t), 0.001))
    (folder / "fixes.csv").write_text("t,heading,sigma\n5.0,0.0,0.01\n")
    (folder / "gnss.csv").write_text("t,speed,bearing\n5.0,10.0,90.0\n")
    proc = gyrocore_cli("process", folder, "--out", tmp_path / "h.csv", "--bias-duration", "1", code=0, timeout=60)
    assert "note" not in proc.stderr
    (folder / "fixes.csv").unlink()
    proc = gyrocore_cli("process", folder, "--out", tmp_path / "h2.csv", "--bias-duration", "1", code=0, timeout=60)
    assert _gnss_note(folder) in proc.stderr


def test_a_file_named_twice_in_a_batch_is_said(tmp_path: Path) -> None:
    """``gyrocore process a.csv link.csv --out DIR`` (``link.csv`` a link to ``a.csv``; or ``a.csv``
    twice) wrote ``DIR/a.csv`` alone, without a word of ``link.csv`` the user named: each name given
    that is dropped as the same file is now said, as ``evaluate`` says it of a log given twice."""
    from gyrocore import batch

    log = _write_log(tmp_path / "a.csv", np.arange(3000) * 0.01, np.full(3000, 0.001))
    (tmp_path / "link.csv").symlink_to(log.name)
    with pytest.warns(gyrocore.InputWarning, match=f"^{re.escape(str(tmp_path / 'link.csv'))}: the same file as "
                                                    f"{re.escape(str(log))}; it is processed once, as "):
        assert batch.expand_inputs([log, tmp_path / "link.csv"]) == [log]
    proc = gyrocore_cli("process", log, log, "--out", tmp_path / "outs", code=0, timeout=60)
    assert f"gyrocore: warning: {log}: given more than once; it is processed once, as {log}\n" in proc.stderr
    assert [p.name for p in (tmp_path / "outs").iterdir()] == ["a.csv"]
    # a pattern that reaches a file named too says nothing: the user gave the file once by name
    proc = gyrocore_cli("process", log, tmp_path / "a*.csv", "--out", tmp_path / "outs2", code=0, timeout=60)
    assert "warning" not in proc.stderr


@pytest.mark.parametrize("order", ["folder first", "file first"])
def test_a_file_named_and_reached_through_its_folder_is_said_in_either_order(tmp_path: Path, order: str) -> None:
    """``expand_inputs(["logs", "logs/a.csv"])`` warned that ``logs/a.csv`` was given more than once
    (it was named once, and reached once through its folder); ``["logs/a.csv", "logs"]`` said
    nothing. Each order now says how the other came; a link in a folder to a file named is the same
    file, in either order too."""
    from gyrocore import batch

    logs = tmp_path / "logs"
    logs.mkdir()
    a = _write_log(logs / "a.csv", np.arange(10) * 0.01, np.zeros(10))
    _write_log(logs / "b.csv", np.arange(10) * 0.01, np.zeros(10))
    items = [logs, a] if order == "folder first" else [a, logs]
    said = f"{a}: named, and also reached through the folder {logs}; it is processed once"
    with pytest.warns(gyrocore.InputWarning, match=f"^{re.escape(said)}$") as caught:
        assert batch.expand_inputs(items) == [a, logs / "b.csv"]
    assert len(caught) == 1
    links = tmp_path / "links"
    links.mkdir()
    (links / "link.csv").symlink_to(Path("..") / "logs" / "a.csv")
    items = [links, a] if order == "folder first" else [a, links]
    first, second = (links / "link.csv", a) if order == "folder first" else (a, links / "link.csv")
    said = f"{second}: the same file as {first}; it is processed once, as {first}"
    with pytest.warns(gyrocore.InputWarning, match=f"^{re.escape(said)}$"):
        assert batch.expand_inputs(items) == [first]


def test_tune_names_its_sensor_option_for_an_unknown_sensor() -> None:
    """``gyrocore tune --sensor XV3500`` (``tune`` takes the name as text) blamed the rate:
    ``--rate-hz 10: unknown sensor 'XV3500' ...``, an option the user never gave."""
    proc = gyrocore_cli("tune", "--sensor", "XV3500", "--sim-drive", "city:0.5", "--max-evals", "2", code=2, timeout=60)
    assert proc.stderr == ("gyrocore: error: --sensor XV3500: unknown sensor 'XV3500' (did you mean 'xv3500'?); choose "
                           "one of xv3500, crs03, fog\n")


@pytest.mark.parametrize(
    ("field", "value", "said"),
    [("bias_dps", 1e9, "sensor field bias_dps = 1000000000.0: gyro model: invalid parameter bias = 17453292.519943297: "
      "must be within +-2^20; the model takes it in SI units (rad, s, degC)"),
     ("temperature_c", (1e9, 25.0), "sensor field temperature_c[0] = 1000000000.0: gyro model: invalid parameter "
      "temperature.start = 1000000000: must be within +-2^20; the model takes it in SI units (rad, s, degC)"),
     ("jitter_s", 1.0, "sensor field jitter_s = 1.0: gyro model: invalid parameter jitter = 1: must be in "
      "[0, 0.25 / rate_hz] s; the model takes it in SI units (rad, s, degC)")],
    ids=["bias_dps", "temperature_c", "jitter_s"],
)
def test_a_simulated_gyros_field_out_of_range_is_named(field: str, value: object, said: str) -> None:
    """``sim.sensor("crs03", bias_dps=1e9)`` (``car_drive(..., bias_dps=...)``) was refused in the
    core's words alone, ``invalid parameter bias = 17453292.519943297``: another name, in rad/s of a
    field given in deg/s."""
    from gyrocore import sim

    with pytest.raises(ValueError, match=f"^{re.escape(said)}$"):
        sim.sensor("crs03", **{field: value})
    with pytest.raises(ValueError, match=f"^{re.escape(said)}$"):
        sim.car_drive(60.0, **{field: value})


def test_a_simulated_gyro_whose_gain_turns_negative_is_refused_by_its_fields() -> None:
    """Each scale term within its own range, together a gain ``1 + s`` below 0 (a gyro reading
    every turn backwards) was simulated; the refusal names the Python fields, not the core's."""
    from gyrocore import sim

    said = ("sensor fields scale_error = -0.5, scale_asymmetry = 0.0, scale_per_c = 0.01, temperature_c = (-40.0, "
            "25.0), reference_temperature_c = 25.0: the gain 1 + s they make is -0.15 at its lowest; it must be > 0")
    fields = {"scale_error": -0.5, "scale_per_c": 0.01, "temperature_c": (-40.0, 25.0)}
    with pytest.raises(ValueError, match=f"^{re.escape(said)}"):
        sim.car_drive(60.0, **fields)
    assert sim.sensor("crs03", **{**fields, "temperature_c": (0.0, 25.0)}).scale_per_c == 0.01  # gain 0.25: kept


def test_a_calibration_save_that_fails_keeps_the_previous_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """``Calibration.save`` wrote over the file in place (the command line's ``--save`` went through
    a temporary file, the Python API did not): a save that failed once the file was opened (a
    full disk) left it truncated, the previous calibration lost."""
    from gyrocore import calibration

    t = np.arange(300) * 0.01
    cal = calibration.static_bias(t, np.full(300, 0.01), (0.0, 2.5))
    path = tmp_path / "cal.json"
    cal.save(path)
    before = path.read_bytes()

    def full_disk(self: Path, text: str, encoding: str | None = None) -> int:
        with open(self, "w", encoding=encoding):  # opened, so truncated, then no room
            raise OSError(28, "No space left on device")

    monkeypatch.setattr(Path, "write_text", full_disk)
    with pytest.raises(OSError):
        calibration.Calibration(method="static_bias", bias=0.02).save(path)
    monkeypatch.undo()
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["cal.json"]  # no temporary file left
    assert calibration.Calibration.load(path).bias == cal.bias


@pytest.mark.skipif(os.name == "nt", reason="symbolic links and POSIX permission bits")
def test_a_calibration_saved_through_a_link_replaces_the_file_it_leads_to(tmp_path: Path) -> None:
    """``Calibration.save("current.json")``, a link to ``real.json``, renamed its new file over the
    link: the link became a regular file and ``real.json`` kept the old calibration; the new file
    had the umask's permissions where the old one was 0600."""
    from gyrocore import calibration

    real = tmp_path / "cals" / "real.json"
    real.parent.mkdir()
    calibration.Calibration(method="static_bias", bias=0.01).save(real)
    real.chmod(0o600)
    link = tmp_path / "current.json"
    link.symlink_to(Path("cals") / "real.json")
    calibration.Calibration(method="static_bias", bias=0.02).save(link)
    assert link.is_symlink() and os.readlink(link) == str(Path("cals") / "real.json")
    assert calibration.Calibration.load(real).bias == 0.02
    assert real.stat().st_mode & 0o777 == 0o600
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["cals", "current.json", "real.json"]  # no temporary file


@pytest.mark.skipif(os.name == "nt", reason="symbolic links and POSIX permission bits")
def test_an_atomic_output_keeps_the_replaced_files_mode_and_a_new_one_the_umasks(tmp_path: Path) -> None:
    """Every output written whole (``atomic_path``, ``StagedFile``: ``--out``, ``--save``,
    ``ParameterSet.write``) keeps the permission bits of the file it replaces, even one it may not
    write itself (0400); a new file gets the umask's, and a dangling link's target is created."""
    from gyrocore import io

    old = tmp_path / "old.txt"
    old.write_text("old")
    old.chmod(0o400)
    with io.atomic_path(old) as tmp:
        tmp.write_text("new")
    assert old.read_text() == "new" and old.stat().st_mode & 0o777 == 0o400
    umask = os.umask(0o022)
    os.umask(umask)
    with io.atomic_path(tmp_path / "fresh.txt") as tmp:
        tmp.write_text("x")
    assert (tmp_path / "fresh.txt").stat().st_mode & 0o777 == 0o666 & ~umask
    dangling = tmp_path / "dangling.txt"
    dangling.symlink_to("later.txt")
    with io.atomic_path(dangling) as tmp:
        tmp.write_text("y")
    assert dangling.is_symlink() and (tmp_path / "later.txt").read_text() == "y"
    (tmp_path / "nowhere.txt").symlink_to(Path("gone") / "x.txt")
    with pytest.raises(FileNotFoundError, match=f"^{re.escape(str(tmp_path / 'nowhere.txt'))}: a symbolic link to "
                                                f"'gone/x.txt', whose folder {re.escape(str(tmp_path / 'gone'))} "
                                                "does not exist; create it or write elsewhere$"):
        io.StagedFile(tmp_path / "nowhere.txt")


def test_the_command_line_refuses_an_output_link_as_before(tmp_path: Path) -> None:
    """An output that is a link (dangling too) is refused as existing without ``--overwrite``, and
    one that leads to an input is refused even with it: written through the link, it would replace
    the input."""
    log = _write_log(tmp_path / "a.csv", np.arange(300) * 0.01, np.full(300, 0.001))
    (tmp_path / "to-input.json").symlink_to(log.name)
    (tmp_path / "dangling.json").symlink_to("gone.json")
    proc = gyrocore_cli("calibrate", log, "--window", "+0", "+2", "--save", tmp_path / "dangling.json", code=2)
    assert proc.stderr == (f"gyrocore: error: {tmp_path / 'dangling.json'} already exists; pass --overwrite to "
                           "replace it, or write elsewhere (nothing was written)\n")
    proc = gyrocore_cli("calibrate", log, "--window", "+0", "+2", "--save", tmp_path / "to-input.json", "--overwrite",
                        code=2)
    assert proc.stderr == (f"gyrocore: error: refusing to write {tmp_path / 'to-input.json'} over or inside the input "
                           f"{log}; write it elsewhere\n")
    before = log.read_bytes()
    gyrocore_cli("calibrate", log, "--window", "+0", "+2", "--save", tmp_path / "dangling.json", "--overwrite", code=0)
    assert (tmp_path / "dangling.json").is_symlink() and "bias" in (tmp_path / "gone.json").read_text()
    assert log.read_bytes() == before


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes")
@pytest.mark.parametrize("reader", ["read_nmea", "read_gnss_csv", "read_fixes_csv"])
def test_a_fixes_reader_refuses_a_named_pipe(tmp_path: Path, reader: str) -> None:
    """``gyrocore.fixes.read_nmea``, ``read_gnss_csv`` and ``read_fixes_csv`` of a named pipe (a
    receiver's live output) waited for ever, where ``read_fixes_file`` and the command line refuse
    one at once. Run in a process of its own, which a hang cannot stop the tests with."""
    pipe = tmp_path / "gnss.csv"
    os.mkfifo(pipe)
    code = f"from gyrocore import fixes\ntry:\n    fixes.{reader}({str(pipe)!r})\nexcept ValueError as e:\n    print(e)"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert proc.stdout == f"{pipe}: a named pipe, socket or device, not a file\n", proc.stderr


@pytest.mark.parametrize(("reader", "kind"), [("read_fixes_file", "fixes.csv"), ("read_fixes_file", "gnss.csv"),
                                              ("read_fixes_csv", "fixes.csv"), ("read_gnss_csv", "gnss.csv")])
def test_a_fixes_file_is_checked_once_by_each_reader(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                     reader: str, kind: str) -> None:
    """``read_fixes_file`` checked its path (``check_file``) and then called ``read_fixes_csv`` or
    ``read_gnss_csv``, which checked it again: each reader now checks a file once, itself."""
    from gyrocore import fixes, fixes_files

    path = tmp_path / kind
    path.write_text("t,heading,sigma\n0,0.1,0.01\n1,0.2,0.01\n" if kind == "fixes.csv"
                    else "t,speed,bearing\n0,5,10\n1,5,11\n2,5,12\n")
    checked: list[Path] = []
    check_file = fixes_files.check_file

    def counted(p: Path) -> None:
        checked.append(p)
        check_file(p)

    monkeypatch.setattr(fixes_files, "check_file", counted)
    assert len(getattr(fixes, reader)(path).t) >= 2
    assert checked == [path]


def test_read_reference_file_takes_a_path_as_text() -> None:
    """``gyrocore.io.read_reference_file("reference.csv")`` (exported, and documented with a path)
    failed with ``AttributeError: 'str' object has no attribute 'is_file'``."""
    path = real_log_path("f110_ds3") / "reference.csv"
    ref = gyrocore.io.read_reference_file(str(path))
    assert np.array_equal(ref["heading"], gyrocore.io.read_reference_file(path)["heading"])


def test_the_exported_path_helpers_take_paths_as_text(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """``gyrocore.io.is_input``, ``output_format``, ``check_not_input``, ``atomic_path``,
    ``StagedFile`` and ``gyrocore.batch.complete_output``, ``output_paths`` (each in its module's
    ``__all__``) raised ``AttributeError: 'str' object has no attribute ...`` for a path as text."""
    from gyrocore import batch, io

    monkeypatch.chdir(tmp_path)
    _write_log(tmp_path / "a.csv", np.arange(10) * 0.01, np.zeros(10))
    assert io.is_input("a.csv") and batch.complete_output("a.csv")
    assert io.output_format("h.parquet") == "parquet"
    assert batch.output_paths(["a.csv"], "out", "csv") == [Path("out/a.csv")]
    with pytest.raises(ValueError, match="^refusing to write a.csv over or inside the input a.csv"):
        io.check_not_input("a.csv", ["a.csv"])
    with io.atomic_path("x.txt") as tmp:
        tmp.write_text("x")
    assert (tmp_path / "x.txt").read_text() == "x"
    io.StagedFile("y.txt").discard()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "x.txt"]


@pytest.mark.parametrize(("name", "what"), [("reference.csv", "reference heading"), ("gnss.csv", "GNSS receiver log")])
def test_a_log_folders_other_file_given_as_a_log_names_the_folder(tmp_path: Path, name: str, what: str) -> None:
    """``gyrocore process comma_seg40/gnss.csv`` (or its reference.csv) said only ``missing column(s)
    gyro_z; it has t, lat, lon, ...``, as of a broken log; a log folder's gyro.csv given alone is told
    of its folder, and so is now each of its files that holds no gyro."""
    comma = real_log_path("comma_seg40")
    proc = gyrocore_cli("process", comma / name, "--out", tmp_path / "h.csv", code=2, timeout=60)
    assert proc.stderr.startswith(f"gyrocore: warning: {comma / name}: the {what} of the log folder {comma}, not its "
                                  f"gyro (gyro.csv); give the folder ({comma}) to read the log\n"
                                  f"gyrocore: error: {comma / name}: missing column(s) gyro_z; ")


def test_calibrate_names_its_options_in_the_static_bias_error() -> None:
    """``gyrocore calibrate LOG --window +0 +1`` said the window is ``shorter than min_duration = 1 s``
    (and without a rest, ``a shorter min_duration / larger max_rate``): the library's keyword names,
    where the command takes ``--min-duration`` and ``--max-rate-dps``."""
    f110 = real_log_path("f110_ds3")
    proc = gyrocore_cli("calibrate", f110, "--window", "+0", "+1", code=0, timeout=60)
    assert "covers 0.945 s of readings, shorter than --min-duration 1 s: the bias would be mostly noise" in proc.stdout
    proc = gyrocore_cli("calibrate", f110, "--min-duration", "1e9", code=0, timeout=60)
    assert ("within 2.86479 deg/s of zero (give --window T0 T1, or a shorter --min-duration / larger --max-rate-dps "
            "if") in proc.stdout
    assert "min_duration" not in proc.stdout


def test_calibrate_says_its_rest_threshold_in_deg_s_and_the_window_by_its_option(tmp_path: Path) -> None:
    """``gyrocore calibrate LOG --max-rate-dps 1`` where no rest was found said ``within 0.0174533
    rad/s of zero (give the rest window, ...)``: the threshold in another unit than the one given,
    and the rest window by no option's name; the steadiest stretch was ``beyond 0.0174533 rad/s``."""
    rng = np.random.default_rng(3)
    t = np.arange(2000) * 0.01
    steady = _write_log(tmp_path / "steady.csv", t, 0.03 + rng.normal(0, 0.001, len(t)))
    proc = gyrocore_cli("calibrate", steady, "--max-rate-dps", "1", code=2, timeout=60)
    assert proc.stderr.startswith(
        f"gyrocore: error: {steady}: nothing to calibrate from: no rest found: no stretch of at least 1 s where the "
        "rate is as steady as the log's quietest blocks and within 1 deg/s of zero (give --window T0 T1, or a "
        "shorter --min-duration / larger --max-rate-dps if this gyro's bias is large); the steadiest stretch, ")
    assert proc.stderr.endswith("as steady as a rest but beyond 1 deg/s: a steady turn, or a rest or straight drive "
                                "with a bias that large (give --window T0 T1)\n")
    assert "rad/s of zero" not in proc.stderr and "rest window" not in proc.stderr
    proc = gyrocore_cli("calibrate", steady, "--max-rate-dps", "2.5", code=0, timeout=60)
    assert "bias = 0.03" in proc.stdout


def test_calibrate_takes_the_block_its_hint_names(tmp_path: Path) -> None:
    """At 10 Hz a 0.25 s block holds 4 readings: a log wholly at rest showed no rest, and the
    error said ``give block=2.4``, a setting ``gyrocore calibrate`` had no option for."""
    rng = np.random.default_rng(2)
    still = tmp_path / "still.csv"
    still.write_text("t,gyro_z\n" + "".join(f"{0.1 * i:.1f},{0.01 + rng.normal(0, 0.002):.6f}\n" for i in range(100)))
    proc = gyrocore_cli("calibrate", still, "--min-duration", "3", code=2, timeout=60)
    assert proc.stderr.rstrip().endswith("give --block 2.4 (25 readings) to find it"), proc.stderr
    proc = gyrocore_cli("calibrate", still, "--min-duration", "3", "--block", "2.4", code=0, timeout=60)
    assert "rest window used: 0.0000 .. 9.9000 s after the first sample (found from the rate)" in proc.stdout
