"""Running a batch's file jobs on threads or on a Dask cluster: a bad file fails alone, and an
interruption stops every running file at its next chunk (removing its temporary output)."""

from __future__ import annotations

import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from typing import Any

from ._extras import require, tqdm_class
from .batch_job import FileReport, _FileJob


def _run_job(job: _FileJob, stop: threading.Event | None = None) -> FileReport:
    """Run one job; any error becomes a failed report (a bad file fails alone)."""
    start = time.perf_counter()

    def check_stop(done: int, total: int | None, unit: str) -> None:
        if stop is not None and stop.is_set():
            raise _Stopped("stopped before the end")

    try:
        return job.run(check_stop)
    except Exception as e:  # noqa: BLE001 - every failure is reported and the batch goes on
        return job.failure(e, time.perf_counter() - start)


class _Stopped(Exception):
    """The batch was interrupted; the file's temporary output is removed."""


def _bar(total: int, enabled: bool) -> Any:
    """A bar over the files on stderr, only when asked for and stderr is a terminal."""
    tqdm = tqdm_class() if enabled and sys.stderr.isatty() else None
    return _NoBar() if tqdm is None else tqdm(total=total, unit="file", leave=False)


class _NoBar:
    """Stands in for a bar that is not drawn (tqdm would still start its monitor thread)."""

    def __enter__(self) -> _NoBar:
        return self

    def __exit__(self, *exc: object) -> None:
        return None

    def update(self, n: int = 1) -> None:
        return None


def _run_on_threads(jobs: list[_FileJob], workers: int, progress: bool) -> list[FileReport]:
    stop = threading.Event()
    reports: dict[int, FileReport] = {}
    with _bar(len(jobs), progress) as bar:
        executor = ThreadPoolExecutor(max_workers=min(workers, len(jobs)), thread_name_prefix="gyrocore")
        try:
            futures = {executor.submit(_run_job, job, stop): i for i, job in enumerate(jobs)}
            for future in as_completed(futures):
                reports[futures[future]] = future.result()
                bar.update(1)
        except BaseException:
            stop.set()  # running files stop at their next chunk and remove their temporary output
            executor.shutdown(wait=True, cancel_futures=True)
            raise
        executor.shutdown()
    return [reports[i] for i in range(len(jobs))]


def _run_on_dask(client: Any, jobs: list[_FileJob], progress: bool) -> list[FileReport]:
    distributed = require("dask.distributed", "running on a Dask cluster")
    Client, dask_completed = distributed.Client, distributed.as_completed
    own = not isinstance(client, Client)
    if own:
        client = Client(client)
    reports: dict[int, FileReport] = {}
    try:
        futures = [
            client.submit(_run_job, job, key=f"gyrocore-{i}-{job.path.name}", pure=False) for i, job in enumerate(jobs)
        ]
        index = {f.key: i for i, f in enumerate(futures)}
        with _bar(len(jobs), progress) as bar:
            try:
                for future in dask_completed(futures):
                    i = index[future.key]
                    try:
                        reports[i] = future.result()
                    except Exception as e:  # noqa: BLE001 - a lost worker fails its file only
                        reports[i] = jobs[i].failure(e, 0.0)
                    bar.update(1)
            except BaseException:
                client.cancel(futures)
                raise
    finally:
        if own:
            client.close()
    return [reports[i] for i in range(len(jobs))]
