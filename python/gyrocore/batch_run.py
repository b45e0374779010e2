"""Running a batch's file jobs on threads or on a Dask cluster: a bad file fails alone, and an
interruption stops every running file at its next chunk (removing its temporary output)."""

from __future__ import annotations

import asyncio
import os
import sys
import threading
import time
import uuid
import warnings
from concurrent.futures import CancelledError, ThreadPoolExecutor, as_completed
from collections.abc import Callable, Iterable
from typing import Any

from ._extras import require, tqdm_class
from ._gyrocore import __version__
from .batch_job import _FileJob
from .batch_report import FileReport
from .io import atomic


def _run_job(job: _FileJob, stop: threading.Event | Any = None) -> FileReport:
    """Run one job; any error becomes a failed report (a bad file fails alone). ``stop`` (a
    thread's or a Dask cluster's event) ends it at its next chunk once set."""
    start = time.perf_counter()

    def check_stop() -> None:
        if stop is not None and stop.is_set():
            raise _Stopped("stopped before the end")

    try:
        return job.run(stop=check_stop)
    except Exception as e:  # noqa: BLE001 - every failure is reported and the batch goes on
        return job.failure(e, time.perf_counter() - start)


class BatchInterrupted(KeyboardInterrupt):
    """A batch stopped by Ctrl-C or SIGTERM: the files it finished before (their outputs complete;
    the others left no output), to say which (``str``: empty when none was)."""

    def __init__(self, finished: list[FileReport]) -> None:
        super().__init__()
        self.finished = finished

    def __str__(self) -> str:
        done = [r.output for r in self.finished if r.output is not None]
        if not done:
            return ""
        shown = ", ".join(done[:3]) + (f" and {len(done) - 3} more" if len(done) > 3 else "")
        return f"{len(done)} file(s) finished before it, complete: {shown}"


def _finished_meanwhile(futures: Iterable[tuple[int, Any]], reports: dict[int, FileReport],
                        named: Callable[[int, FileReport], FileReport] = lambda i, report: report) -> None:
    """Adds the reports of the files that finished while the batch stopped (``named`` names their
    files as given): past their last chunk when the signal came, they complete, and their outputs
    are whole."""
    for i, future in futures:
        if i in reports or not future.done() or future.cancelled():
            continue
        try:
            reports[i] = named(i, future.result())
        # a file the signal stopped (its chunk check raised the KeyboardInterrupt, see _signals),
        # or a lost worker: no report, and no output; the batch's own interrupt is raised after
        except (Exception, KeyboardInterrupt):  # noqa: BLE001
            continue


def _interrupted(e: BaseException, reports: dict[int, FileReport]) -> None:
    """An interrupt of the batch becomes :class:`BatchInterrupted` with the files it finished (the
    ones stopped or failed left no output)."""
    if isinstance(e, KeyboardInterrupt) and not isinstance(e, BatchInterrupted):
        raise BatchInterrupted([reports[i] for i in sorted(reports) if reports[i].ok]) from e


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


def run_on_threads(jobs: list[_FileJob], workers: int, progress: bool) -> list[FileReport]:
    stop = threading.Event()
    reports: dict[int, FileReport] = {}
    with _bar(len(jobs), progress) as bar:
        executor = ThreadPoolExecutor(max_workers=min(workers, len(jobs)), thread_name_prefix="gyrocore")
        futures: dict[Any, int] = {}
        try:
            futures = {executor.submit(_run_job, job, stop): i for i, job in enumerate(jobs)}
            for future in as_completed(futures):
                reports[futures[future]] = future.result()
                bar.update(1)
        except BaseException as e:
            stop.set()  # running files stop at their next chunk and remove their temporary output
            executor.shutdown(wait=True, cancel_futures=True)
            _finished_meanwhile(((i, f) for f, i in futures.items()), reports)
            _interrupted(e, reports)
            raise
        executor.shutdown()
    return [reports[i] for i in range(len(jobs))]


def run_on_dask(client: Any, jobs: list[_FileJob], progress: bool) -> list[FileReport]:
    """The jobs on the cluster of ``client``, a Dask client (:func:`connected` makes one of an
    address or a cluster; its caller closes it)."""
    distributed = require("dask.distributed", "running on a Dask cluster")
    reports: dict[int, FileReport] = {}
    # The workers' files check it at every chunk, as the threads' files check theirs: a task
    # already running on a worker is not stopped by cancelling its future.
    batch = uuid.uuid4().hex
    stop = distributed.Event(f"gyrocore-stop-{batch}", client=client)
    sent = [job.for_a_worker(batch) for job in jobs]

    def named(i: int, report: FileReport) -> FileReport:
        return jobs[i].as_given(report, sent[i])

    # A key of the batch's own: the cluster takes a key it holds already for that task, and
    # another batch's first file of the same name (gyrocore-0-d0.csv) was taken for this one's,
    # never processed, its report the other's.
    futures = [
        client.submit(_run_job, job, stop, key=f"gyrocore-{batch}-{i}-{_readable(job.path.name)}", pure=False)
        for i, job in enumerate(sent)
    ]
    index = {f.key: i for i, f in enumerate(futures)}
    with _bar(len(jobs), progress) as bar:
        try:
            for future in distributed.as_completed(futures):
                i = index[future.key]
                try:
                    reports[i] = named(i, future.result())
                except Exception as e:  # noqa: BLE001 - a lost worker fails its file only
                    reports[i] = jobs[i].failure(_lost(distributed, e), 0.0)
                # The cluster forgets the report once read: a worker that died holding it made
                # the cluster process the file again (each file 3 times over when one killed
                # every worker), writing its output anew.
                future.release()
                bar.update(1)
        except BaseException as e:
            _stop_on_cluster(distributed, client, stop, futures)
            _finished_meanwhile(enumerate(futures), reports, named)
            _interrupted(e, reports)
            raise
        finally:  # what the workers that died while writing an output left of it, a folder at a time
            for folder in dict.fromkeys(job.staging_folder() for job in sent):
                atomic.discard_tagged(folder, batch)
    return [reports[i] for i in range(len(jobs))]


def _readable(name: str) -> str:
    """A file's name as valid UTF-8, for the key of its task (shown by Dask's dashboard): a name of
    bytes that are not (``caf\\xe9.csv`` of a Latin-1 system) broke the client's connection to
    the scheduler, which sends keys as UTF-8, and every file of the batch failed."""
    return os.fsencode(name).decode("utf-8", "replace")


def _lost(distributed: Any, error: Exception) -> Exception | str:
    """Why the cluster gave no report of a file, for its failure: Dask's own words were the repr
    of its exception (``KilledWorker('gyrocore-...-oom.csv', <WorkerState 'tcp://...', name: 0,
    status: closed, ...>, 3)``, ``FutureCancelledError()``)."""
    if isinstance(error, distributed.KilledWorker):
        return (f"every Dask worker that ran it died ({error.allowed_failures + 1} of them): out of memory, or "
                "killed; the workers' logs say which; its output is not written")
    # Newer distributed raise its FutureCancelledError, a CancelledError with Dask's reason;
    # distributed 2023 has no such class (looking it up failed the batch) and gives no reason.
    if isinstance(error, CancelledError):
        reason = getattr(error, "reason", "none given")
        return (f"the Dask cluster dropped it before it finished (Dask's reason: {reason}; the scheduler "
                "gone?); run it again (--skip-existing goes on with the inputs without an output)")
    return error


def check_client(client: Any) -> None:
    """Refuse, before any output is made, a ``client`` that is no Dask client, cluster or address
    (Dask's bare "Scheduler address must be a string or a Cluster instance"), or a client that was
    closed (Dask's ``ClosedClientError: Client is closed. Can't send update-graph message``, after
    the output folder was made)."""
    distributed = require("dask.distributed", "running on a Dask cluster")
    if isinstance(client, distributed.Client):
        if client.status in ("closing", "closed"):
            raise ValueError("client= is a Dask client that was closed (client.close(), or the end of its with "
                             "block): give an open one, or the scheduler's address (tcp://host:8786)")
        return
    if not isinstance(client, str) and not hasattr(client, "scheduler_address"):  # a cluster has one
        raise TypeError("client must be a dask.distributed.Client, a Dask cluster or a scheduler's address "
                        f"(tcp://host:8786), got {type(client).__name__} {client!r}")


def _version() -> str:
    """The version of gyrocore (of its compiled core) where this runs: a worker, asked by :func:`check_workers`."""
    return __version__


def check_workers(client: Any) -> None:
    """Refuse, before any output is made, a cluster whose workers cannot import gyrocore (not
    installed there, or its compiled core missing: each worker that took a file died reading its
    task, and the batch waited for ever) or run another version of it than this one (whose
    headings may differ from a run here). A worker that joins later refuses each file it is given
    if its version differs (``_FileJob._check_seen_here``)."""
    address = client.scheduler.address
    try:
        answers = client.run(_version, on_error="return")
    except OSError as e:  # a client whose scheduler went away: Dask's bare "ConnectionPool closing."
        raise ConnectionError(f"the Dask scheduler at {address} no longer answers this client ({e}); check that it "
                              "runs, and connect to it again") from None
    if not answers:  # the batch waited without a word, for ever where no worker comes
        warnings.warn(f"the Dask cluster at {address} has no workers: the files wait until some join "
                      f"(dask worker {address}; an adaptive cluster starts them for the files)", RuntimeWarning,
                      stacklevel=3)
    wrong = [f"{worker}: " + (f"gyrocore {answer}" if isinstance(answer, str) else f"cannot import gyrocore ({answer})")
             for worker, answer in sorted(answers.items()) if answer != __version__]
    if wrong:
        more = f" (and {len(wrong) - 2} more)" if len(wrong) > 2 else ""
        raise ValueError(f"the Dask cluster's workers must run gyrocore {__version__}, as this machine does: "
                         f"{'; '.join(wrong[:2])}{more}; install it on every worker "
                         f"(pip install 'gyrocore[dask]=={__version__}')")


def connected(client: Any) -> tuple[Any, bool]:
    """``client`` as a Dask client, and whether it was made here (from an address or a cluster,
    to be closed by the caller once the batch is done)."""
    distributed = require("dask.distributed", "running on a Dask cluster")
    if isinstance(client, distributed.Client):
        return client, False
    return _connect(distributed.Client, client), True


def _connect(Client: Any, address: Any) -> Any:
    """A client of the scheduler at ``address``; an address Dask cannot read, or a scheduler it
    cannot reach, is an error that says which and what to check (Dask's own words named neither
    the option nor the address's form, and the dashboard's http:// address is a common mistake)."""
    form = "the scheduler's address as `dask scheduler` prints it (tcp://host:8786; the dashboard's http://host:8787 is another)"
    try:
        if isinstance(address, str):
            _handshake(address)
        return Client(address)
    except _NoScheduler as e:
        raise ConnectionError(f"something answered at {address!r}, but not as a Dask scheduler ({e}); check that "
                              f"{address!r} is {form}; without a scheduler the files run on this machine's "
                              "cores") from None
    except ValueError as e:
        raise ValueError(f"scheduler address {address!r}: {e}; give {form}") from e
    except OSError as e:
        raise ConnectionError(f"no Dask scheduler answered at {address!r}: {e}; check that it runs and that this machine "
                              f"reaches it, and that {address!r} is {form}; without a scheduler the files run on "
                              "this machine's cores") from e


class _NoScheduler(Exception):
    """What answered at a scheduler's address did not greet as a Dask scheduler does."""


def _no_greeting(error: BaseException | None, waited: float) -> _NoScheduler:
    """What answered at a scheduler's address, as said of it: ``error`` is what reading its answer
    raised, None or a time-out where nothing came within ``waited`` seconds."""
    if error is None or isinstance(error, asyncio.TimeoutError):
        return _NoScheduler(f"no greeting in {waited:g} s")
    return _NoScheduler(f"an answer Dask cannot read: {type(error).__name__}")


def _handshake(address: str) -> None:
    """Greet the scheduler at ``address`` as a client does, within Dask's connect timeout
    (``distributed.comm.timeouts.connect``). ``Client`` waits for the greeting's answer without a
    limit: a server of another kind at the address (a web server) held the command for ever, and
    one whose answer reads as a huge length made it fail with numpy's ``Unable to allocate 3.07
    EiB``. Raises OSError where nothing answers, ValueError for an address Dask cannot read, and
    :class:`_NoScheduler` for an answer that is no scheduler's."""
    import dask
    from distributed.comm.core import connect

    seconds = dask.utils.parse_timedelta(dask.config.get("distributed.comm.timeouts.connect"), default="seconds")

    async def greet() -> None:
        comm = await connect(address, timeout=seconds)
        await comm.close()

    async def within_time() -> None:
        try:  # connect's own timeout ends the wait for a connection; this one, the greeting's after it
            await asyncio.wait_for(greet(), 2 * seconds)
        except asyncio.TimeoutError:  # an OSError too, since Python 3.11
            raise _no_greeting(None, 2 * seconds) from None
        except OSError as e:
            # distributed before 2023.4 greets inside connect, within its timeout, and says a
            # greeting that failed is an OSError, caused by what the answer raised
            if str(e).startswith("Timed out during handshake"):
                raise _no_greeting(e.__cause__, seconds) from None
            raise  # nothing answered: said as before
        except ValueError:  # an address Dask cannot read: said as before
            raise
        except Exception as e:  # noqa: BLE001 - any answer Dask cannot read is no scheduler's
            raise _no_greeting(e, 2 * seconds) from None

    failed: list[BaseException] = []

    def run() -> None:
        try:
            asyncio.run(within_time())
        except BaseException as e:  # noqa: BLE001 - raised again in the caller's thread
            failed.append(e)

    # a loop of its own, in a thread of its own: the caller's thread may run one already (a
    # notebook); a daemon, so that Ctrl-C while it waits ends the command at once
    thread = threading.Thread(target=run, name="gyrocore-dask-greeting", daemon=True)
    thread.start()
    thread.join()
    if failed:
        raise failed[0]


#: How long an interrupted batch waits for the cluster's running files to stop [s].
STOP_TIMEOUT = 30.0


def _stop_on_cluster(distributed: Any, client: Any, stop: Any, futures: list[Any]) -> None:
    """Stops the files still waiting (cancelled) and those running (each at its next chunk,
    removing its temporary output), and waits for the running ones; says so if one does not stop
    in time (a lost connection to the scheduler, a worker stuck in one chunk)."""
    pending = [f for f in futures if not f.done()]
    try:
        stop.set()  # first: a file that a worker starts from here on stops at its first chunk
        # The files no worker has started are cancelled, not waited for: waiting for a worker (none
        # yet, or each busy with another batch), they held an interrupt for the whole timeout, and
        # were said not to have stopped, their output "may still be written".
        started = {key for keys in client.processing().values() for key in keys}
        client.cancel([f for f in pending if f.key not in started])
        pending = [f for f in pending if f.key in started]
        distributed.wait(pending, timeout=STOP_TIMEOUT)
    except Exception:  # noqa: BLE001 - the scheduler gone or the wait timed out: say so below
        pass
    running = [f for f in pending if not f.done()]
    for future in running:  # a finished one keeps its report (its output is complete)
        future.cancel()
    if running:
        print(f"gyrocore: warning: {len(running)} file(s) on the Dask cluster did not stop within "
              f"{STOP_TIMEOUT:g} s: their output may still be written", file=sys.stderr)
