"""One call at a time on a stream: a second thread's call is refused with words that name the object.

A stream (:class:`gyrocore.Pipeline`, :class:`gyrocore.fixes.Fusion`) keeps state in Python and in
Rust, and its Rust call runs without the GIL. A call from another thread meanwhile met the Rust
object's borrow and raised ``RuntimeError: Already mutably borrowed`` (even ``repr`` of it in a
notebook), or, between the Rust call and the Python bookkeeping after it, ran on a state half
updated. Every method that reads or changes the state takes the object's :class:`Turn` first.

A file's reading (:meth:`gyrocore.io.GyroSource.chunks`) and a table being written
(:class:`gyrocore.io.HeadingWriter`) are streams too: chunks taken by two threads from one reading
were split between them without a word, and two threads' writes mixed their rows in one file.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable, Iterator
from typing import Any, Generic, TypeVar

_F = TypeVar("_F", bound=Callable[..., Any])
_T = TypeVar("_T")

#: What a refused call of a stream (a pipeline, a filter) should do instead.
STREAM_ADVICE = ("a stream takes one call at a time; give each thread its own (copy.copy of it carries the "
                 "state), or hold a lock around its calls")


class InUseError(RuntimeError):
    """A call on a stream while another thread's call on it runs."""


class Turn:
    """Whose turn it is on one object: the thread of the call that runs, or none."""

    def __init__(self, advice: str = STREAM_ADVICE) -> None:
        self._lock = threading.Lock()
        self._owner: int | None = None
        self._call = ""
        #: what a refused call should do instead, said after the refusal
        self._advice = advice

    def take(self, owner: str, call: str) -> bool:
        """Makes this thread's ``call`` the object's one call until :meth:`let_go`: True; False where
        this thread's call has it already (a call made from inside the running one, on its thread:
        a callback, an ``__array__`` of an input, goes on as part of it); else :class:`InUseError`
        naming ``owner`` (what the object is, in words) and the call that runs."""
        me = threading.get_ident()
        if self._owner == me:
            return False
        if not self._lock.acquire(blocking=False):
            raise InUseError(f"{owner} is in use by another thread (its {self._call} runs there): {self._advice}")
        self._owner, self._call = me, call
        return True

    def let_go(self) -> None:
        """Ends the call that :meth:`take` began (on its thread)."""
        if self._owner == threading.get_ident():
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
        # no contextmanager block: its 6 us a call made a writer's one-row writes a third slower
        began = self._turn.take(self._in_use_name, f"{type(self).__name__}.{name}()")
        try:
            return method(self, *args, **kwargs)
        finally:
            if began:
                self._turn.let_go()

    return guarded  # type: ignore[return-value]


class OneReader(Generic[_T]):
    """The items of ``items`` for the thread that takes the first, to the last: a reading is one
    stream in order, and another thread's ``next()`` on it meanwhile is refused
    (:class:`InUseError` naming ``owner``, ``advice`` after it), the reading left whole for the
    first thread. Shared, the chunks were split between the threads without a word (or one of
    them met ``ValueError: generator already executing``)."""

    def __init__(self, items: Iterator[_T], owner: str, call: str, advice: str) -> None:
        self._items, self._owner, self._call = items, owner, call
        self._turn = Turn(advice)

    def __iter__(self) -> OneReader[_T]:
        return self

    def __next__(self) -> _T:
        self._turn.take(self._owner, self._call)  # held from the first item to the end
        try:
            return next(self._items)
        except BaseException:  # the end, or an error that ended the reading: another may begin
            self._turn.let_go()
            raise

    def close(self) -> None:
        """Ends the reading where it is (its file closed), as a generator's ``close`` does."""
        self._turn.take(self._owner, self._call)
        try:
            close = getattr(self._items, "close", None)
            if close is not None:
                close()
        finally:
            self._turn.let_go()
