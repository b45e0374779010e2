"""Every input named is accounted for (processed, or failed with its reason), and no output lands in
an input folder: through the command line and process_many."""

from __future__ import annotations

import os
from functools import partial
from pathlib import Path

import pytest

from gyrocore.batch import process_many

from .conftest import gyrocore_cli
from .test_batch import synthetic_csv


gyrocore = partial(gyrocore_cli, timeout=120)


def broken_links(folder: Path) -> dict[str, str]:
    """A dangling symbolic link and a loop, each named like a log, with the reason each must give."""
    folder.mkdir(exist_ok=True)
    (folder / "dangling.csv").symlink_to(folder / "gone.csv")
    (folder / "loop.csv").symlink_to(folder / "loop.csv")
    return {"dangling.csv": "No such file or directory", "loop.csv": "Too many levels of symbolic links"}


def test_broken_links_named_on_the_command_line_fail_with_their_reason(tmp_path: Path) -> None:
    good = synthetic_csv(tmp_path / "good.csv", 300)
    reasons = broken_links(tmp_path / "in")
    named = [tmp_path / "in" / name for name in reasons]
    proc = gyrocore("process", good, *named, "--out", tmp_path / "out", "--preset", "raw")
    assert proc.returncode == 1, proc.stderr
    lines = proc.stdout.splitlines()
    assert lines[-1].startswith("1 of 3 files processed, 2 failed")
    for path, (name, reason) in zip(named, reasons.items()):
        line = next(line for line in lines if name in line)
        assert line.startswith(f"FAILED {path}: a symbolic link to ") and reason in line
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["good.csv"]


def test_broken_links_in_a_folder_are_reported_by_process_many(tmp_path: Path) -> None:
    folder = tmp_path / "logs"
    reasons = broken_links(folder)
    synthetic_csv(folder / "good.csv", 300)
    summary = process_many([folder], out_dir=tmp_path / "out", preset="raw", jobs=2)
    assert [Path(r.input).name for r in summary.files] == ["dangling.csv", "good.csv", "loop.csv"]
    assert [r.ok for r in summary.files] == [False, True, False]
    for report in summary.failed:
        assert reasons[Path(report.input).name] in (report.error or "")


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads a file without read permission")
def test_an_unreadable_file_fails_with_its_reason(tmp_path: Path) -> None:
    locked = synthetic_csv(tmp_path / "locked.csv", 300)
    locked.chmod(0)
    proc = gyrocore("process", locked, synthetic_csv(tmp_path / "good.csv", 300), "--out", tmp_path / "out")
    assert proc.returncode == 1
    assert "permission denied" in next(line for line in proc.stdout.splitlines() if "locked.csv" in line)


def test_a_named_pipe_is_refused_not_waited_on(tmp_path: Path) -> None:
    fifo = tmp_path / "stream.csv"
    os.mkfifo(fifo)
    proc = gyrocore("process", fifo, "--out", tmp_path / "h.csv")
    assert proc.returncode == 2
    assert proc.stderr.strip() == (
        f"gyrocore: error: {fifo}: not a regular file (a named pipe, socket or device); give a file or folder"
    )


@pytest.mark.parametrize("out", ["logs", "logs/headings", "logs/h.csv"])
def test_no_output_is_written_into_an_input_folder(tmp_path: Path, out: str) -> None:
    logs = tmp_path / "logs"
    logs.mkdir()
    synthetic_csv(logs / "a.csv", 300)
    before = sorted(p.name for p in logs.iterdir())
    proc = gyrocore("process", logs, "--out", tmp_path / out, "--format", "parquet")
    assert proc.returncode == 2
    assert proc.stderr == f"gyrocore: error: refusing to write {tmp_path / out} over or inside the input {logs}; " + (
        "write it elsewhere\n"
    )
    assert sorted(p.name for p in logs.iterdir()) == before
    # so a later run over the folder still works
    assert gyrocore("process", logs, "--out", tmp_path / "elsewhere", "--preset", "raw").returncode == 0


def test_an_output_folder_holding_the_inputs_is_refused(tmp_path: Path) -> None:
    synthetic_csv(tmp_path / "a.csv", 300)
    with pytest.raises(ValueError, match=f"refusing to write into {tmp_path}: it holds the input {tmp_path / 'a.csv'}"):
        process_many([str(tmp_path / "*.csv")], out_dir=tmp_path, fmt="parquet")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv"]


def test_other_commands_refuse_to_write_over_or_into_their_input(tmp_path: Path) -> None:
    log = tmp_path / "drive"
    log.mkdir()
    synthetic_csv(log / "gyro.csv", 3000)
    (log / "meta.json").write_text('{"stationary": [1700000000.0, 1700000015.0]}')
    before = {p.name: p.read_bytes() for p in log.iterdir()}
    for args in (
        ("allan", log / "gyro.csv", "--kalibr", log / "gyro.csv"),
        ("allan", log, "--plot", log / "allan.png"),
        ("calibrate", log, "--save", log / "meta.json"),
    ):
        proc = gyrocore(*args)
        assert proc.returncode == 2, proc.stderr
        assert proc.stderr.startswith(f"gyrocore: error: refusing to write {args[-1]} over or inside the input")
        assert {p.name: p.read_bytes() for p in log.iterdir()} == before


def test_evaluate_and_tune_refuse_to_write_into_a_log_folder(tmp_path: Path) -> None:
    log = tmp_path / "drive"
    log.mkdir()
    synthetic_csv(log / "gyro.csv", 300)
    for args in (
        ("evaluate", log, "--preset", "raw", "--plot-dir", log / "plots"),
        ("tune", log, "--out", log / "meta.json"),
    ):
        proc = gyrocore(*args)
        assert proc.returncode == 2, proc.stderr
        assert proc.stderr.startswith(f"gyrocore: error: refusing to write {args[-1]} over or inside the input {log}")
    assert sorted(p.name for p in log.iterdir()) == ["gyro.csv"]


def test_a_log_folder_without_gyro_csv_is_named_not_read_as_logs(tmp_path: Path) -> None:
    log = tmp_path / "gm"
    log.mkdir()
    for name in ("odometry.csv", "reference.csv"):
        synthetic_csv(log / name, 300)
    why = f"{log}: not a log folder (no gyro.csv)"
    assert gyrocore("process", log, "--out", tmp_path / "x.csv", code=2).stderr.startswith(f"gyrocore: error: {why}")
    proc = gyrocore("process", log, "--out", tmp_path / "out", code=1)
    assert f"FAILED {why}" in proc.stdout
    assert not (tmp_path / "x.csv").exists() and not list((tmp_path / "out").iterdir())


def test_a_recursive_pattern_takes_each_log_folder_once_and_ends_at_a_loop(tmp_path: Path) -> None:
    # "fleet/**/*.csv" matched a log folder's reference.csv and odometry.csv as logs, sent every
    # log folder's gyro.csv to one output name, and followed a link back to the fleet 40 levels
    # deep. Each log folder is one input, and each file is taken once however it was reached.
    import gyrocore
    from gyrocore.batch import expand_inputs

    fleet = tmp_path / "fleet"
    for name in ("a", "b"):
        gyrocore.datasets.write_sample(fleet / name)
    (fleet / "sub").mkdir()
    synthetic_csv(fleet / "sub" / "drive.csv", 100)
    (fleet / "sub" / "loop").symlink_to(fleet, target_is_directory=True)
    found = expand_inputs([f"{fleet}/**/*.csv"])
    assert [p.relative_to(fleet).as_posix() for p in found] == ["a", "b", "sub/drive.csv"]


def test_a_file_a_pattern_reaches_through_a_loop_is_named_without_it(tmp_path: Path) -> None:
    # its name sorted after the loop's ("x.csv" > "loop"), so the report named it
    # fleet/sub/loop/sub/loop/... forty levels deep, the first name the sorted matches gave
    from gyrocore.batch import expand_inputs

    fleet = tmp_path / "fleet"
    (fleet / "sub").mkdir(parents=True)
    synthetic_csv(fleet / "sub" / "x.csv", 100)
    synthetic_csv(fleet / "sub" / "a.csv", 100)
    (fleet / "sub" / "loop").symlink_to(fleet, target_is_directory=True)
    found = expand_inputs([f"{fleet}/**/*.csv"])
    assert [p.relative_to(fleet).as_posix() for p in found] == ["sub/a.csv", "sub/x.csv"]


def test_a_folder_of_logs_names_the_subfolders_it_does_not_search(tmp_path: Path) -> None:
    from gyrocore import InputWarning
    from gyrocore.batch import expand_inputs

    synthetic_csv(tmp_path / "top.csv", 100)
    (tmp_path / "day1").mkdir()
    synthetic_csv(tmp_path / "day1" / "drive.csv", 100)
    with pytest.warns(InputWarning, match=r"1 subfolder\(s\) not searched \(day1\).*\*\*/\*\.csv"):
        assert [p.name for p in expand_inputs([tmp_path])] == ["top.csv"]


def test_a_partitioned_parquet_dataset_is_told_how_to_give_it(tmp_path: Path) -> None:
    # it said only "no logs in this folder", naming .parquet among what it looks for
    import numpy as np
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = pa.table({"t": np.arange(100) * 0.01, "gyro_z": np.zeros(100), "part": np.repeat([0, 1], 50)})
    pq.write_to_dataset(table, tmp_path / "ds.parquet", partition_cols=["part"])
    proc = gyrocore_cli("process", tmp_path / "ds.parquet", "--out", tmp_path / "h.csv", code=2)
    assert proc.stderr.rstrip().endswith(
        "it holds 2 Parquet file(s) in its subfolders (a partitioned dataset?), and gyrocore reads a log from one "
        f"file: write it as one (pyarrow.parquet.write_table), or give the files ('{tmp_path / 'ds.parquet'}/**/*.parquet') "
        "if each is a log of its own")
    empty = tmp_path / "empty"
    empty.mkdir()
    assert gyrocore_cli("process", empty, "--out", tmp_path / "h.csv", code=2).stderr.rstrip().endswith(
        "log or bag folders)")


def test_a_folder_is_listed_once(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A folder of logs was listed twice, once for its logs and again for its compressed ones: a
    large folder on a network file system paid twice, and a file arriving between the two
    listings was seen by one and not the other."""
    import gzip
    import warnings
    from collections.abc import Iterator

    from gyrocore.batch import expand_inputs

    for name in ("b.csv", "a.csv"):
        synthetic_csv(tmp_path / name, 100)
    (tmp_path / "c.csv.gz").write_bytes(gzip.compress((tmp_path / "a.csv").read_bytes()))
    (tmp_path / "day1").mkdir()
    listed: list[Path] = []
    iterdir = Path.iterdir

    def counted(self: Path) -> Iterator[Path]:
        listed.append(self)
        return iterdir(self)

    monkeypatch.setattr(Path, "iterdir", counted)
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        assert expand_inputs([tmp_path]) == [tmp_path / "a.csv", tmp_path / "b.csv"]
    assert listed.count(tmp_path) == 1
    packed, unsearched = sorted(str(w.message) for w in said)  # what the two listings said, said of one
    assert packed == f"{tmp_path}: 1 compressed log(s) that are not read (c.csv.gz): decompress them first"
    assert unsearched.startswith(f"{tmp_path}: 1 subfolder(s) not searched (day1)")
