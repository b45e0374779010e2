"""Output names that one folder holds as one file: ``Drive.csv`` and ``drive.csv`` where the output
folder ignores case (macOS, Windows, a FAT card, an ext4 folder with case folding), ``café.csv``
with its ``é`` composed (NFC) and decomposed (NFD) where it composes names alike (macOS). Written
there one after the other, the second output silently replaced the first.

Whether a folder does so is asked of the folder itself (:func:`folding`), not guessed from the
system: a Linux machine may write to a FAT card or an SMB share, a Mac to a case-sensitive volume.
Names that two folders hold apart are never refused where the output folder holds them apart.
"""

from __future__ import annotations

import os
import secrets
import sys
import unicodedata
from collections.abc import Sequence
from pathlib import Path
from typing import NamedTuple

from .io import atomic


class Folding(NamedTuple):
    """How a folder compares names: whether it ignores case, and whether it takes a name's
    composed and decomposed accented letters (NFC, NFD) for one."""

    case: bool
    normalization: bool


#: Where the folder cannot be asked (no permission to create a file in it): what its system's
#: usual filesystems do (macOS: APFS, case- and normalization-insensitive; Windows: NTFS, which
#: ignores case), so that a refusal errs on the side of keeping both outputs.
USUAL = Folding(case=sys.platform in ("darwin", "win32"), normalization=sys.platform == "darwin")


def folding(folder: Path) -> Folding:
    """How ``folder`` (or, where it does not exist yet, the nearest folder above it, where it will
    be made) compares names: a file of a mixed-case name with a composed ``é`` is created there,
    looked up by its name in the other case and decomposed, and removed. Where no file can be
    created there, :data:`USUAL`."""
    where = atomic.nearest_folder(folder)
    name = f".gyrocore-Case-\u00e9-{secrets.token_hex(6)}.tmp"  # unique: another's file is never touched
    probe = where / name
    atomic._live.add(probe)  # removed by an interrupt's clean-up too
    try:
        os.close(os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
    except (OSError, UnicodeError):  # read-only, no permission, a filesystem that refuses the name
        atomic._live.discard(probe)
        return USUAL
    try:
        return Folding(case=os.path.lexists(where / name.swapcase()),
                       normalization=os.path.lexists(where / unicodedata.normalize("NFD", name)))
    finally:
        probe.unlink(missing_ok=True)
        atomic._live.discard(probe)


def key(name: str, how: Folding) -> str:
    """``name`` as a folder that compares names ``how`` tells it from others: two names with one
    key are one file there. Case is folded with :meth:`str.casefold`, which folds a little more
    than some filesystems (``ß`` as ``ss``): such names are refused rather than risked."""
    if how.case:
        name = name.casefold()
    return unicodedata.normalize("NFD", name) if how.normalization else name


def first_clash(outputs: Sequence[Path], how: Folding) -> tuple[int, int] | None:
    """The indices of the first two ``outputs`` (the files of one folder) whose names differ but
    are one file in a folder that compares names ``how``; None if there are none."""
    seen: dict[str, int] = {}
    for i, o in enumerate(outputs):
        j = seen.setdefault(key(o.name, how), i)
        if j != i and outputs[j].name != o.name:
            return j, i
    return None


def why_one(a: str, b: str, how: Folding) -> str:
    """Why the folder holds the names ``a`` and ``b`` as one file."""
    if how.normalization and unicodedata.normalize("NFD", a) == unicodedata.normalize("NFD", b):
        return "composes accented letters alike (Unicode NFC and NFD)"
    return "ignores case"


def clash(sources: Sequence[object], outs: Sequence[Path], folder: Path, verb: str = "written") -> str | None:
    """What to say of the first two ``outs`` (the files of ``sources`` in ``folder``) whose names
    the folder holds as one file (``a and b would both be written to ...``), or None. The folder
    is asked (:func:`folding`, a file created and removed) only where some names could be one."""
    if first_clash(outs, Folding(case=True, normalization=True)) is None:
        return None
    how = folding(folder)
    found = first_clash(outs, how)
    if found is None:
        return None
    i, j = found
    return (f"{sources[i]} and {sources[j]} would both be {verb} to {outs[i]}: {folder} "
            f"{why_one(outs[i].name, outs[j].name, how)}, and holds {outs[i].name} and {outs[j].name} as one file")
