"""A fleet on a Dask cluster, as its operator meets it: batches that share the cluster, workers
whose working folder is not the client's, workers that die, a scheduler that goes away. Each
batch is compared with the same batch run here on threads (``jobs=2``): the outputs are
bit-identical and the reports equal."""

from __future__ import annotations

import contextlib
import importlib
import os
import socket
import subprocess
import sys
import threading
import time
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

import gyrocore
from gyrocore import batch_job, batch_run
from gyrocore.batch import BatchReport, process_many

from .test_batch import synthetic_csv

distributed = pytest.importorskip("dask.distributed")

_run_job = batch_run._run_job


@pytest.fixture(scope="module")
def threads() -> Iterator[Any]:
    """A client of a cluster of threads in this process (one worker of two threads)."""
    with (
        distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cluster,
        distributed.Client(cluster) as client,
    ):
        yield client


@pytest.fixture(scope="module")
def processes() -> Iterator[Any]:
    """A client of a cluster of two worker processes of one thread each (the machine's two cores)."""
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
    try:
        with distributed.Client(cluster) as client:
            yield client
    finally:
        # distributed 2023.1's close waited for ever, one run in five, on a worker process that a
        # test had killed: a bounded wait, whatever is left of them ends with the test run
        with contextlib.suppress(distributed.TimeoutError):
            cluster.close(timeout=30)


def comparable(report: BatchReport) -> dict[str, Any]:
    """A batch's report without its times, which differ from run to run, and with its outputs'
    names alone (the batches compared write into folders of their own)."""
    plain = report.as_dict()
    del plain["seconds"]
    for f in plain["files"]:
        del f["seconds"]
        f["output"] = f["output"] and Path(f["output"]).name
    return plain


_both = threading.Barrier(2)


def _beside_the_other(job: Any, stop: Any = None) -> Any:
    """A file's job that runs only while another batch's runs too (a thread of the same worker)."""
    _both.wait(timeout=10)
    return _run_job(job, stop)


def test_two_batches_on_one_cluster_each_process_their_own_files(tmp_path: Path, threads: Any,
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    # Two operators' batches on one cluster, each with a first input named d0.csv: a task's key
    # was its index and the input's name, so the second batch's file was taken for the first's,
    # never processed, and its report was the first batch's (input A/d0.csv, output outA/d0.csv)
    # with an empty output folder.
    a, b = tmp_path / "A", tmp_path / "B"
    a.mkdir()
    b.mkdir()
    inputs = [synthetic_csv(a / "d0.csv", 3000, seed=1), synthetic_csv(b / "d0.csv", 2000, seed=2)]
    monkeypatch.setattr(batch_run, "_run_job", _beside_the_other)
    _both.reset()
    reports: dict[str, BatchReport] = {}

    def run(name: str, log: Path) -> None:
        reports[name] = process_many([log], out_dir=tmp_path / f"out{name}", client=threads, preset="raw", bias=0.0)

    runs = [threading.Thread(target=run, args=(n, log)) for n, log in zip("AB", inputs)]
    for r in runs:
        r.start()
    for r in runs:
        r.join(timeout=60)
    for name, log, rows in zip("AB", inputs, (3000, 2000)):
        (report,) = reports[name].files
        assert report.ok, report.error
        out = tmp_path / f"out{name}" / "d0.csv"
        assert (report.input, report.output, report.rows_out) == (str(log), str(out), rows)
        assert os.listdir(tmp_path / f"out{name}") == ["d0.csv"]


def _fleet(folder: Path) -> Path:
    """Three good logs and one malformed CSV in ``folder``."""
    folder.mkdir()
    for k in range(3):
        synthetic_csv(folder / f"d{k}.csv", 3000 + 500 * k, seed=k)
    (folder / "bad.csv").write_text("t,gyro_z\n0,0\n0.01,zero\n")
    return folder


def test_relative_paths_are_the_clients_on_workers_that_run_elsewhere(tmp_path: Path, processes: Any,
                                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    # The workers' working folder is not the client's (another machine, a process started
    # elsewhere): `gyrocore process logs --out out --scheduler ...` failed every file with
    # "logs/d0.csv: no such file or folder" although it was there, and an absolute input with a
    # relative output folder was written into the workers' folder, not the one reported.
    _fleet(tmp_path / "logs")
    monkeypatch.chdir(tmp_path)
    assert all(cwd != str(tmp_path) for cwd in processes.run(os.getcwd).values())
    here = process_many(["logs"], out_dir="out", jobs=2, preset="raw", bias=0.0)
    os.rename("out", "here")
    there = process_many(["logs"], out_dir="out", client=processes, preset="raw", bias=0.0)
    assert [(r.ok, r.input, r.output) for r in there.files] == [
        (False, "logs/bad.csv", None), *((True, f"logs/d{k}.csv", f"out/d{k}.csv") for k in range(3))
    ]
    assert comparable(there) == comparable(here)
    assert sorted(os.listdir("out")) == sorted(os.listdir("here")) == ["d0.csv", "d1.csv", "d2.csv"]
    for name in os.listdir("out"):
        assert Path("out", name).read_bytes() == Path("here", name).read_bytes()
    absolute = process_many([tmp_path / "logs" / "d0.csv"], out_dir="again", client=processes, preset="raw", bias=0.0)
    assert absolute.files[0].output == "again/d0.csv" and os.listdir("again") == ["d0.csv"]


def _without_gyrocore() -> None:
    """Make this process (a worker) one where gyrocore is not installed."""
    import sys

    class Missing:
        def find_spec(self, name: str, path: object = None, target: object = None) -> None:
            if name.partition(".")[0] == "gyrocore":
                raise ModuleNotFoundError(f"No module named {name!r}", name=name)

    for name in [m for m in sys.modules if m.partition(".")[0] == "gyrocore"]:
        del sys.modules[name]
    sys.meta_path.insert(0, Missing())


def test_workers_without_gyrocore_are_named_before_any_work(tmp_path: Path) -> None:
    # Each worker that took a file died reading its task (Dask's "Failed to deserialize ...
    # ModuleNotFoundError: No module named 'gyrocore'" in its log), and the batch waited for ever.
    log = synthetic_csv(tmp_path / "d0.csv", 300)
    with (
        distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster,
        distributed.Client(cluster) as client,
    ):
        client.run(_without_gyrocore)
        done: list[BaseException] = []

        def run() -> None:
            try:
                process_many([log], out_dir=tmp_path / "out", client=client, preset="raw", bias=0.0)
            except BaseException as e:  # noqa: BLE001 - the test's thread says it below
                done.append(e)

        thread = threading.Thread(target=run, daemon=True)
        thread.start()
        thread.join(timeout=30)
        assert done, "the batch waited for workers that cannot run it"
    assert isinstance(done[0], ValueError)
    assert str(done[0]).startswith(f"the Dask cluster's workers must run gyrocore {batch_run.__version__}, as this "
                                   f"machine does: tcp://")
    assert "cannot import gyrocore" in str(done[0]) and "No module named 'gyrocore'" in str(done[0])
    assert not (tmp_path / "out").exists()


def test_workers_of_another_gyrocore_are_named_before_any_work(tmp_path: Path, processes: Any,
                                                               monkeypatch: pytest.MonkeyPatch) -> None:
    # another version computes other headings than the same batch here, without a word
    log = synthetic_csv(tmp_path / "d0.csv", 300)
    monkeypatch.setattr(batch_run, "__version__", "0.0.1")  # this machine's, as the workers' is the real one
    with pytest.raises(ValueError, match=r"^the Dask cluster's workers must run gyrocore 0\.0\.1, as this machine "
                                         rf"does: tcp://[^ ]+: gyrocore {gyrocore.__version__}; tcp://[^ ]+: "):
        process_many([log], out_dir=tmp_path / "out", client=processes, preset="raw", bias=0.0)
    assert not (tmp_path / "out").exists()


def test_a_worker_of_another_gyrocore_that_joins_later_fails_each_file_it_takes(
        tmp_path: Path, processes: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    # the workers are asked their version before the batch; one that joined after it ran the files
    # it took with its own, whose headings may differ. The late worker is played by a client whose
    # version differs from the workers' only once the check is past.
    logs = _fleet(tmp_path / "logs")
    for_a_worker = batch_job._FileJob.for_a_worker

    def from_another_client(job: batch_job._FileJob, tag: str) -> batch_job._FileJob:
        sent = for_a_worker(job, tag)
        if job.path.name == "d1.csv":
            sent.client_version = "0.0.1"
        return sent

    monkeypatch.setattr(batch_job._FileJob, "for_a_worker", from_another_client)
    report = process_many([logs], out_dir=tmp_path / "out", client=processes, preset="raw", bias=0.0)
    assert [r.ok for r in report.files] == [False, True, False, True]  # bad.csv, and d1.csv
    assert report.files[2].error == (
        f"the Dask worker at {socket.gethostname()} runs gyrocore {gyrocore.__version__}, the client 0.0.1 (a worker "
        "that joined after the batch began?): install gyrocore[dask]==0.0.1 on every worker")
    assert not (tmp_path / "out" / "d1.csv").exists()


class _DiesOnOom(distributed.WorkerPlugin):
    """Each worker process dies (as the kernel's out-of-memory killer ends it) once it has
    written a chunk of the input ``oom.csv``; the other files run as ever."""

    name = "gyrocore-test-dies-on-oom"

    def setup(self, worker: Any) -> None:
        from gyrocore.io import writer

        write = writer.HeadingWriter.write

        def write_then_die(self: Any, result: Any) -> None:
            write(self, result)
            if self.path.name == "oom.csv":
                os._exit(137)

        writer.HeadingWriter.write = write_then_die  # type: ignore[method-assign]


def test_a_file_that_kills_every_worker_fails_alone_and_says_so(tmp_path: Path, processes: Any) -> None:
    # It failed with Dask's repr, `KilledWorker('gyrocore-3-oom.csv', <WorkerState 'tcp://...',
    # name: 0, status: closed, memory: 0, processing: 0>, 3)`
    logs = _fleet(tmp_path / "logs")
    synthetic_csv(logs / "oom.csv", 3000, seed=7)
    here = process_many([logs], out_dir=tmp_path / "here", jobs=2, preset="raw", bias=0.0, chunk_rows=1000)
    # register_plugin in newer distributed, which no longer have 2023's register_worker_plugin
    register = getattr(processes, "register_plugin", None) or processes.register_worker_plugin
    register(_DiesOnOom())
    try:
        # as the command line runs it (no --overwrite): a file the cluster ran again, its worker
        # dead before its report was read, was reported "written meanwhile by something else"
        there = process_many([logs], out_dir=tmp_path / "out", client=processes, preset="raw", bias=0.0,
                             chunk_rows=1000, overwrite=False)
    finally:
        processes.unregister_worker_plugin(_DiesOnOom.name)
    oom = there.files[-1]
    assert oom.input == str(logs / "oom.csv") and not oom.ok and here.files[-1].ok
    assert oom.error == (f"{logs / 'oom.csv'}: every Dask worker that ran it died (4 of them): out of memory, or "
                         "killed; the workers' logs say which; its output is not written")
    assert comparable(there)["files"][:-1] == comparable(here)["files"][:-1]
    assert [r.ok for r in there.files] == [False, True, True, True, False]
    # and no temporary output of the attempts that died (4 of oom.csv, the size of its output each)
    assert sorted(os.listdir(tmp_path / "out")) == ["d0.csv", "d1.csv", "d2.csv"]


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@contextlib.contextmanager
def _scheduler_and_worker() -> Iterator[tuple[str, subprocess.Popen[bytes]]]:
    """A scheduler and a worker of two threads, each a process of its own (as `dask scheduler`
    and `dask worker` start them): the scheduler's address, and its process, to end."""
    address = f"tcp://127.0.0.1:{_free_port()}"
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    scheduler = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                                  "--port", address.rpartition(":")[2], "--dashboard-address", ":0"], **quiet)
    worker = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address, "--nthreads", "2",
                               "--no-nanny", "--dashboard-address", ":0"], **quiet)
    try:
        yield address, scheduler
    finally:
        for process in (scheduler, worker):
            process.kill()
            process.wait()


def test_a_client_whose_scheduler_went_away_is_named(tmp_path: Path) -> None:
    # Dask's bare "ConnectionPool closing.", once the client had tried to connect again
    log = synthetic_csv(tmp_path / "d0.csv", 300)
    with _scheduler_and_worker() as (address, scheduler):
        client = distributed.Client(address, timeout=3)  # it tries to connect again for 3 s
        client.wait_for_workers(1, timeout=30)
        scheduler.kill()
        scheduler.wait()
        with pytest.raises(ConnectionError, match=rf"^the Dask scheduler at {address} no longer answers this client "
                                                  r"\(.*\); check that it runs, and connect to it again$"):
            process_many([log], out_dir=tmp_path / "out", client=client, preset="raw", bias=0.0)
        with contextlib.suppress(Exception):
            client.close(timeout=2)
    assert not (tmp_path / "out").exists()


def test_a_scheduler_that_goes_away_mid_batch_fails_the_files_it_had_and_says_so(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # They failed with `FutureCancelledError()`, the repr of Dask's exception.
    short, long = synthetic_csv(tmp_path / "short.csv", 1000), synthetic_csv(tmp_path / "long.csv", 1_000_000)
    with _scheduler_and_worker() as (address, scheduler):
        client = distributed.Client(address, timeout=30)
        client.wait_for_workers(1, timeout=30)

        def scheduler_gone(self: object, n: int = 1) -> None:  # once the short file is done
            scheduler.kill()
            scheduler.wait()

        monkeypatch.setattr(batch_run._NoBar, "update", scheduler_gone)
        report = process_many([short, long], out_dir=tmp_path / "out", client=client, preset="raw", bias=0.0,
                              chunk_rows=1000)
        with contextlib.suppress(Exception):  # the client's goodbye to a scheduler that is gone
            client.close(timeout=2)
    assert report.files[0].ok and not report.files[1].ok
    # distributed 2023 cancels the future without a reason (and without the class that has one,
    # whose lookup failed the whole batch with an AttributeError)
    newer = hasattr(importlib.import_module("distributed.client"), "FutureCancelledError")
    reason = "scheduler-connection-lost" if newer else "none given"
    assert report.files[1].error == (
        f"{long}: the Dask cluster dropped it before it finished (Dask's reason: {reason}; the "
        "scheduler gone?); run it again (--skip-existing goes on with the inputs without an output)")


def test_an_input_the_workers_do_not_see_is_said_to_be_missing_there(tmp_path: Path, processes: Any,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    # Workers without the client's filesystem (/tmp or a home folder of the client's machine):
    # `FAILED .../d0.csv: no such file or folder`, of a file the user sees on the client. The
    # other machine is played by the input removed once the client has found it.
    logs = _fleet(tmp_path / "logs")
    for_a_worker = batch_job._FileJob.for_a_worker

    def not_on_the_workers(job: batch_job._FileJob, tag: str) -> batch_job._FileJob:
        sent = for_a_worker(job, tag)
        if job.path.name == "d1.csv":
            job.path.unlink()
        if job.out.parent.name == "elsewhere":
            job.out.parent.rmdir()
        return sent

    monkeypatch.setattr(batch_job._FileJob, "for_a_worker", not_on_the_workers)
    report = process_many([logs], out_dir=tmp_path / "out", client=processes, preset="raw", bias=0.0)
    assert [r.ok for r in report.files] == [False, True, False, True]
    host = socket.gethostname()
    assert report.files[2].error == (
        f"{logs / 'd1.csv'}: no such input on the Dask worker at {host}, though the client at {host} found it: the "
        "workers must see the inputs and the output folder at the paths the client gives (a shared filesystem, "
        "mounted at the same place)")
    (alone,) = process_many([logs / "d0.csv"], out_dir=tmp_path / "elsewhere", client=processes, preset="raw",
                            bias=0.0).files
    assert alone.error == (
        f"{tmp_path / 'elsewhere'}: no such output folder on the Dask worker at {host}, though the client at {host} "
        "found it: the workers must see the inputs and the output folder at the paths the client gives (a shared "
        "filesystem, mounted at the same place)")


def test_a_cluster_without_workers_is_said_to_wait_for_them(tmp_path: Path) -> None:
    # `gyrocore process ... --scheduler ADDRESS` waited for ever without a word
    log = synthetic_csv(tmp_path / "d0.csv", 300)
    with (
        distributed.LocalCluster(n_workers=0, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster,
        distributed.Client(cluster) as client,
        warnings.catch_warnings(record=True) as said,
    ):
        warnings.simplefilter("always")
        reports: list[BatchReport] = []
        thread = threading.Thread(target=lambda: reports.append(
            process_many([log], out_dir=tmp_path / "out", client=client, preset="raw", bias=0.0)))
        thread.start()
        thread.join(timeout=5)
        assert thread.is_alive() and not reports  # no worker, no work
        assert [str(w.message) for w in said if w.category is RuntimeWarning] == [
            f"the Dask cluster at {cluster.scheduler_address} has no workers: the files wait until some join (dask "
            f"worker {cluster.scheduler_address}; an adaptive cluster starts them for the files)"]
        cluster.scale(1)
        thread.join(timeout=30)
    assert reports and reports[0].files[0].ok


def test_a_relative_path_through_a_link_and_up_is_the_one_the_client_reads(tmp_path: Path, processes: Any,
                                                                            monkeypatch: pytest.MonkeyPatch) -> None:
    # `link/../d0.csv`, link leading to elsewhere/deep: the system reads elsewhere/d0.csv, as a
    # run here does; tidied by its text, it named ./d0.csv, another file (or none)
    elsewhere = tmp_path / "elsewhere"
    (elsewhere / "deep").mkdir(parents=True)
    synthetic_csv(elsewhere / "d0.csv", 3000, seed=1)
    synthetic_csv(tmp_path / "d0.csv", 2000, seed=2)  # what the tidied name reads
    (tmp_path / "link").symlink_to(elsewhere / "deep")
    monkeypatch.chdir(tmp_path)
    here = process_many(["link/../d0.csv"], out_dir="here", jobs=2, preset="raw", bias=0.0)
    there = process_many(["link/../d0.csv"], out_dir="out", client=processes, preset="raw", bias=0.0)
    assert there.files[0].rows_out == here.files[0].rows_out == 3000
    assert Path("out", "d0.csv").read_bytes() == Path("here", "d0.csv").read_bytes()


def test_a_name_that_is_not_utf8_is_processed_as_on_threads(tmp_path: Path, processes: Any) -> None:
    # `café.csv` named by a Latin-1 system (the byte 0xe9): the task's key, sent to the scheduler
    # as UTF-8, broke the client's connection, and every file of the batch failed (0 of 2).
    logs = tmp_path / "logs"
    logs.mkdir()
    synthetic_csv(logs / "a.csv", 1000)
    synthetic_csv(logs / "b.csv", 1200, seed=1).rename(logs / os.fsdecode(b"caf\xe9.csv"))
    here = process_many([logs], out_dir=tmp_path / "here", jobs=2, preset="raw", bias=0.0)
    there = process_many([logs], out_dir=tmp_path / "out", client=processes, preset="raw", bias=0.0)
    assert [r.ok for r in there.files] == [True, True]
    assert comparable(there) == comparable(here)
    for name in os.listdir(tmp_path / "here"):
        assert (tmp_path / "out" / name).read_bytes() == (tmp_path / "here" / name).read_bytes()


def test_an_interrupt_cancels_the_files_no_worker_has_started_at_once(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    # Ctrl-C while the files waited for a worker (none yet, or all busy with another batch): the
    # command waited 30 s for them to stop, then said "3 file(s) on the Dask cluster did not stop
    # within 30 s: their output may still be written", of files no worker had started.
    logs = _fleet(tmp_path / "logs")

    def interrupted(futures: Any) -> Iterator[Any]:  # Ctrl-C while the batch waits for its first file
        time.sleep(0.5)
        raise KeyboardInterrupt
        yield

    with (
        distributed.LocalCluster(n_workers=0, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster,
        distributed.Client(cluster) as client,
        warnings.catch_warnings(),
    ):
        warnings.simplefilter("ignore", RuntimeWarning)  # no workers yet
        monkeypatch.setattr(distributed, "as_completed", interrupted)
        start = time.perf_counter()
        with pytest.raises(batch_run.BatchInterrupted) as stopped:
            process_many([logs], out_dir=tmp_path / "out", client=client, preset="raw", bias=0.0)
        waited = time.perf_counter() - start
    assert waited < batch_run.STOP_TIMEOUT / 3 and stopped.value.finished == []
    assert "did not stop" not in capsys.readouterr().err
    assert os.listdir(tmp_path / "out") == []
