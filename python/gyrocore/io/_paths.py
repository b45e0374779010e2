"""What stands at a path that is read as a file: a regular file, nothing, or something that cannot
be read as one (a folder, a named pipe, a symbolic link that cannot be followed), which is named in
the error."""

from __future__ import annotations

import os
from pathlib import Path


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
