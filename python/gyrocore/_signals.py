"""Interrupts that are never lost.

A KeyboardInterrupt raised inside a library call can be swallowed: pyarrow imports pandas lazily
during its first conversion to numpy and discards any exception raised in that import, so a run
interrupted then would go on and replace its output. Two defences:

- :func:`not_swallowed` runs such a call and raises KeyboardInterrupt after it if a signal came
  during it (the readers and writers run pyarrow's first conversion under it, before any data);
- under :func:`handled` (the command line) SIGINT and SIGTERM also set a flag that outlives the
  exception: a staged output is never committed once a signal came
  (:meth:`gyrocore.io.StagedFile.commit`), and the streaming loops check it between chunks
  (:func:`check`).
"""

from __future__ import annotations

import signal
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType
from typing import Any

_SIGNALS = (signal.SIGINT, signal.SIGTERM)

_received = threading.Event()


def received() -> bool:
    """True once a signal came while :func:`handled` was active."""
    return _received.is_set()


def check() -> None:
    """Raise KeyboardInterrupt if a signal came while :func:`handled` was active."""
    if received():
        raise KeyboardInterrupt


@contextmanager
def handled() -> Iterator[None]:
    """While the block runs, SIGINT and SIGTERM raise KeyboardInterrupt and are remembered.

    Only the main thread can own signal handlers; elsewhere the block runs unchanged.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(signum: int, frame: FrameType | None) -> None:
        _received.set()
        raise KeyboardInterrupt

    hook = sys.unraisablehook

    def keep_quiet(unraisable: Any) -> None:
        # A signal that lands where Python cannot raise (a weakref callback of the import system,
        # a __del__) would print "Exception ignored ... Traceback"; the flag already keeps it.
        if not (isinstance(unraisable.exc_value, KeyboardInterrupt) and _received.is_set()):
            hook(unraisable)

    _received.clear()
    previous = {s: signal.signal(s, interrupt) for s in _SIGNALS}
    sys.unraisablehook = keep_quiet
    try:
        yield
    finally:
        sys.unraisablehook = hook
        for s, handler in previous.items():
            signal.signal(s, handler)


@contextmanager
def not_swallowed() -> Iterator[None]:
    """Raise KeyboardInterrupt when the block ends if SIGINT or SIGTERM came during it, even if
    code in the block swallowed the exception its handler raised.

    Only signals with a Python handler are watched (the default SIGTERM ends the process anyway),
    and only in the main thread, where handlers run.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    came: list[int] = []

    def relay(handler: Any) -> Any:
        def record(signum: int, frame: FrameType | None) -> None:
            came.append(signum)
            handler(signum, frame)

        return record

    previous = {s: signal.getsignal(s) for s in _SIGNALS}
    watched = {s: h for s, h in previous.items() if callable(h)}
    for s, h in watched.items():
        signal.signal(s, relay(h))
    try:
        yield
    finally:
        for s, h in watched.items():
            signal.signal(s, h)
    if came:
        raise KeyboardInterrupt
