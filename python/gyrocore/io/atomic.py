"""Files that appear whole or not at all: written under a temporary name, renamed at the end.

A reader of ``path`` sees either the old file or the finished new one, never a half-written one,
even when the writer fails or is interrupted (:class:`StagedFile`, :func:`atomic_path`).
"""

from __future__ import annotations

import contextvars
import errno
import filecmp
import os
import secrets
import stat
import weakref
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

from .. import _signals

#: This process's temporary files not yet committed or discarded. A name is added before its file
#: exists, so an interrupt at any moment (even between creating the file and the caller's
#: ``try``) leaves it known to :func:`discard_all`.
_live: set[Path] = set()
#: What a write fails with when there is no room for the file: a full disk, a user's quota, a file
#: larger than the filesystem takes.
_NO_ROOM = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG)


def _nearest(folder: Path) -> Path:
    """``folder``, or where it does not exist, the nearest path above it that does."""
    while not os.path.lexists(folder) and folder != folder.parent:
        folder = folder.parent
    return folder


def _no_folder_at(path: Path, folder: Path) -> str | None:
    """Why ``folder`` (the output ``path``'s, or one to make) cannot hold it, where the nearest path
    at or above it that exists is a file, not a folder (``-o notes.csv/x.csv``: a folder there
    cannot be made either); None where that is a folder."""
    above = _nearest(folder)
    if os.path.lexists(above) and not above.is_dir():
        return f"{path}: {above} is not a folder; write the output elsewhere"
    return None


#: Why nothing could be created in a folder that exists, which the system said is missing (a
#: virtual filesystem's, ``/proc``: even root's ``open(O_CREAT)`` fails with ENOENT there).
_TAKES_NO_FILES = "it exists, but nothing can be created in it, as in a virtual filesystem such as /proc"


def output_folder_missing(path: Path) -> str:
    """Why the output ``path`` cannot be written for want of its folder: none, a file there or
    above it, or a folder that exists but takes no new file (a file's creation failed as if it
    were missing: it said ``the folder /proc does not exist``)."""
    parent = path.parent
    said = _no_folder_at(path, parent)
    if said is not None:
        return said
    if parent.is_dir():
        return cannot_write_in(path, _TAKES_NO_FILES)
    return f"{path}: the folder {parent} does not exist; create it or write elsewhere"


def cannot_write_in(path: Path, why: str | None, folder: Path | None = None) -> str:
    """Why the output ``path`` cannot be written in its folder, or in ``folder`` where a link leads
    (named, not the hidden temporary file's)."""
    where = path.parent if folder is None or folder == path.parent else folder
    return f"{path}: cannot write in {where} ({why}); write the output elsewhere"


def make_folder(path: Path) -> None:
    """Make the output folder ``path`` (and its parents) if it is missing; an error that names it
    and what to do where it cannot be made (a read-only filesystem, no permission, a full disk)."""
    try:
        path.mkdir(parents=True, exist_ok=True)
    except FileExistsError:  # a file in the way: the caller's check names it, before any work
        raise NotADirectoryError(f"{path}: a file, where the output folder goes; write the output elsewhere") from None
    except (FileNotFoundError, NotADirectoryError):  # its place is a file's, or in /proc (a bare errno said so)
        said = _no_folder_at(path, path)
        if said is not None:
            raise NotADirectoryError(said) from None
        where = _nearest(path)
        raise PermissionError(f"{path}: cannot make the output folder in {where} ({_TAKES_NO_FILES}); write the "
                              "output elsewhere") from None
    except OSError as e:
        if e.errno not in (errno.EROFS, errno.EACCES, errno.EPERM, *_NO_ROOM):
            raise
        raise PermissionError(f"{path}: cannot make the output folder ({e.strerror}); write the output elsewhere") from None


def check_output_folder(path: Path, *, made: bool = False) -> None:
    """Refuse, before any work, an output whose folder is missing or is no folder (it was found
    only when the output was written, after the work, or after a report had been printed). Where
    the command makes the folder (``made``), only a file in its way is refused."""
    if not made:
        if not path.parent.is_dir():
            raise FileNotFoundError(output_folder_missing(path))
        if not os.access(path.parent, os.W_OK):  # a read-only filesystem too (EROFS), even for root
            raise PermissionError(cannot_write_in(path, "no permission to write there, or a read-only filesystem"))
        return
    said = _no_folder_at(path, path.parent)
    if said is not None:
        raise NotADirectoryError(said)


def already_there(taken: Sequence[str | Path], option: str) -> FileExistsError:
    """The refusal of outputs that were there before a run told not to replace them began its work
    (``gyrocore``'s outputs without ``--overwrite``, the API's ``overwrite=False``): they exist,
    and ``option`` replaces them. One that appears during the work is another run's, written
    meanwhile (:meth:`StagedFile.commit` says so)."""
    names = [str(p) for p in taken]
    shown = ", ".join(names[:3]) + (f" and {len(names) - 3} more" if len(names) > 3 else "")
    verb, them = ("exists", "it") if len(names) == 1 else ("exist", "them")
    return FileExistsError(f"{shown} already {verb}; pass {option} to replace {them}, or write elsewhere "
                           "(nothing was written)")


#: While outputs are known to have been refused before the work where they were there (by the
#: command line, or by an outer call of :func:`kept_outputs`), the option that would have replaced
#: them (``--overwrite``, ``overwrite=True``): one found at an output later was written meanwhile,
#: and is refused as such, naming that option, when the output is committed. None elsewhere.
_checked: contextvars.ContextVar[str | None] = contextvars.ContextVar("gyrocore_outputs_checked", default=None)


@contextmanager
def outputs_checked(option: str) -> Iterator[None]:
    """A block whose outputs were refused before it where they existed (the command line checks
    its own before any work), ``option`` the one that replaces them (``--overwrite``):
    :func:`kept_outputs` checks nothing in it, and an output refused in it names that option."""
    token = _checked.set(option)
    try:
        yield
    finally:
        _checked.reset(token)


def replacing_option(option: str) -> str:
    """The option that replaces an output, as the user who started the work knows it: that of the
    outer block's check (the command line's ``--overwrite``), else ``option`` (the function's own).
    A file written meanwhile under the Python API was refused naming ``--overwrite``."""
    return _checked.get() or option


def refuse_present(paths: Iterable[str | Path], replace: bool, option: str) -> None:
    """Where outputs may not be replaced (not ``replace``), refuse before the work those that are
    there already (:func:`already_there`, naming ``option``), unless the block was checked
    (:func:`outputs_checked`). Without it a file saved twice was refused only when the second was
    written, said to be "written meanwhile by something else"."""
    if not replace and _checked.get() is None:
        taken = [p for p in paths if os.path.lexists(p)]
        if taken:
            raise already_there(taken, option)


@contextmanager
def kept_outputs(paths: Iterable[str | Path], replace: bool, option: str) -> Iterator[None]:
    """A block that writes ``paths``, their refusal checked before it (:func:`refuse_present`); in
    the block, one that appears is another run's, written meanwhile."""
    refuse_present(paths, replace, option)
    with outputs_checked(replacing_option(option)):
        yield


def check_replaceable(path: Path) -> None:
    """Refuse an output ``path`` that is, or is a symbolic link to, a named pipe, socket or device:
    the staged file renamed over it replaced it with a regular file (a link to /dev/null, written
    by root, replaced the device node)."""
    target = Path(os.path.realpath(path)) if path.is_symlink() else path
    if target.exists() and not target.is_file() and not target.is_dir():
        where = "" if target == path else f" (where its symbolic link leads, {target})"
        raise ValueError(f"{path}: a named pipe, socket or device{where}, not a file; an output replaces files "
                         "only: write it elsewhere")


def named_if_no_room(path: Path, error: BaseException) -> BaseException:
    """``error``, or for a write that found no room for ``path`` (an OSError that names no file:
    ``[Errno 28] No space left on device``) one that says which output and what to do."""
    if not (isinstance(error, OSError) and error.errno in _NO_ROOM and error.filename is None):
        return error
    named = OSError(f"{path}: {error.strerror} while writing it (the output is not written, and a file of that name "
                    "is left as it was): free space, or write elsewhere")
    named.errno = error.errno
    return named


def nearest_folder(folder: Path) -> Path:
    """``folder``, or where it does not exist yet (a folder a run will make), the nearest folder
    above it: the one whose filesystem it will be on."""
    while not folder.is_dir() and folder != folder.parent:
        folder = folder.parent
    return folder


def name_max(folder: Path) -> int:
    """The longest file name, in bytes, that ``folder`` (or, where it does not exist yet, the
    nearest folder above it) takes: 255 on the usual filesystems, where it cannot be asked."""
    try:
        return os.pathconf(nearest_folder(folder), "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):  # no pathconf (Windows), or the folder cannot say
        return 255


#: The mark of the temporary files written in this context (:func:`tagged`), empty for none.
_tag: contextvars.ContextVar[str] = contextvars.ContextVar("gyrocore_temporary_tag", default="")


@contextmanager
def tagged(tag: str) -> Iterator[None]:
    """Name the temporary files written in the block ``.NAME.<tag>-<random>.tmp``: what a process
    that dies leaves of them (a Dask worker killed mid-file, whose ``finally`` never runs) is then
    found by its tag (:func:`discard_tagged`), and never another run's file."""
    token = _tag.set(tag)
    try:
        yield
    finally:
        _tag.reset(token)


def discard_tagged(folder: Path, tag: str) -> None:
    """Remove the temporary files of ``tag`` (see :func:`tagged`) left in ``folder``."""
    for tmp in folder.glob(f".*.{tag}-*.tmp"):
        tmp.unlink(missing_ok=True)


def temporary_name(name: str, limit: int = 255) -> str:
    """The hidden name ``.NAME.<random>.tmp`` (``.NAME.<tag>-<random>.tmp`` in a block of
    :func:`tagged`) under which the file ``name`` is written, its ``NAME`` cut short where the
    whole would be longer than ``limit`` bytes: an output of a long name (an input's name of
    238-255 bytes kept) failed with ``File name too long`` naming the hidden file."""
    tag = _tag.get()
    token = f".{tag + '-' if tag else ''}{secrets.token_hex(6)}.tmp"
    room = limit - 1 - len(token)
    while len(os.fsencode(name)) > room:  # cut whole characters, never a multi-byte one in half
        name = name[:-1]
    return f".{name}{token}"


def sync_folder(folder: Path) -> None:
    """Put a rename in ``folder`` on disk: the file's data was, but its new name lives in the
    folder, which a power cut could roll back (a finished output gone, or the old one back).
    Where a folder cannot be opened to sync (Windows, some network filesystems), nothing."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:  # a folder that cannot be synced (EINVAL on some filesystems): its rename stands
        pass
    finally:
        os.close(fd)


class StagedFile:
    """A temporary file next to ``path`` that becomes ``path`` on :meth:`commit`.

    :meth:`discard` (call it in a ``finally``) removes it unless committed, so an error or an
    interruption never leaves ``path`` half written; one neither committed nor discarded goes with
    the object, or at the interpreter's exit. A hard kill can leave the hidden temporary
    file (``.NAME.*.tmp``, ``NAME`` cut short where the whole would be too long) behind, but never
    a partial ``path``.

    Where ``path`` is a symbolic link, the file it leads to (:attr:`target`, its final target) is
    staged beside and replaced, and the link is kept: renamed over, the link became a regular file
    and the file it led to kept the old contents. The new file takes the permission bits of the
    file it replaces (a calibration kept at 0600 stays 0600); a new name gets the umask's.
    """

    def __init__(self, path: str | Path, *, replace: bool = True) -> None:
        path = Path(path)  # exported: a path as text failed on a missing parent
        self.path = path
        #: False: :meth:`commit` never replaces a file that appeared at ``path`` meanwhile (see there)
        self.replace = replace
        #: what replaces such a file, named where one is refused (:func:`replacing_option`; a
        #: writer's own option, ``replace``, outside a checked block)
        self.option = replacing_option("replace=True")
        #: The file that is replaced: ``path``, or the final target of ``path`` where it is a link
        #: (also one that leads nowhere yet, whose target is then created).
        self.target = Path(os.path.realpath(path)) if path.is_symlink() else path
        check_replaceable(path)
        for _ in range(3):
            tmp = self.target.parent / temporary_name(self.target.name, name_max(self.target.parent))
            _live.add(tmp)
            try:
                # created exclusively with the umask's permissions (mkstemp's 0600 would hide the
                # output from other users)
                os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
            except FileExistsError:  # another's file: never ours to remove
                _live.discard(tmp)
                continue
            except (FileNotFoundError, NotADirectoryError):  # named after the output, not the hidden file
                _live.discard(tmp)
                if self.target == path:
                    raise FileNotFoundError(output_folder_missing(path)) from None
                raise FileNotFoundError(f"{path}: a symbolic link to {os.readlink(path)!r}, whose folder "
                                        f"{self.target.parent} does not exist; create it or write elsewhere") from None
            except OSError as e:
                _live.discard(tmp)
                if not isinstance(e, PermissionError) and e.errno != errno.EROFS:
                    raise
                raise PermissionError(cannot_write_in(path, e.strerror, self.target.parent)) from None
            self.tmp = tmp
            # a writer entered by hand and never left (a notebook's cell, a script that ends first)
            # kept its temporary file for good: it goes when the object does, or at the exit
            self._abandoned = weakref.finalize(self, _forget, tmp)
            return
        raise FileExistsError(f"{self.target.parent}: cannot create a temporary file for {self.target.name}")

    def commit(self) -> None:
        """Make the temporary file ``path`` (its :attr:`target`): on disk first, given the permission
        bits of the file it replaces, then renamed (atomic on one filesystem), and the rename put on
        disk (:func:`sync_folder`).

        Raises KeyboardInterrupt instead if a signal came during the run, even one whose exception a
        library swallowed (see :mod:`gyrocore._signals`): an interrupted run keeps the old file.
        """
        fd = os.open(self.tmp, os.O_RDWR)  # Windows syncs only writable handles
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
        try:
            mode = stat.S_IMODE(os.stat(self.target).st_mode)
        except OSError:  # nothing there yet: the umask's permissions stay
            mode = None
        if mode is not None:  # after the sync, which opens the file for writing (a 0400 file's mode)
            os.chmod(self.tmp, mode)
        _signals.check()
        if self.replace:
            os.replace(self.tmp, self.target)
        else:
            self._place_new()
        self._abandoned.detach()
        _live.discard(self.tmp)
        sync_folder(self.target.parent)

    def _place_new(self) -> None:
        """Give the temporary file its name only if nothing has it yet (a hard link made, which fails
        where the name is taken, then the temporary name removed): a run told not to replace an
        output checked that there was none before its work, and another run writing the same output
        meanwhile had its output replaced without a word, both reported ok."""
        taken = FileExistsError(f"{self.path}: written meanwhile by something else (another run writing the same "
                                f"output?); it is kept, and this run's output is not written: run it again with "
                                f"{self.option} to replace it, or write elsewhere")
        try:
            os.link(self.tmp, self.target)
        except FileExistsError:
            if not self._written_alike():
                raise taken from None
        except OSError as e:  # no hard links here (FAT, some network shares): checked, then renamed
            if e.errno not in (errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EXDEV, errno.EMLINK):
                raise
            if not os.path.lexists(self.target):
                os.replace(self.tmp, self.target)
                return
            if not self._written_alike():
                raise taken from None
        self.tmp.unlink()

    def _written_alike(self) -> bool:
        """Whether the file that appeared at the target holds this run's bytes: nothing of the
        other's is lost, and this run's output is there. A Dask cluster runs a file again when the
        worker that held its report died before the report was read, and the second run found the
        first's output: a file written whole was reported failed, "written meanwhile"."""
        try:
            return os.path.isfile(self.target) and filecmp.cmp(self.tmp, self.target, shallow=False)
        except OSError:
            return False

    def discard(self) -> None:
        """Remove the temporary file if it is still there."""
        self._abandoned()  # once: a later call, or the object's end, does nothing


def _forget(tmp: Path) -> None:
    """Remove the uncommitted temporary file ``tmp`` (:meth:`StagedFile.discard`)."""
    tmp.unlink(missing_ok=True)
    _live.discard(tmp)


def discard_all() -> None:
    """Remove every temporary file of this process not yet committed or discarded: after an
    interrupt, also one that came before its writer's ``finally`` was in place."""
    for tmp in list(_live):
        tmp.unlink(missing_ok=True)
        _live.discard(tmp)


@contextmanager
def atomic_path(path: str | Path, *, replace: bool = True) -> Iterator[Path]:
    """A temporary path next to ``path`` (next to the file it leads to, for a link), renamed to it
    when the block ends without error and removed otherwise (also on KeyboardInterrupt); see
    :class:`StagedFile` (and its ``replace``: False keeps a file that appeared at ``path`` while the
    block ran; one there before it is refused at once, :func:`kept_outputs`)."""
    with kept_outputs([path], replace, "replace=True"):
        staged = StagedFile(path, replace=replace)
        try:
            yield staged.tmp
            staged.commit()
        except OSError as e:
            raise named_if_no_room(staged.path, e) from None
        finally:
            staged.discard()


def write_atomically(path: str | Path, write: Callable[[str], object], *, replace: bool = True) -> None:
    """``write(name)`` writes the file under a temporary name beside ``path``, renamed to ``path``
    at the end: no half-written output (a plot's ``savefig``, say); ``replace`` as
    :func:`atomic_path`'s."""
    with atomic_path(path, replace=replace) as tmp:
        write(str(tmp))


def write_text_atomically(path: str | Path, text: str, *, replace: bool = True) -> None:
    """``text`` as ``path``'s UTF-8 content, whole or not at all; ``replace`` as
    :func:`atomic_path`'s."""
    with atomic_path(path, replace=replace) as tmp:
        tmp.write_text(text, encoding="utf-8")
