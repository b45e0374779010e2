"""Chunked processing of whole files (rows in = rows out, chunk-size invariance, atomic output,
errors located in the file) and batches on threads and on a Dask cluster."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
import warnings
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.csv as pa_csv
import pyarrow.parquet as pq
import pytest

import gyrocore
from gyrocore.batch import expand_inputs, process_file, process_many

from .conftest import real_log_path


def synthetic_csv(path: Path, n: int, *, seed: int = 0, rest: float = 20.0) -> Path:
    """A 100 Hz drive from a Unix epoch: rest, then turns; rate with bias and noise [rad/s]."""
    rng = np.random.default_rng(seed)
    i = np.arange(n)
    t = 1.7e9 + i * 0.01 + rng.uniform(0, 1e-3, n)
    rate = np.where(t - t[0] < rest, 0.0, 0.3 * np.sin(i / 700.0)) + 0.004 + rng.normal(0, 0.01, n)
    pa_csv.write_csv(pa.table({"t": t, "gyro_z": np.round(rate, 7)}), path)
    return path


def read_table(path: Path) -> pa.Table:
    return pq.read_table(path) if path.suffix == ".parquet" else pa_csv.read_csv(path)


def leftovers(folder: Path) -> list[str]:
    return [p.name for p in folder.iterdir() if p.name.endswith(".tmp")]


def test_streamed_file_equals_the_in_memory_pipeline_on_a_real_log(tmp_path: Path) -> None:
    folder = real_log_path("f110_ds3")
    out = tmp_path / "h.csv"
    report = process_file(folder, out, preset="combined", chunk_rows=500)
    assert report.ok and report.rows_in == report.rows_out == 2736
    log = gyrocore.read_log(folder)
    expected = log.process("combined")  # static bias from meta.json's rest window, as the stream
    table = read_table(out)
    for name in ("t", "heading", "rate", "drift"):
        # bit for bit, but for the sign of zero: a CSV writes -0.0 as 0.0
        assert table[name].to_numpy().tobytes() == (getattr(expected, name) + 0.0).tobytes(), name


@pytest.mark.parametrize("fmt", ["csv", "parquet"])
def test_output_does_not_depend_on_the_chunk_size(tmp_path: Path, fmt: str) -> None:
    src = synthetic_csv(tmp_path / "in.csv", 60_000)
    outputs = []
    for rows in (997, 60_000, 1 << 20):
        out = tmp_path / f"h{rows}.{fmt}"
        report = process_file(src, out, preset="recommended", bias_duration=15.0, chunk_rows=rows)
        assert report.rows_in == report.rows_out == 60_000
        outputs.append(read_table(out))
    for other in outputs[1:]:
        assert other.equals(outputs[0])
    assert len(outputs[0]) == 60_000


def test_every_row_is_counted_one_sample_per_chunk(tmp_path: Path) -> None:
    src = synthetic_csv(tmp_path / "in.csv", 300)
    whole = process_file(src, tmp_path / "a.parquet", preset="hdr", bias_duration=1.0)
    single = process_file(src, tmp_path / "b.parquet", preset="hdr", bias_duration=1.0, chunk_rows=1)
    assert whole.rows_out == single.rows_out == 300
    assert read_table(tmp_path / "a.parquet").equals(read_table(tmp_path / "b.parquet"))


def test_units_and_heading_options_reach_the_output(tmp_path: Path) -> None:
    folder = real_log_path("broad_10")
    log = gyrocore.read_log(folder)
    pq.write_table(pa.table({"ms": log.t * 1e3, "dps": np.degrees(log.rate)}), tmp_path / "in.parquet")
    report = process_file(
        tmp_path / "in.parquet",
        tmp_path / "h.parquet",
        preset="static_bias",
        heading="compass",
        time_col="ms",
        rate_col="dps",
        time_unit="ms",
        rate_unit="deg/s",
        bias_window=log.stationary,
    )
    assert report.warnings == ()
    expected = log.process("static_bias")
    table = read_table(tmp_path / "h.parquet")
    np.testing.assert_allclose(table["t"].to_numpy(), log.t, rtol=1e-15)
    np.testing.assert_allclose(table["heading"].to_numpy(), np.pi / 2 - expected.heading, atol=1e-9)
    assert pq.read_schema(tmp_path / "h.parquet").metadata[b"gyrocore"].startswith(b'{"heading": "compass"')


@pytest.mark.parametrize("row", [3456, 3000])  # inside a chunk, and the first row of a chunk
def test_duplicate_timestamp_names_file_global_row_and_line(tmp_path: Path, row: int) -> None:
    lines = [f"{i * 0.01:.2f},0.001" for i in range(5000)]
    lines[row] = lines[row - 1]
    src = tmp_path / "dup.csv"
    src.write_text("t,gyro_z\n" + "\n".join(lines) + "\n")
    out = tmp_path / "h.csv"
    with pytest.raises(ValueError) as e:
        process_file(src, out, preset="raw", chunk_rows=1000)
    message = str(e.value)
    value = f"{(row - 1) * 0.01:.2f}"
    assert message.startswith(f"timestamps must strictly increase: t[{row}] = {value} follows {value}")
    assert message.endswith(f"({src}, line {row + 2})")
    assert not out.exists() and leftovers(tmp_path) == []


def test_bag_stamps_that_go_back_name_the_message(tmp_path: Path) -> None:
    from .test_io import STAMPS, Z, write_bag

    stamps = list(STAMPS[:100])
    stamps[70] = stamps[60]
    write_bag(tmp_path / "back.bag", stamps, Z[:100], ros1=True)
    with pytest.raises(ValueError, match=rf"t\[70\] = .* \({tmp_path / 'back.bag'}, message 70 on /imu\)$"):
        process_file(tmp_path / "back.bag", tmp_path / "h.csv", preset="raw", chunk_rows=32)


def test_nan_rate_names_the_line_or_is_held_and_reported(tmp_path: Path) -> None:
    src = tmp_path / "nan.csv"
    src.write_text("t,gyro_z\n" + "".join(f"{i},{'nan' if i == 70 else 0.001}\n" for i in range(100)))
    with pytest.raises(ValueError, match=rf"rate\[70\] is NaN.*\({src}, line 72\)"):
        process_file(src, tmp_path / "h.csv", preset="raw", chunk_rows=30)
    with pytest.warns(gyrocore.InputWarning, match="replaced by the last usable one"):  # the report's words
        report = process_file(src, tmp_path / "h.csv", preset="raw", chunk_rows=30, nonfinite="hold")
    assert report.rows_out == 100 and any("1 reading(s) not finite or beyond +-2^20 replaced" in w for w in report.warnings)


def test_output_is_never_the_input(tmp_path: Path) -> None:
    src = synthetic_csv(tmp_path / "in.csv", 100)
    before = src.read_bytes()
    with pytest.raises(ValueError, match="refusing to write"):
        process_file(src, src, preset="raw")
    link = tmp_path / "link.csv"
    os.link(src, link)
    with pytest.raises(ValueError, match="refusing to write"):
        process_file(src, link, preset="raw")
    assert src.read_bytes() == before
    with pytest.raises(ValueError, match="refusing to write .* inside the input"):
        process_file(real_log_path("f110_ds3"), real_log_path("f110_ds3") / "heading.csv", preset="raw")


def test_a_failed_run_leaves_the_previous_output_intact(tmp_path: Path) -> None:
    src = tmp_path / "late_error.csv"
    src.write_text("t,gyro_z\n" + "".join(f"{i},0.001\n" for i in range(5000)) + "5000,oops\n")
    out = tmp_path / "h.csv"
    out.write_text("previous\n")
    with pytest.raises(ValueError, match="line 5002, column 2"):
        process_file(src, out, preset="raw", chunk_rows=100)
    assert out.read_text() == "previous\n" and leftovers(tmp_path) == []


def test_an_interrupted_run_writes_nothing(tmp_path: Path) -> None:
    src = synthetic_csv(tmp_path / "in.csv", 20_000)

    def interrupt(done: int, total: int | None, unit: str) -> None:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        process_file(src, tmp_path / "h.csv", preset="raw", chunk_rows=1000, progress=interrupt)
    assert not (tmp_path / "h.csv").exists() and leftovers(tmp_path) == []


def test_a_killed_command_leaves_no_output(tmp_path: Path) -> None:
    src = synthetic_csv(tmp_path / "in.csv", 400_000)
    out = tmp_path / "h.csv"
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "gyrocore.cli",
            "process",
            str(src),
            "--out",
            str(out),
            "--preset",
            "raw",
            "--chunk-rows",
            "2000",
        ],
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 30
    while not leftovers(tmp_path) and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.005)  # wait until the output is being written
    if proc.poll() is not None:
        pytest.skip("the run finished before it could be interrupted")
    proc.send_signal(signal.SIGTERM)
    _, stderr = proc.communicate(timeout=30)
    assert leftovers(tmp_path) == []
    if out.exists():  # the signal came after the rename: then the output is complete
        assert len(read_table(out)) == 400_000
    else:
        assert proc.returncode == 130, stderr
        assert stderr.strip() == "gyrocore: interrupted; no partial output was left"


def test_empty_input_is_an_error_without_output(tmp_path: Path) -> None:
    src = tmp_path / "empty.csv"
    src.write_text("t,gyro_z\n")
    with pytest.raises(ValueError, match="empty.csv: no samples"):
        process_file(src, tmp_path / "h.csv", preset="raw")
    assert not (tmp_path / "h.csv").exists()


def test_missing_rest_window_is_reported(tmp_path: Path) -> None:
    src = synthetic_csv(tmp_path / "in.csv", 500)
    # Causal: no rest window given, so no bias.
    with pytest.warns(UserWarning, match="removes a static bias"):
        report = process_file(src, tmp_path / "h.csv", preset="static_bias", mode="causal")
    assert any(w.endswith("was given: the bias is taken as 0 (on the command line: --bias-window, --bias-duration "
                          "or --bias-dps)") for w in report.warnings), report.warnings
    # A preset with a rest tracker says what the Python pipeline says: 0 until it measures one.
    with pytest.warns(UserWarning, match="removes a static bias"):
        report = process_file(src, tmp_path / "t.csv", preset="tracked", mode="causal")
    assert any("the bias is taken as 0 until the rest tracker measures one at a stop (on the command line" in w
               for w in report.warnings), report.warnings
    # Whole mode finds the rest the file is made of, and says so.
    report = process_file(src, tmp_path / "w.csv", preset="static_bias")
    assert not report.warnings and report.bias_source is not None and "(rate)" in report.bias_source
    assert len(report.rests) == 1 and report.rests[0].bias == pytest.approx(0.004, abs=0.002)


# --- batches -------------------------------------------------------------------------------


@pytest.fixture()
def fleet(tmp_path: Path) -> list[Path]:
    """Three good logs of different formats and one malformed CSV."""
    good = [synthetic_csv(tmp_path / f"drive{k}.csv", 3000 + 1000 * k, seed=k) for k in range(2)]
    table = pa_csv.read_csv(good[0])
    pq.write_table(table, tmp_path / "drive_p.parquet")
    bad = tmp_path / "broken.csv"
    bad.write_text("t,gyro_z\n0,0\n0.01,zero\n")
    return [*good, tmp_path / "drive_p.parquet", bad]


def check_summary(summary: gyrocore.batch.BatchReport, fleet: list[Path], out_dir: Path) -> None:
    assert [r.input for r in summary.files] == [str(p) for p in fleet]
    assert [r.ok for r in summary.files] == [True, True, True, False]
    bad = summary.files[3]
    assert bad.error == f"{fleet[3]}: line 3, column 2 (gyro_z): 'zero' is not a number" and bad.output is None
    for report in summary.succeeded:
        assert report.rows_in == report.rows_out == len(read_table(Path(report.output or "")))
    assert summary.rows_out == 3000 + 4000 + 3000
    assert sorted(p.name for p in out_dir.iterdir()) == ["drive0.csv", "drive1.csv", "drive_p.csv"]
    assert "1 failed" in str(summary) and "FAILED" in str(summary)


def test_batch_on_threads_fails_the_bad_file_alone(fleet: list[Path], tmp_path: Path) -> None:
    summary = process_many(fleet, out_dir=tmp_path / "out", jobs=2, bias_duration=10.0)
    check_summary(summary, fleet, tmp_path / "out")
    one = process_file(fleet[0], tmp_path / "one.csv", bias_duration=10.0)
    assert read_table(tmp_path / "one.csv").equals(read_table(tmp_path / "out" / "drive0.csv"))
    assert one.rows_out == summary.files[0].rows_out


def test_batch_on_a_dask_cluster(fleet: list[Path], tmp_path: Path) -> None:
    distributed = pytest.importorskip("dask.distributed")
    with (
        distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cluster,
        distributed.Client(cluster) as client,
    ):
        summary = process_many(fleet, out_dir=tmp_path / "out", client=client, bias_duration=10.0)
        check_summary(summary, fleet, tmp_path / "out")
        again = process_many(
            fleet[:1], out_dir=tmp_path / "again", client=cluster.scheduler_address, bias_duration=10.0
        )
    assert again.files[0].ok
    assert read_table(tmp_path / "again" / "drive0.csv").equals(read_table(tmp_path / "out" / "drive0.csv"))


@pytest.mark.parametrize("address, said", [
    ("http://127.0.0.1:8787", "scheduler address 'http://127.0.0.1:8787': unknown address scheme 'http'"),
    ("127.0.0.1", "scheduler address '127.0.0.1': missing port number"),
    ("tcp://127.0.0.1:9", "no Dask scheduler answered at 'tcp://127.0.0.1:9'"),
])
def test_a_scheduler_that_cannot_be_reached_is_named_with_what_to_check(fleet: list[Path], tmp_path: Path,
                                                                        address: str, said: str) -> None:
    # Dask's own "Timed out trying to connect" named neither the option nor the address's form.
    # A command of its own: a client that failed to start leaves Dask's event loop unusable for
    # the next one in the same process.
    pytest.importorskip("dask.distributed")
    env = {**os.environ, "DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT": "1s"}
    run = subprocess.run([sys.executable, "-m", "gyrocore", "process", str(fleet[0]), "--scheduler", address,
                          "--out", str(tmp_path / "out"), "--bias-duration", "10"],
                         capture_output=True, text=True, env=env, timeout=120)
    assert run.returncode == 2 and said in run.stderr and "tcp://host:8786" in run.stderr, run.stderr
    assert not (tmp_path / "out").exists() or leftovers(tmp_path / "out") == []


def test_an_interrupted_batch_stops_the_files_running_on_the_cluster(tmp_path: Path,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    # Cancelling a future does not stop a task a worker already runs: the long file went on and
    # wrote its output after the command had said "no partial output was left". Interrupted
    # when the short file is done, the long one stops at its next chunk and leaves nothing.
    distributed = pytest.importorskip("dask.distributed")
    from gyrocore import batch_run

    files = [synthetic_csv(tmp_path / "short.csv", 1000), synthetic_csv(tmp_path / "long.csv", 3_000_000)]

    def interrupt(self: object, n: int = 1) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(batch_run._NoBar, "update", interrupt)
    out = tmp_path / "out"
    with (
        distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cluster,
        distributed.Client(cluster) as client,
    ):
        with pytest.raises(batch_run.BatchInterrupted) as interrupted:
            process_many(files, out_dir=out, client=client, preset="raw", bias=0.0)
        time.sleep(2.0)  # what a running task would still write
        assert not (out / "long.csv").exists()
        assert [p.name for p in out.iterdir()] == ["short.csv"]
    assert [r.output for r in interrupted.value.finished] == [str(out / "short.csv")]


@pytest.mark.parametrize("signal_flag", [False, True])
def test_an_interrupted_batch_says_which_files_it_finished(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, signal_flag: bool
) -> None:
    # Their outputs are complete; without the list a user could only guess which to run again.
    from gyrocore import _signals, batch_run

    files = [synthetic_csv(tmp_path / "short.csv", 1000), synthetic_csv(tmp_path / "long.csv", 3_000_000)]
    monkeypatch.setattr(_signals, "_received", threading.Event())

    def interrupt(self: object, n: int = 1) -> None:
        if signal_flag:  # as a signal's handler does: the running file then stops with a KeyboardInterrupt
            _signals._received.set()
        raise KeyboardInterrupt

    monkeypatch.setattr(batch_run._NoBar, "update", interrupt)
    out = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt) as interrupted:
        process_many(files, out_dir=out, jobs=2, preset="raw", bias=0.0)
    assert isinstance(interrupted.value, batch_run.BatchInterrupted)
    assert str(interrupted.value) == f"1 file(s) finished before it, complete: {out / 'short.csv'}"
    assert sorted(p.name for p in out.iterdir()) == ["short.csv"]


def test_batch_inputs_from_folders_and_globs(tmp_path: Path) -> None:
    for k in range(3):
        synthetic_csv(tmp_path / f"d{k}.csv", 100)
    (tmp_path / "notes.txt").write_text("not a log")
    found = expand_inputs([tmp_path, str(tmp_path / "d*.csv"), real_log_path("f110_ds3")])
    assert [p.name for p in found] == ["d0.csv", "d1.csv", "d2.csv", "f110_ds3"]
    with pytest.raises(ValueError, match="no such file or folder, and no file matches it"):
        expand_inputs([str(tmp_path / "nothing*.csv")])


def test_batch_refuses_two_inputs_with_one_output_name_before_any_work(tmp_path: Path) -> None:
    synthetic_csv(tmp_path / "a.csv", 100)
    pq.write_table(pa_csv.read_csv(tmp_path / "a.csv"), tmp_path / "a.parquet")
    with pytest.raises(ValueError, match="would both be written to"):
        process_many([tmp_path / "a.csv", tmp_path / "a.parquet"], out_dir=tmp_path / "out", preset="raw")
    assert not (tmp_path / "out").exists()


def test_batch_rejects_invalid_parameters_before_any_work(tmp_path: Path) -> None:
    synthetic_csv(tmp_path / "a.csv", 100)
    with pytest.raises(ValueError, match="hdr_c2"):
        process_many([tmp_path / "a.csv"], out_dir=tmp_path / "out", preset="hdr", hdr_c2=-1.0)


def drive_with_repairs(path: Path, *, repeat: int | None = None) -> Path:
    """A Parquet log whose float32 times resolve only 1/128 s (still increasing at 100 Hz), with a
    forward clock jump of 10 s (a gap, bridged) and a NaN reading (held); ``repeat``: that row's
    time repeats the one before, an error after all of them."""
    t = 1e5 + np.arange(3000) * 0.01
    t[2000:] += 10.0
    if repeat is not None:
        t[repeat] = t[repeat - 1]
    rate = np.full(len(t), 0.001)
    rate[2500] = np.nan
    pq.write_table(pa.table({"t": pa.array(t, pa.float32()), "gyro_z": rate}), path)
    return path


@pytest.mark.filterwarnings("ignore::gyrocore.InputWarning")  # the batch's, raised again on its threads
def test_a_files_report_holds_every_warning_it_raised(tmp_path: Path) -> None:
    # a given bias: the file is read once, as it streams, and everything it warns about comes then
    good = drive_with_repairs(tmp_path / "jump.parquet")
    bad = drive_with_repairs(tmp_path / "repeat.parquet", repeat=2800)
    options = {"bias_dps": 0.0, "nonfinite": "hold", "chunk_rows": 1000}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        report = process_file(good, tmp_path / "h.csv", **options)
    float32 = "the times are float32, which at their size resolve only 0.0078125 s"
    assert any(w.startswith(float32) for w in report.warnings), report.warnings
    assert any(w.startswith("1 gap(s), the longest 10.0") for w in report.warnings), report.warnings  # float32 rounds
    # a caller of the API gets those same warnings, naming the file, and no others, each from the
    # line that called
    assert sorted(str(w.message) for w in caught) == sorted(f"{good}: {w}" for w in report.warnings)
    assert {w.filename for w in caught} == {__file__}
    # in a batch on parallel threads, each file's own, also of the file that failed
    summary = process_many([good, bad], out_dir=tmp_path / "out", jobs=2, **options)
    assert summary.files[0].warnings == report.warnings
    assert not summary.files[1].ok and "must strictly increase" in (summary.files[1].error or "")
    assert any(w.startswith(float32) for w in summary.files[1].warnings), summary.files[1].warnings


@pytest.mark.filterwarnings("ignore::gyrocore.InputWarning")  # the same words, raised
def test_the_ok_line_says_what_the_input_policy_did(tmp_path: Path) -> None:
    t = 1.7e9 + np.arange(3000) * 0.01
    t[1500:] += 10.0  # a forward clock jump: a gap, bridged
    rate = np.full(len(t), 0.001)
    rate[[700, 2000]] = np.nan
    pa_csv.write_csv(pa.table({"t": t, "gyro_z": rate}), src := tmp_path / "jump.csv")
    summary = process_many([src], out_dir=tmp_path / "out", nonfinite="hold")
    said = ("2 reading(s) not finite or beyond +-2^20 replaced by the last usable one; 1 gap(s), the longest 10.01 s, "
            "across which the heading changes by 0.0000 rad (0.00 deg)")  # the bias, 0.001 rad/s, removed
    ok_line, policy = str(summary).splitlines()[:2]
    assert ok_line.startswith(f"ok     {src}: 3000 rows in, 3000 out") and policy == f"       input policy: {said}"
    report = summary.files[0].as_dict()
    assert (report["held"], report["skipped"], report["gaps"]) == (2, 0, 1)
    assert report["longest_gap"] == pytest.approx(10.01)
    # a file the policy left alone says nothing of it
    assert "input policy" not in str(process_file(synthetic_csv(tmp_path / "plain.csv", 3000), tmp_path / "h.csv"))


def test_causal_mode_warns_of_an_unmeasured_bias_only_for_files_it_processes(tmp_path: Path) -> None:
    good = synthetic_csv(tmp_path / "good.csv", 300)
    bad = synthetic_csv(tmp_path / "bad.csv", 300)
    lines = bad.read_text().splitlines()
    lines[100] = lines[100].split(",")[0] + ",nan"  # a NaN rate: the file fails at its row
    bad.write_text("\n".join(lines) + "\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        report = process_many([good, bad], out_dir=tmp_path / "out", preset="static_bias", mode="causal", jobs=1)
    done, failed = report.files
    assert failed.error is not None and done.error is None, report
    assert any("removes a static bias" in w for w in done.warnings), done.warnings
    # the failed file was not processed: no bias of its output was taken as 0
    assert not any("removes a static bias" in w for w in failed.warnings), failed.warnings
    assert sum("removes a static bias" in str(w.message) for w in caught) == 1, [str(w.message) for w in caught]


def test_a_time_repeated_across_a_files_chunks_is_the_files_duplicate(tmp_path: Path) -> None:
    """A repeat on a chunk's edge reads as a stream sending a chunk again to the pipeline; from a
    file it is the file's duplicate, told as one."""
    rows = [f"{k * 0.1:.1f},0.01" for k in range(10)]
    rows[6] = rows[5]  # the first sample of the third 3-row chunk repeats the last of the second
    path = tmp_path / "a.csv"
    path.write_text("t,gyro_z\n" + "\n".join(rows) + "\n")
    with pytest.raises(ValueError) as info:
        process_file(path, tmp_path / "o.csv", preset="raw", chunk_rows=3)
    assert str(info.value) == f"timestamps must strictly increase: t[6] = 0.5 follows 0.5 (sort the log and " \
        f"drop duplicate timestamps) ({path}, line 8)"


@pytest.mark.parametrize("chunk_rows", [100, 300, 10_000])
def test_a_failed_files_rows_in_are_the_samples_before_its_bad_one(tmp_path: Path, chunk_rows: int) -> None:
    """A file that fails at a bad sample reports the rows read up to it, whatever the chunks: it
    counted the whole chunks before the failing one (0 in one chunk, 900 in chunks of 300)."""
    path = tmp_path / "mid.csv"
    rows = [f"{k * 0.01:.2f},0.01" for k in range(2000)]
    rows[1000] = "10.00,nan"
    path.write_text("t,gyro_z\n" + "\n".join(rows) + "\n")
    summary = process_many([path], out_dir=tmp_path / "out", preset="raw", chunk_rows=chunk_rows, jobs=1)
    (report,) = summary.files
    assert not report.ok and "rate[1000] is NaN" in str(report.error)
    assert (report.rows_in, report.rows_out) == (1000, 0)


def test_batch_totals_count_the_files_processed(tmp_path: Path) -> None:
    # "1 of 2 files processed, 1 failed; 2836 rows in, 2736 out": the failed file's rows before its NaN
    good = synthetic_csv(tmp_path / "good.csv", 3000)
    bad = tmp_path / "bad.csv"
    lines = good.read_text().splitlines()
    bad.write_text("\n".join([*lines[:101], f"{lines[101].split(',')[0]},nan", *lines[102:]]) + "\n")
    summary = process_many([good, bad], out_dir=tmp_path / "out", preset="raw", jobs=1)
    assert summary.files[1].rows_in == 100 and (summary.rows_in, summary.rows_out) == (3000, 3000)
    assert str(summary).splitlines()[-1].startswith("1 of 2 files processed, 1 failed; 3000 rows in, 3000 out, ")
