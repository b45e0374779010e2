"""Ctrl-C and kill: exit 130 and the previous output untouched, whenever the signal comes (issue:
pyarrow swallowed an interrupt raised in its lazy import of pandas, and the run replaced the output)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from gyrocore import _signals
from gyrocore.batch import process_file
from gyrocore.cli import main
from gyrocore.io import StagedFile

from .test_batch import leftovers, read_table, synthetic_csv

PREVIOUS = "previous output\n"
INTERRUPTED = "gyrocore: interrupted; no partial output was left"


def _command(src: Path, out: Path) -> list[str]:
    """A run that replaces the previous output ``out``."""
    return ["process", str(src), "--out", str(out), "--preset", "raw", "--chunk-rows", "5000", "--overwrite"]


def _owns_signals(pid: int) -> bool:
    """Whether the process has a handler for SIGTERM (Linux: the SigCgt mask in /proc)."""
    with open(f"/proc/{pid}/status") as f:
        caught = next(line for line in f if line.startswith("SigCgt:"))
    return bool(int(caught.split()[1], 16) >> (signal.SIGTERM - 1) & 1)


def _check_interrupted(proc: subprocess.CompletedProcess[str] | subprocess.Popen[str], stderr: str, out: Path) -> None:
    assert proc.returncode == 130, stderr
    assert stderr.strip() == INTERRUPTED and "Traceback" not in stderr
    assert out.read_text() == PREVIOUS and leftovers(out.parent) == []


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads the signal mask from /proc")
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_at_any_moment_of_a_run_exits_130_and_keeps_the_previous_output(
    tmp_path: Path, signum: signal.Signals
) -> None:
    src = synthetic_csv(tmp_path / "in.csv", 600_000)
    out = tmp_path / "h.csv"

    def started() -> subprocess.Popen[str]:
        """The command, once it owns its signals."""
        out.write_text(PREVIOUS)
        proc = subprocess.Popen(
            [sys.executable, "-m", "gyrocore.cli", *_command(src, out)], stderr=subprocess.PIPE, text=True
        )
        deadline = time.monotonic() + 60
        while proc.poll() is None and not _owns_signals(proc.pid) and time.monotonic() < deadline:
            time.sleep(0.002)
        return proc

    # a run without a signal completes
    proc = started()
    proc.communicate(timeout=60)
    assert proc.returncode == 0
    kept = []
    # from the moment the command owns its signals: reading the header, the first chunk (pyarrow's
    # lazy imports), the stream, the rename
    delays = (0.0, 0.02, 0.05, 0.1, 0.2, 0.4, 0.8, 1.6)
    for delay in delays:
        proc = started()
        time.sleep(delay)
        if proc.poll() is not None:
            break  # it finished before this delay; longer ones would too
        proc.send_signal(signum)
        _, stderr = proc.communicate(timeout=60)
        assert "Traceback" not in stderr and leftovers(tmp_path) == []
        if out.read_text() == PREVIOUS:
            _check_interrupted(proc, stderr, out)
            kept.append(delay)
        else:  # the signal came after the rename: the output is the complete new one
            assert len(read_table(out)) == 600_000
            assert proc.returncode in (0, 130, -signum), stderr
    # Signals sent as the command starts (before its first chunk is read: a run of 600,000
    # samples lasts far longer than 0.02 s on any machine) always interrupt it. Later ones may
    # come after the rename, more or less often with the machine's load: each was checked above.
    assert kept[:2] == [0.0, 0.02], kept


_TRAP = """
import os, signal, sys, warnings

def send():
{send}

class SignalDuringImport:
    # sends the signal to this process while pyarrow imports pandas, once the command owns its signals
    def find_spec(self, name, path=None, target=None):
        if name == "pandas" and signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL:
            sys.meta_path.remove(self)
            send()
        return None

sys.meta_path.insert(0, SignalDuringImport())
from gyrocore.cli import main
sys.exit(main({argv!r}))
"""


@pytest.mark.parametrize("fmt", ["csv", "parquet"])
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_inside_pyarrows_lazy_import_of_pandas_is_not_lost(
    tmp_path: Path, fmt: str, signum: signal.Signals
) -> None:
    src = synthetic_csv(tmp_path / "in.csv", 2000)
    if fmt == "parquet":
        pq.write_table(read_table(src), tmp_path / "in.parquet")
        src = tmp_path / "in.parquet"
    out = tmp_path / f"h.{fmt}"
    out.write_text(PREVIOUS)
    _check_trapped(tmp_path, src, out, f"    os.kill(os.getpid(), {int(signum)})")


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_warning_from_an_import_the_signal_cut_short_is_not_shown(tmp_path: Path, signum: signal.Signals) -> None:
    """pandas 1.5's Cython modules warn "Cython module failed to patch module with custom type"
    when the signal lands in their import: the run says only that it was interrupted (the warning
    was shown as gyrocore's own)."""
    src = synthetic_csv(tmp_path / "in.csv", 2000)
    out = tmp_path / "h.csv"
    out.write_text(PREVIOUS)
    send = (f"    try:\n        os.kill(os.getpid(), {int(signum)})\n    except KeyboardInterrupt:\n"
            "        warnings.warn('Cython module failed to patch module with custom type', RuntimeWarning)\n"
            "        raise")
    _check_trapped(tmp_path, src, out, send)


def _check_trapped(tmp_path: Path, src: Path, out: Path, send: str) -> None:
    """The command run with `send` (the body of a function) called as pyarrow imports pandas."""
    script = textwrap.dedent(_TRAP).format(send=send, argv=_command(src, out))
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    _check_interrupted(proc, proc.stderr, out)


_EVAL_TRAP = """
import os, signal, sys

class SignalInsideEval:
    # the signal lands inside an eval, as it does when it interrupts an import that builds a
    # namedtuple (argparse's lazy import of shutil): CPython then marks the KeyboardInterrupt as
    # unhandled and, at exit, kills the process with SIGINT unless the program ends it itself
    def find_spec(self, name, path=None, target=None):
        if signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL:
            sys.meta_path.remove(self)
            eval("os.kill(os.getpid(), signal.SIGINT) or __import__('time').sleep(5)")
        return None

sys.meta_path.insert(0, SignalInsideEval())
sys.argv[1:] = {argv!r}
from gyrocore.cli import run
run()
"""


def test_ctrl_c_inside_an_eval_still_exits_130(tmp_path: Path) -> None:
    """Run as ``python -m`` runs the command (a program run with ``-c`` or as a file exits
    through another path that never looks at that mark)."""
    src = synthetic_csv(tmp_path / "in.csv", 2000)
    out = tmp_path / "h.csv"
    out.write_text(PREVIOUS)
    (tmp_path / "trapped.py").write_text(textwrap.dedent(_EVAL_TRAP).format(argv=_command(src, out)))
    proc = subprocess.run(
        [sys.executable, "-m", "trapped"], cwd=tmp_path, capture_output=True, text=True, timeout=120
    )
    _check_interrupted(proc, proc.stderr, out)


def test_the_api_raises_an_interrupt_that_came_inside_pyarrows_lazy_import(tmp_path: Path) -> None:
    """process_file in a program that keeps Python's own Ctrl-C handling: KeyboardInterrupt, no output."""
    src = synthetic_csv(tmp_path / "in.csv", 2000)
    out = tmp_path / "h.csv"
    out.write_text(PREVIOUS)
    script = textwrap.dedent(
        f"""
        import os, signal, sys
        # Python's own Ctrl-C handling, also where the test runs with SIGINT ignored (a shell's
        # background job), which a child inherits and Python then leaves alone
        signal.signal(signal.SIGINT, signal.default_int_handler)
        class SignalDuringImport:
            def find_spec(self, name, path=None, target=None):
                if name == "pandas":
                    sys.meta_path.remove(self)
                    os.kill(os.getpid(), signal.SIGINT)
                return None
        from gyrocore.batch import process_file
        sys.meta_path.insert(0, SignalDuringImport())
        try:
            process_file({str(src)!r}, {str(out)!r}, preset="raw")
        except KeyboardInterrupt:
            sys.exit(3)
        """
    )
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 3, proc.stderr
    assert out.read_text() == PREVIOUS and leftovers(tmp_path) == []


def test_a_swallowed_interrupt_still_stops_the_commit(tmp_path: Path) -> None:
    """Under the command's handlers a signal is remembered: even if a library swallows the
    KeyboardInterrupt, the staged output does not replace the old one."""
    out = tmp_path / "h.csv"
    out.write_text(PREVIOUS)
    with _signals.handled():
        staged = StagedFile(out)
        try:
            staged.tmp.write_text("new\n")
            try:
                os.kill(os.getpid(), signal.SIGTERM)
                time.sleep(1)  # the handler runs here
            except KeyboardInterrupt:
                pass  # what pyarrow's lazy import did
            with pytest.raises(KeyboardInterrupt):
                staged.commit()
        finally:
            staged.discard()
    assert out.read_text() == PREVIOUS and leftovers(tmp_path) == []
    # the flag belongs to that run: the next one commits
    with _signals.handled():
        process_file(synthetic_csv(tmp_path / "in.csv", 100), out, preset="raw")
    assert np.array_equal(read_table(out)["t"].to_numpy(), pa.csv.read_csv(tmp_path / "in.csv")["t"].to_numpy())


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads the signal mask from /proc")
def test_an_interrupted_batch_leaves_each_output_previous_or_complete(tmp_path: Path) -> None:
    logs = tmp_path / "logs"
    logs.mkdir()
    for i in range(4):
        synthetic_csv(logs / f"d{i}.csv", 300_000, seed=i)
    out = tmp_path / "out"
    out.mkdir()
    for i in range(4):
        (out / f"d{i}.csv").write_text(PREVIOUS)
    proc = subprocess.Popen(
        [sys.executable, "-m", "gyrocore.cli", "process", str(logs), "--out", str(out), "--preset", "raw",
         "--jobs", "2", "--chunk-rows", "5000", "--overwrite"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    # The signal as the first file is committed: the others are under way or waiting, on a machine
    # of any speed (a fixed delay found all four done on a fast one). A file stopped by it raises
    # in its own thread, which the command must not take for the interrupt's end.
    outputs = [out / f"d{i}.csv" for i in range(4)]  # not the staged files beside them
    while proc.poll() is None and all(p.stat().st_size == len(PREVIOUS) for p in outputs):
        time.sleep(0.001)
    proc.send_signal(signal.SIGTERM)
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130 and stdout == ""
    # the line names the files finished before the signal, if any (all of them, up to three)
    line, *rest = stderr.strip().splitlines()
    assert not rest and line.startswith(INTERRUPTED), stderr
    assert leftovers(out) == []
    kept = [p for p in sorted(out.iterdir()) if p.read_text() == PREVIOUS]
    assert kept, "the signal came before the first of the four files was done"
    done = set(out.iterdir()) - set(kept)
    for p in done:
        assert len(read_table(p)) == 300_000
    assert line == INTERRUPTED if not done else (f"{len(done)} file(s) finished before it, complete: " in line
                                                 and all(str(p) in line for p in done))


def test_an_interrupt_right_after_a_temporary_file_is_made_leaves_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A signal between the staged file's creation and its writer's ``finally`` (found by the
    test above, rarely): the command removes it on the way out."""
    src = synthetic_csv(tmp_path / "in.csv", 2000)
    out = tmp_path / "h.csv"
    out.write_text(PREVIOUS)
    made = StagedFile.__init__

    def interrupted(self: StagedFile, path: Path, **how: bool) -> None:
        made(self, path, **how)
        raise KeyboardInterrupt  # the file exists, and nobody holds it yet

    monkeypatch.setattr(StagedFile, "__init__", interrupted)
    assert main(_command(src, out)) == 130
    assert out.read_text() == PREVIOUS and leftovers(tmp_path) == []


def test_an_interrupt_where_python_cannot_raise_it_is_kept_without_a_traceback(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # A signal inside a weakref callback or a __del__ (the import system's module locks) cannot
    # raise there: Python hands it to sys.unraisablehook, which prints "Exception ignored ...
    # Traceback", and goes on. The flag keeps the interrupt for the next check, quietly; any
    # other unraisable exception still reaches the hook.
    import sys
    import threading

    from gyrocore import _signals

    reached: list[type[BaseException]] = []
    monkeypatch.setattr(sys, "unraisablehook", lambda u: reached.append(type(u.exc_value)))
    # a flag of this test's own: the module's stays clear for the tests after it
    monkeypatch.setattr(_signals, "_received", threading.Event())

    class RaisesWhenCollected:
        def __init__(self, error: type[BaseException]) -> None:
            self.error = error

        def __del__(self) -> None:
            _signals._received.set()
            raise self.error

    with _signals.handled():
        RaisesWhenCollected(KeyboardInterrupt)
        RaisesWhenCollected(ValueError)
        with pytest.raises(KeyboardInterrupt):
            _signals.check()
    assert reached == [ValueError]


def test_an_interrupt_where_the_extension_first_meets_numpy_is_no_panic(tmp_path: Path) -> None:
    """The extension's first use of NumPy's C API ran numpy's version check, Python code that a
    Ctrl-C can interrupt, and a KeyboardInterrupt there became a Rust panic with a traceback (seen
    when a signal came at a command's first chunk): the API is found as the module is imported."""
    script = textwrap.dedent(
        """
        import numpy, numpy.lib
        import gyrocore
        def interrupted(*args, **kwargs):
            raise KeyboardInterrupt
        numpy.lib.NumpyVersion = interrupted  # what a later first use of the C API would run
        heading = gyrocore.integrate(numpy.arange(3.0), numpy.ones(3))
        print(heading.tolist())
        """
    )
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0 and proc.stdout == "[0.0, 1.0, 2.0]\n", proc.stderr
