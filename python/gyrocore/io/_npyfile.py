"""Reading NumPy files a block of rows at a time: ``.npy`` with plain reads, ``.npz`` member by
member from its zip archive.

An ``.npy`` file holds a structured array with time and rate (or three-axis) fields, or a 2-D
array (samples x columns) in C or Fortran order; an ``.npz`` archive holds them as 1-D arrays.
"""

from __future__ import annotations

import io
import math
import zipfile
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

import numpy as np

from .._checks import warn
from ._columns import CHOOSE_COLUMNS, column_positions, warn_own_time_unit

if TYPE_CHECKING:
    from .read_options import ReadOptions
    from .source import GyroSource


def npy_header(path: Path | str, f: Any) -> tuple[tuple[int, ...], bool, np.dtype[Any]]:
    """(shape, Fortran order, dtype) of an .npy file (``path`` names it in an error, an .npz
    member by the archive and its name); ``f`` is left at the start of the data."""
    fmt = np.lib.format
    try:
        version = fmt.read_magic(f)
        if version == (1, 0):
            shape, fortran, dtype = fmt.read_array_header_1_0(f)
        else:
            shape, fortran, dtype = fmt.read_array_header_2_0(_ascii_header(f) if version == (3, 0) else f)
    except Exception as e:  # numpy's header parser raises ValueError, SyntaxError, TokenError, ...
        raise ValueError(f"{path}: not a NumPy .npy file ({type(e).__name__}: {e})") from None
    if any(n < 0 for n in shape):  # numpy's parser takes them; counted, they read as no samples
        raise ValueError(f"{path}: not a NumPy .npy file (its header's shape {shape} has a negative size)")
    return shape, fortran, dtype


def _ascii_header(f: Any) -> io.BytesIO:
    """The header of a version 3.0 file (UTF-8, which np.save writes for field names beyond
    Latin-1) as the version 2.0 reader takes it: in ASCII, other characters escaped in its string
    literals. numpy has no public reader of 3.0, and 2.0's decodes Latin-1 ('ω_z' read as 'Ï\x89_z').
    ``f`` is left at the start of the data."""
    size = f.read(4)
    text = f.read(int.from_bytes(size, "little")).decode("utf-8").encode("ascii", "backslashreplace")
    return io.BytesIO(len(text).to_bytes(4, "little") + text)


def npy_shape(path: Path, options: ReadOptions) -> tuple[int, ...]:
    """The shape of the .npy file ``path``, read from its header, warning where the file would be
    read otherwise than the options say or a user would expect: a time unit given for a duration
    field, which carries its own; a plain array of more than two columns read with the default
    rate column 1 (a ``t, gx, gy, gz`` array's is the x axis)."""
    with open(path, "rb") as f:
        shape, _, dtype = _sized_header(path, f)
    if dtype.names:
        if options.time in dtype.names:
            _warn_own_time_unit(path, options.time, dtype[options.time], options.time_unit)
    elif len(shape) == 2 and shape[1] > 2 and options.rate_col is None and options.gyro_cols is None:
        warn(f"{path}: a plain array of {shape[1]} columns, and the rate is read from column 1, the default: "
             "give rate_col (--rate-col N) to say which column is the yaw rate, or gyro_cols (--gyro-cols X,Y,Z) "
             "for three axes")
    return shape


def npy_fields(path: Path) -> list[str] | None:
    """The field names of a structured .npy file, which may state their units (``t_ms``,
    ``gyro_z [deg/s]``) as a CSV header's names do; None for a plain array (numbered columns)."""
    with open(path, "rb") as f:
        names = _sized_header(path, f)[2].names
    return None if names is None else list(names)


def npz_names(path: Path) -> list[str]:
    """The array names of the .npz archive ``path``, which may state their units as :func:`npy_fields`."""
    with _npz_archive(path) as archive:
        return [name for name, _ in _member_names(archive)]


def check_npz(path: Path, options: ReadOptions) -> None:
    """Open the .npz archive ``path`` (a file that is none is refused as it is opened) and warn
    where a time unit is given and its time array is a duration, which carries its own."""
    with _npz_archive(path) as archive:
        member = dict(_member_names(archive)).get(options.time)
        if member is not None and options.time_unit is not None:
            with _npz_member(path, archive, member) as f:
                dtype = _member_header(path, options.time, f)[2]
            _warn_own_time_unit(path, options.time, dtype, options.time_unit)


def _warn_own_time_unit(path: Path, name: str, dtype: np.dtype[Any], given: str | None) -> None:
    """Warn that ``given`` is not used where the time column ``name`` is a timedelta64."""
    if given is not None and dtype.kind in "mM":
        warn_own_time_unit(path, name, str(dtype), np.datetime_data(dtype)[0], given)


def npy_chunks(
    src: GyroSource, rows: int, columns: tuple[str, ...]
) -> Iterator[tuple[np.ndarray, list[np.ndarray], float, int]]:
    """Read an .npy file a block of rows at a time with plain reads (a memory map would count the
    whole file in the resident memory by the end). ``columns``: the fields to read beside the
    time, or for a plain 2-D array column numbers (the rate's default is 1)."""
    per_second = src.options.counts_per_second
    o = src.options
    with open(src.path, "rb") as f:
        shape, fortran, dtype = _sized_header(src.path, f)
        offset = f.tell()
        if dtype.names:
            if len(shape) != 1:
                raise ValueError(f"{src.path}: a structured array must be 1-D, got shape {shape}")
            column_positions(src.path, list(dtype.names), (o.time, *columns))
            for name in (o.time, *columns):
                _check_numbers(src, name, dtype[name], time=name == o.time)
            n = shape[0]
            for start in range(0, n, rows):
                rec = np.fromfile(f, dtype=dtype, count=min(rows, n - start))
                _check_read(src, rec, min(rows, n - start))
                yield rec[o.time], [rec[c] for c in columns], per_second, start + len(rec)
            return
        if len(shape) != 2 or shape[1] < 2:
            raise ValueError(
                f"{src.path}: expected a structured array with time and rate fields, or a 2-D array "
                f"(samples x columns), got shape {shape}"
            )
        _check_numbers(src, "the array", dtype)
        n, width = shape
        numbers = [_column_number(src, o.time_col, 0, width)]
        if columns == (o.rate,) and o.rate_col is None:  # a plain array's rate is column 1, not gyro_z
            numbers.append(1)
        else:
            numbers += [_column_number(src, c, 1, width) for c in columns]
        for start in range(0, n, rows):
            count = min(rows, n - start)
            if fortran:  # columns are contiguous: read the column segments
                cols = []
                for j in numbers:
                    f.seek(offset + (j * n + start) * dtype.itemsize)
                    cols.append(np.fromfile(f, dtype=dtype, count=count))
                    _check_read(src, cols[-1], count)
            else:
                block = np.fromfile(f, dtype=dtype, count=count * width)
                _check_read(src, block, count * width)
                block = block.reshape(count, width)
                cols = [block[:, j] for j in numbers]
            yield cols[0], cols[1:], per_second, start + count


def _check_numbers(src: GyroSource, name: str, dtype: np.dtype[Any], *, time: bool = False) -> None:
    """Real numbers; a time may also be a duration (timedelta64, which carries its unit) or a
    datetime64, read as seconds since the Unix epoch as a Parquet timestamp column is (what
    ``df.to_records()`` and ``np.save`` of pandas times write)."""
    if dtype.kind not in ("iufmM" if time else "iuf"):
        raise ValueError(f"{src.path}: {name} holds {dtype}, not real numbers{' or times' if time else ''}")
    if dtype.kind in "mM" and np.datetime_data(dtype)[0] in ("Y", "M", "generic"):
        raise ValueError(f"{src.path}: {name} holds {dtype}, which has no fixed length in seconds")


def _sized_header(path: Path, f: Any) -> tuple[tuple[int, ...], bool, np.dtype[Any]]:
    """:func:`npy_header` of a file that holds all its header claims: one that claims more is
    refused before any block is allocated (a shape of (3, 10**12) asked numpy for terabytes for the
    first block of rows), and before a warning about its shape would speak of columns it lacks."""
    shape, fortran, dtype = npy_header(path, f)
    need = math.prod(shape) * dtype.itemsize
    have = path.stat().st_size - f.tell()
    if have < need:
        raise ValueError(
            f"{path}: file ends early (truncated .npy): its header's shape {shape} of {dtype} takes "
            f"{need} bytes, the file holds {have} after the header"
        )
    return shape, fortran, dtype


def _check_read(src: GyroSource, data: np.ndarray, expected: int) -> None:
    """Refuse a block read short: the file shrank after its size was checked."""
    if len(data) != expected:
        raise ValueError(f"{src.path}: file ends early (truncated .npy)")


def _column_number(src: GyroSource, name: str | None, default: int, width: int) -> int:
    if name is None:
        return default
    if not name.isdigit() or int(name) >= width:
        raise ValueError(
            f"{src.path}: a plain 2-D array has numbered columns 0..{width - 1}; "
            f"got column {name!r} (give the column number)"
        )
    return int(name)


def npz_chunks(
    src: GyroSource, rows: int, columns: tuple[str, ...]
) -> Iterator[tuple[np.ndarray, list[np.ndarray], float, int]]:
    """Read the 1-D arrays of an .npz archive a block of rows at a time, each member streamed from
    the zip file (decompressed as it goes where it is compressed): the memory a block takes, not
    the archive's (``np.load`` reads a member whole, a 10 GB one into 10 GB)."""
    o = src.options
    wanted = (o.time, *columns)
    with _npz_archive(src.path) as archive, ExitStack() as members:
        # two members of one name (t.npy twice, or t and t.npy) are refused, not one of them taken
        # without a word
        members_named = _member_names(archive)
        try:
            column_positions(src.path, [name for name, _ in members_named], wanted, _choose_members(members_named))
        except ValueError as e:
            raise ValueError(f"{e}{_table_members(src.path, archive, members_named)}") from None
        names = dict(members_named)
        streams, dtypes, lengths = {}, {}, {}
        for name in wanted:
            f = members.enter_context(_npz_member(src.path, archive, names[name]))
            shape, _, dtype = _member_header(src.path, name, f)
            _check_numbers(src, f"array {name}", dtype, time=name == o.time)
            if len(shape) != 1:
                raise ValueError(f"{src.path}: array {name} must be 1-D, got shape {shape}")
            have = archive.getinfo(names[name]).file_size - f.tell()
            if have < shape[0] * dtype.itemsize:  # before any block is allocated for it
                raise ValueError(f"{src.path}: member {name} ends early (truncated .npz): its header's shape "
                                 f"{shape} of {dtype} takes {shape[0] * dtype.itemsize} bytes, it holds {have}")
            streams[name], dtypes[name], lengths[name] = f, dtype, shape[0]
        n = lengths[o.time]
        for name in wanted:
            if lengths[name] != n:
                raise ValueError(f"{src.path}: {o.time} has {n} samples but {name} has {lengths[name]}")
        for start in range(0, n, rows):
            count = min(rows, n - start)
            block = [_member_block(src.path, name, streams[name], dtypes[name], count) for name in wanted]
            yield block[0], block[1:], o.counts_per_second, start + count


def _choose_members(members_named: list[tuple[str, str]]) -> str:
    """What to do about a missing array: the reading options; for the arrays ``np.savez`` names
    ``arr_0``, ``arr_1``, ... when given without names, which of them to give (the order is the
    caller's, so both ways are said)."""
    names = [name for name, _ in members_named]
    if len(names) < 2 or names != [f"arr_{k}" for k in range(len(names))]:
        return CHOOSE_COLUMNS
    return (f"{CHOOSE_COLUMNS}; np.savez(file, t, rate) names its arrays arr_0, arr_1, ...: give "
            "time_col='arr_0', rate_col='arr_1' (--time-col arr_0 --rate-col arr_1) where they were saved in "
            "that order, or save them by name, np.savez(file, t=t, gyro_z=rate)")


def _table_members(path: Path, archive: zipfile.ZipFile, members_named: list[tuple[str, str]]) -> str:
    """For a missing column: the first member that is a table (samples x columns), which no
    column option reads, and how to save it; empty where there is none."""
    for name, member in members_named:
        with _npz_member(path, archive, member) as f:
            shape = _member_header(path, name, f)[0]
        if len(shape) == 2:
            return (f"; its {name} is a 2-D array of shape {shape}, and an .npz archive is read one 1-D array per "
                    f"column: save the table as an .npy file (np.save; its columns are numbered, the time 0 and "
                    f"the rate 1 unless --time-col/--rate-col say), or each column by name, np.savez(file, t={name}[:, 0], gyro_z={name}[:, 1])")
    return ""


def _member_names(archive: zipfile.ZipFile) -> list[tuple[str, str]]:
    """(array name, member name) of each member, the array named as np.load names it."""
    return [(n[:-4] if n.endswith(".npy") else n, n) for n in archive.namelist()]


@contextmanager
def _npz_archive(path: Path) -> Iterator[zipfile.ZipFile]:
    """The .npz file ``path`` open as a zip archive; bad bytes are a ValueError naming it."""
    try:
        archive = zipfile.ZipFile(path)
    except Exception as e:  # BadZipFile, EOFError, ... on bad bytes
        raise ValueError(f"{path}: not a readable NumPy .npz file ({type(e).__name__}: {e})") from None
    with archive:
        yield archive


@contextmanager
def _npz_member(path: Path, archive: zipfile.ZipFile, member: str) -> Iterator[IO[bytes]]:
    try:
        f = archive.open(member)
    except Exception as e:  # a damaged local header, an unsupported compression, encryption
        raise ValueError(f"{path}: not a readable NumPy .npz file ({type(e).__name__}: {e})") from None
    with f:
        yield f


def _member_header(path: Path, name: str, f: IO[bytes]) -> tuple[tuple[int, ...], bool, np.dtype[Any]]:
    """The .npy header of the member ``name``: one that is no .npy (np.load's raw bytes) is named."""
    try:
        magic = f.read(len(np.lib.format.MAGIC_PREFIX))
    except Exception as e:
        raise ValueError(f"{path}: damaged .npz file (member {name}: {type(e).__name__}: {e})") from None
    if magic != np.lib.format.MAGIC_PREFIX:
        raise ValueError(f"{path}: member {name} is not a NumPy array")
    # the header read to its end and no further: a seek would stop zipfile checking the CRC
    version = f.read(2)
    size = f.read(2 if version[:1] == b"\x01" else 4)
    length = int.from_bytes(size, "little") if len(size) in (2, 4) else 0
    header = io.BytesIO(magic + version + size + f.read(length))
    return npy_header(f"{path}: member {name}", header)


def _member_block(path: Path, name: str, f: IO[bytes], dtype: np.dtype[Any], count: int) -> np.ndarray:
    """The next ``count`` values of a member; a short read or a damaged (bad CRC, bad deflate)
    member is a ValueError naming the file and member."""
    try:
        data = f.read(count * dtype.itemsize)
    except Exception as e:  # zipfile's BadZipFile (CRC), zlib.error
        raise ValueError(f"{path}: damaged .npz file (member {name}: {type(e).__name__}: {e})") from None
    if len(data) != count * dtype.itemsize:
        raise ValueError(f"{path}: member {name} ends early (truncated .npz)")
    return np.frombuffer(data, dtype=dtype)
