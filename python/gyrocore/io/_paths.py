"""What stands at a path that is read as a file: a regular file, nothing, or something that cannot
be read as one (a folder, a named pipe, a symbolic link that cannot be followed), which is named in
the error."""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

from ..window import as_command_line_says


def missing(path: Path) -> str:
    """Why ``path``, which does not exist, cannot be read: no such file, or a broken link."""
    if not path.is_symlink():
        return f"{path}: no such file or folder"
    return f"{path}: {unfollowable(path)}"


def unfollowable(link: Path) -> str:
    """What a symbolic link that leads nowhere is: dangling, or a loop."""
    reason = "no such file"
    try:
        link.stat()
    except OSError as e:  # a dangling link, or a loop (ELOOP)
        reason = e.strerror or reason
    return f"a symbolic link to {os.readlink(link)!r}, which cannot be followed ({reason})"


def check_file(path: Path) -> None:
    """Refuse a ``path`` that is not a regular file.

    Raises:
        FileNotFoundError: nothing is there, or a link that cannot be followed.
        ValueError: a folder, or a named pipe, socket or device (reading one would wait for ever).
    """
    if path.is_file():
        check_readable(path)
        return
    if not path.exists():
        raise FileNotFoundError(missing(path))
    what = "a folder" if path.is_dir() else "a named pipe, socket or device"
    raise ValueError(f"{path}: {what}, not a file")


def has_file(path: Path) -> bool:
    """Whether the optional file ``path`` is there: False if nothing has its name, True for a
    regular file. Anything else of that name is an error (:func:`check_file`): taken for no file,
    a log folder's meta.json would lose its rest window, its odometry its speed, without a word."""
    if not os.path.lexists(path):
        return False
    check_file(path)
    return True


def denied(path: str | Path) -> str:
    """Why ``path`` cannot be read for lack of permission, and what to do (Python's own words,
    ``[Errno 13] Permission denied: 'x'``, say neither whether it is read or what to change)."""
    if Path(path).is_dir():
        return (f"{path}: permission denied: this user may not list the folder; make it readable "
                f"(chmod +rx {path}) or copy it somewhere readable")
    return (f"{path}: permission denied: this user may not read the file; make it readable "
            f"(chmod +r {path}) or copy it somewhere readable")


def check_readable(path: Path) -> None:
    """Refuse a file or folder ``path`` this user may not read (PermissionError, :func:`denied`).

    Opening it is the only true test (``os.access`` ignores ACLs, and root reads anything); a
    folder is listed, and one that may be listed but not entered fails on its first entry."""
    try:
        if path.is_dir():
            with os.scandir(path) as entries:
                for entry in entries:
                    entry.stat(follow_symlinks=False)
                    break
        else:
            os.close(os.open(path, os.O_RDONLY))
    except PermissionError:
        raise PermissionError(denied(path)) from None


def arrow_path(path: str | Path) -> bytes:
    """``path`` as pyarrow opens it: the bytes of its name on disk. pyarrow encodes a name given as
    text to UTF-8 itself, which fails for a name that is not UTF-8 (a logger's FAT card written in
    Latin-1, ``caf\\xe9.csv``: ``'utf-8' codec can't encode character '\\udce9' ...: surrogates not
    allowed``)."""
    return os.fsencode(path)


def error_text(error: BaseException) -> str:
    """The one line that says what went wrong: a PermissionError of Python's (``[Errno 13]``) as
    the path and what to change, worded for any access (it may come from a read or a write, where
    :func:`denied` is a read's), anything else as it reads."""
    if isinstance(error, PermissionError) and error.filename is not None and "[Errno" in str(error):
        return (f"{error.filename}: permission denied: this user may not open it; change its permissions "
                "(chmod) or use another path")
    return as_command_line_says(str(error))  # the command line's windows take +T


def one_line(text: str) -> str:
    """``text`` on one line: a control character (a line break or terminal escape in a file's
    name) shown as its escape, ``\\n``, so that an error, a warning or a ``FAILED`` line stays one
    line."""
    return "".join(c if c.isprintable() or c == " " else repr(c)[1:-1] for c in text)


#: The first bytes of each kind of file read, the suffixes it is read by, and what it is called.
_MAGIC = (
    (b"PAR1", (".parquet", ".pq"), "a Parquet file"),
    (b"\x93NUMPY", (".npy",), "a NumPy .npy file"),
    (b"PK\x03\x04", (".npz",), "a zip archive (a NumPy .npz file?)"),
    (b"#ROSBAG", (".bag",), "a ROS 1 bag"),
)


#: What to write instead of a table in a format that is not read.
_AS_READ = "write the samples as Parquet or CSV (pandas: df.to_parquet(path), df.to_csv(path, index=False))"


def content_hint(path: Path) -> str:
    """What the content of the file ``path`` is where its suffix says another kind (a Parquet
    file named .npy, CSV text named .parquet), with the name that reads it; else empty. The
    reader's own error (bad magic bytes, not a zip file) does not say what the file is."""
    try:
        with open(path, "rb") as f:
            head = f.read(512)
    except OSError:
        return ""
    suffix = path.suffix.lower()
    known = _magic(head)
    if known is not None:
        suffixes, what = known
        return "" if suffix in suffixes else f"; its content is that of {what}: name it {path.stem}{suffixes[0]}"
    if suffix in (".csv", ".tsv"):  # the CSV reader names compressed data and other encodings itself
        return ""
    if head.startswith(b"\x1f\x8b"):
        return "; it is compressed with gzip: decompress it first"
    # tables pandas writes in formats not read (df.to_feather, df.to_json): "name it a.csv" misled for JSON
    if head.startswith(b"ARROW1"):
        return f"; it is an Arrow IPC (Feather) file, which is not read: {_AS_READ}"
    if head.lstrip()[:1] in (b"{", b"["):
        return f"; its content is JSON, which is not read: {_AS_READ}"
    if head and b"\0" not in head and _is_text(head):
        return f"; its content is text (a CSV file?): name it {path.stem}.csv"
    return ""


def content_kind(head: bytes) -> str | None:
    """What kind of file gyrocore reads the bytes ``head`` (a file's first) begin (``a Parquet
    file``), or None."""
    known = _magic(head)
    return None if known is None else known[1]


def _magic(head: bytes) -> tuple[tuple[str, ...], str] | None:
    """The suffixes and the name of the kind of file whose first bytes ``head`` are, by :data:`_MAGIC`."""
    return next(((suffixes, what) for magic, suffixes, what in _MAGIC if head.startswith(magic)), None)


def _is_text(head: bytes) -> bool:
    """Whether ``head``, a file's first bytes, is UTF-8 text (a character cut at its end aside)."""
    try:
        head.decode("utf-8")
    except UnicodeDecodeError as e:
        return e.start >= len(head) - 3 and e.reason == "unexpected end of data"
    return True


#: Suffixes of compressed files: a log compressed (``a.csv.gz``) is named, not passed over.
COMPRESSED = (".gz", ".bz2", ".xz", ".zst", ".zip")


def compressed_logs(entries: Iterable[Path], suffixes: tuple[str, ...]) -> str:
    """What a folder holds of logs compressed (``a.csv.gz``, ``gyro.csv.gz``: a suffix of
    ``suffixes`` then one of :data:`COMPRESSED`), which no reader reads, with what to do; else
    empty. A folder of such logs was said to hold none, and beside other logs they were left out
    of a batch without a word. ``entries``: the folder's listing, which its caller has made already
    (a folder listed twice cost twice on a network file system, and a file arriving between the
    two listings was seen by one and not the other)."""
    found = sorted(c.name for c in entries
                   if c.suffix.lower() in COMPRESSED and Path(c.stem).suffix.lower() in suffixes)
    if not found:
        return ""
    names = ", ".join(found[:3]) + (" ..." if len(found) > 3 else "")
    return f"{len(found)} compressed log(s) that are not read ({names}): decompress them first"
