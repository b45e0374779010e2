"""One call at a time on a stream: a second thread's call is refused with words that name the object.

A stream (:class:`gyrocore.Pipeline`, :class:`gyrocore.fixes.Fusion`) keeps state in Python and in
Rust, and its Rust call runs without the GIL. A call from another thread meanwhile met the Rust
object's borrow and raised ``RuntimeError: Already mutably borrowed`` (even ``repr`` of it in a
notebook), or, between the Rust call and the Python bookkeeping after it, ran on a state half
updated. Every method that reads or changes the state takes the object's :class:`Turn` first.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any, TypeVar

_F = TypeVar("_F", bound=Callable[..., Any])


class InUseError(RuntimeError):
    """A call on a stream while another thread's call on it runs."""


class Turn:
    """Whose turn it is on one object: the thread of the call that runs, or none."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._owner: int | None = None
        self._call = ""

    @contextmanager
    def taken(self, owner: str, call: str) -> Iterator[None]:
        """Runs the block as the object's one call, or raises :class:`InUseError` naming ``owner``
        (what the object is, in words) and the call that runs. A call made from inside the running one (on its thread: a
        callback, an ``__array__`` of an input) goes on as part of it."""
        me = threading.get_ident()
        if self._owner == me:
            yield
            return
        if not self._lock.acquire(blocking=False):
            raise InUseError(
                f"{owner} is in use by another thread (its {self._call} runs there): a stream takes one call "
                f"at a time; give each thread its own (copy.copy of it carries the state), or hold a lock "
                f"around its calls")
        self._owner, self._call = me, call
        try:
            yield
        finally:
            self._owner = None
            self._lock.release()

    def busy(self) -> bool:
        """Whether another thread's call runs now."""
        return self._owner is not None and self._owner != threading.get_ident()


def one_at_a_time(method: _F) -> _F:
    """Runs ``method`` in its object's turn (``self._turn``; ``self._in_use_name`` says what the
    object is), so that another thread's call on it meanwhile is refused, not interleaved."""
    name = method.__name__

    @functools.wraps(method)
    def guarded(self: Any, *args: Any, **kwargs: Any) -> Any:
        with self._turn.taken(self._in_use_name, f"{type(self).__name__}.{name}()"):
            return method(self, *args, **kwargs)

    return guarded  # type: ignore[return-value]
