"""A batch's inputs (paths, folders of logs, glob patterns) and its outputs' names, refusing an output
that would land among the inputs; :mod:`gyrocore.batch` re-exports the public names."""

from __future__ import annotations

import fnmatch
import glob
import os
from collections.abc import Iterable, Sequence
from pathlib import Path

from . import batch_names, io
from ._checks import warn
from .io._kitti import log_name, oxts_folder, sensor_folder_hint
from .io._logfolder import lacks_gyro
from .io import atomic
from .io._paths import check_readable, compressed_logs
from .io.writer import file_id


def expand_inputs(items: Iterable[str | Path]) -> list[Path]:
    """Files and folders from paths, folders of logs and glob patterns (``logs/**/*.csv``).

    A log folder or ROS 2 bag folder is one input; any other folder stands for the inputs directly
    in it. Every path named, and every name with an input's suffix that a folder or pattern gives,
    is kept even if it cannot be read (a dangling symbolic link, a loop, no permission, a log
    folder without gyro.csv): it fails later with its reason instead of silently dropping out, or
    its other files being read as logs. Raises ValueError for an item that
    matches nothing.
    """
    # each input with how it came: named (None), in a folder (the folder), or by a pattern (its text)
    found: list[tuple[Path, Path | str | None]] = []
    for item in items:
        named, matches = _matches(item)
        for m in matches:
            if not named and _in_log_folder(m):  # a pattern's reference.csv: part of its log
                m = m.parent
            if m.is_dir() and not _named_as_input(m):
                check_readable(m)
                entries = sorted(m.iterdir())
                inside = [c for c in entries if _named_as_input(c)]
                packed = compressed_logs(entries, io.FILE_SUFFIXES)  # the one listing
                if not inside and named:
                    raise ValueError(f"{m}: no logs in this folder ({', '.join(io.FILE_SUFFIXES)}, log or bag folders)"
                                     + (f"; it holds {packed}" if packed else _dataset_hint(m) or sensor_folder_hint(m)))
                if packed:
                    warn(f"{m}: {packed}")
                _warn_unsearched(m, [c for c in entries if c.is_dir() and not _named_as_input(c)])
                found += [(c, m) for c in inside]
            elif named or _named_as_input(m):
                found.append((m, None if named else str(item)))
    # One input per file or folder however it was reached (a pattern through a link that loops
    # back reaches the same files under ever longer names).
    unique: dict[Path, tuple[Path, Path | str | None]] = {}
    for entry in found:
        key = _identity(entry[0])
        kept = unique.setdefault(key, entry)
        if kept is entry:
            continue
        if isinstance(kept[1], str) and entry[1] == kept[1] and len(entry[0].parts) < len(kept[0].parts):
            # the pattern's matches come sorted, so "sub/loop/.../sub/x.csv" came before "sub/x.csv":
            # the file is named without the loop, in the place the first name took
            unique[key] = entry
        elif said := _collision(entry, kept):
            warn(said)
    return [p for p, _ in unique.values()]


def _collision(dropped: tuple[Path, Path | str | None], kept: tuple[Path, Path | str | None]) -> str | None:
    """What to say of an input ``dropped`` as the one ``kept`` (each with how it came: named, the
    folder it is in, a pattern), in either order: a path named that another entry reaches lost one
    name without a word. Nothing where neither was named, nor for a pattern that reaches a file
    named too (the user gave it once by name)."""
    (p, p_via), (k, k_via) = dropped, kept
    if p_via is not None and k_via is not None:
        return None
    if p != k:  # as itself and through a link
        return f"{p}: the same {'folder' if p.is_dir() else 'file'} as {k}; it is processed once, as {k}"
    if p_via is None and k_via is None:
        return f"{p}: given more than once; it is processed once, as {k}"
    folder = k_via if p_via is None else p_via
    if isinstance(folder, Path):
        return f"{p}: named, and also reached through the folder {folder}; it is processed once"
    return None


def _dataset_hint(folder: Path) -> str:
    """What to do with a folder that holds Parquet files in its subfolders only: a partitioned
    dataset (pyarrow's ``write_to_dataset``, Spark), which gyrocore does not read as one log."""
    parts = sorted(p for suffix in (".parquet", ".pq") for p in folder.glob(f"*/**/*{suffix}"))
    if not parts:
        return ""
    return (f"; it holds {len(parts)} Parquet file(s) in its subfolders (a partitioned dataset?), and gyrocore reads "
            "a log from one file: write it as one (pyarrow.parquet.write_table), or give the files "
            f"('{folder}/**/*.parquet') if each is a log of its own")


def _in_log_folder(path: Path) -> bool:
    """Whether ``path`` is a file of a log folder (its samples, reference, odometry, fixes)."""
    return path.is_file() and (io.is_input(path.parent) or lacks_gyro(path.parent))


def _identity(path: Path) -> Path:
    """The file or folder ``path`` stands for (itself where it cannot be resolved: a loop)."""
    try:
        return path.resolve(strict=True)
    except (OSError, RuntimeError):
        return path


def _warn_unsearched(folder: Path, subfolders: list[Path]) -> None:
    """Say which subfolders of a folder of logs were not searched (a folder stands for the inputs
    directly in it), and how to include them."""
    if subfolders:
        names = ", ".join(p.name for p in subfolders[:3]) + (" ..." if len(subfolders) > 3 else "")
        warn(f"{folder}: {len(subfolders)} subfolder(s) not searched ({names}): a folder stands for the logs "
             f"directly in it; give '{folder}/**/*.csv' (or the subfolders) to include theirs")


def check_outside_inputs(items: Iterable[str | Path], out: Path, inputs: Sequence[Path] = ()) -> None:
    """Refuse an output (file or folder) that is, or lies inside, a folder given as input (directly
    or by a pattern), or an output folder that holds one of ``inputs``: a later run over that
    folder would read the outputs as logs (and a CSV output could be its own input)."""
    io.check_not_input(out, [m for item in items for m in _matches(item)[1] if m.is_dir()])
    out_id = file_id(out)  # the same folder under another name too (another case, a bind mount)
    for p in inputs:
        # realpath, not Path.resolve, which raises RuntimeError on a link loop (see io.check_not_input)
        if os.path.realpath(p.parent) == os.path.realpath(out) or (out_id is not None and file_id(p.parent) == out_id):
            raise ValueError(
                f"refusing to write into {out}: it holds the input {p}, and the outputs would be read as "
                "logs by a later run over it; give an output folder outside the inputs"
            )


def check_unreached(items: Iterable[str | Path], outputs: Iterable[Path]) -> None:
    """Refuse an output (a file, or an output folder and the files it receives) that a glob pattern
    among ``items`` reaches once it exists: the run went through, and the same command again
    (``--skip-existing`` to go on after an interruption, ``--overwrite``) read the outputs as logs,
    or was refused as writing into its inputs."""
    patterns = [str(item) for item in items if not os.path.lexists(item)]
    for out in outputs:
        for pattern in patterns:
            if _reaches(pattern, out):
                raise ValueError(f"refusing to write {out}: the pattern {pattern!r} reaches it, and the same run "
                                 "again (--skip-existing to go on after an interruption, --overwrite) would read the "
                                 "outputs as logs; write them where the pattern does not reach")


def _reaches(pattern: str, path: Path) -> bool:
    """Whether ``glob.glob(pattern, recursive=True)`` gives ``path`` once it exists (by name: a link
    that leads there is not followed)."""
    return _glob_match(Path(os.path.abspath(pattern)).parts, Path(os.path.abspath(path)).parts)


def _glob_match(pattern: tuple[str, ...], parts: tuple[str, ...]) -> bool:
    """Whether the names ``parts`` match the glob pattern's names ``pattern`` as glob matches them: a
    ``**`` is any number of names, and a wildcard takes a hidden name (``.x``) only where the
    pattern's name starts with a dot too."""
    if not pattern:
        return not parts
    head, rest = pattern[0], pattern[1:]
    if head == "**":
        deeper = bool(parts) and not parts[0].startswith(".") and _glob_match(pattern, parts[1:])
        return deeper or _glob_match(rest, parts)
    if not parts or (parts[0].startswith(".") and not head.startswith(".")):
        return False
    return fnmatch.fnmatchcase(parts[0], head) and _glob_match(rest, parts[1:])


def _matches(item: str | Path) -> tuple[bool, list[Path]]:
    """Whether ``item`` names a path itself, and the paths it stands for (itself, or a pattern's
    matches); raises ValueError if it matches nothing."""
    p = Path(item)
    if os.path.lexists(p):  # also true for a dangling link, which exists() is not
        return True, [p]
    matches = [Path(m) for m in sorted(glob.glob(str(item), recursive=True))]
    if not matches:
        raise ValueError(f"{item}: no such file or folder, and no file matches it{_brackets_hint(str(item))}")
    return False, matches


def _brackets_hint(pattern: str) -> str:
    """How to match the brackets of a name (``run[1]/*.csv``, where ``[1]`` is a pattern's set of
    characters, which matched ``run1`` alone), where the pattern with them escaped matches."""
    literal = pattern.replace("[", "[[]")  # as glob.escape writes a bracket
    if literal == pattern or not glob.glob(literal, recursive=True):
        return ""
    return (f"; in a pattern, brackets are a set of characters ([1] matches 1): give {literal!r} to match "
            "the brackets in a name")


def _named_as_input(path: Path) -> bool:
    """An input, or a path that says it is one but cannot be read as one (a dangling link, a log
    folder without gyro.csv)."""
    return io.is_input(path) or lacks_gyro(path) or (not path.is_dir() and path.suffix.lower() in io.FILE_SUFFIXES)


def complete_output(path: str | Path) -> bool:
    """Whether a run finished the output ``path``: it is a regular file. Outputs are written under a
    hidden temporary name, synced and renamed over ``path`` only once every row is through
    (:mod:`gyrocore.io.atomic`), so an output that exists is complete; an interrupted or failed run
    leaves none (a hard kill may leave the hidden temporary file, never ``path``)."""
    return Path(path).is_file()


def output_paths(inputs: Sequence[str | Path], out_dir: str | Path, fmt: str,
                 named: Sequence[str | Path] = ()) -> list[Path]:
    """``out_dir/<input name without suffix>.<fmt>`` for each input (a KITTI drive's: the drive folder's
    name, also where its ``oxts`` folder is given, as every drive's is); refuses two inputs that would
    share an output, also through a symbolic link at an output's name (its target is written), and
    an output whose link leads to an input, into an input folder or to a file ``named`` by an
    option (``--params``, ``--calibration``): with ``--overwrite`` the file it leads to was
    replaced, an input by another input's heading, or one output by another's."""
    given, folder = [Path(p) for p in inputs], Path(out_dir)  # exported: paths as text failed
    outs = [folder / f"{_output_stem(p)}.{fmt}" for p in given]
    # realpath, not Path.resolve, which raises RuntimeError on a link loop (see io.check_not_input)
    real_inputs = {Path(os.path.realpath(p)): p for p in [*given, *map(Path, named)]}
    seen: dict[Path, tuple[Path, Path]] = {}
    for p, o in zip(given, outs):
        target = Path(os.path.realpath(o))
        if target in seen:
            first, first_out = seen[target]
            links = _through_links(first_out, o)
            raise ValueError(f"{first} and {p} would both be written to {target if links else o}{links}; "
                             f"{'remove the link, or ' if links else ''}process them separately")
        seen[target] = p, o
        hit = next((real_inputs[a] for a in (target, *target.parents) if a in real_inputs), None)
        if hit is not None:
            links = _through_links(o)
            raise ValueError(f"refusing to write {o} over or inside the input {hit}{links}; "
                             f"{'remove the link, or ' if links else ''}write the outputs elsewhere")
    _check_one_file_each(given, outs, folder)
    return outs


def _output_stem(path: Path) -> str:
    """The name of ``path``'s output without its suffix: a file's name without its suffix, a
    folder's name; a KITTI OXTS folder's, its drive's (``2011_09_30_drive_0034_sync/oxts`` gives
    ``2011_09_30_drive_0034_sync``: every drive's OXTS folder is named ``oxts``, and two drives
    into one output folder clashed)."""
    if not path.is_dir():
        return path.stem
    oxts = oxts_folder(path)
    return path.name if oxts is None else log_name(path, oxts)


def _check_one_file_each(inputs: Sequence[Path], outs: Sequence[Path], folder: Path) -> None:
    """Refuse two outputs whose names the output folder holds as one file (``Drive.csv`` and
    ``drive.csv`` where it ignores case): the second replaced the first without a word. The folder
    is asked (a file created and removed) only where some names could be one file there. Refuse
    too an output's name longer than the folder takes (an input's name of 252-255 bytes given
    another suffix, ``.parquet``): it failed after the work with ``File name too long``."""
    limit = atomic.name_max(folder)
    for p, o in zip(inputs, outs):
        if (size := len(os.fsencode(o.name))) > limit:
            raise ValueError(f"{p}: its output's name, {o.name}, is {size} bytes long, and {folder} takes names of "
                             f"{limit} at most; give the input a shorter name, or its output one of its own "
                             "(gyrocore process INPUT --out FILE)")
    said = batch_names.clash(inputs, outs, folder)
    if said is not None:
        raise ValueError(f"{said}; rename one of the inputs, or process them separately")


def _through_links(*outputs: Path) -> str:
    """How the outputs named are led elsewhere: the symbolic links among them, and where each leads."""
    links = [f"{o} is a symbolic link to {os.readlink(o)!r}" for o in dict.fromkeys(outputs) if o.is_symlink()]
    return f" ({'; '.join(links)})" if links else ""
