"""Reading Parquet files: the time and rate (or three-axis) columns, a batch of rows at a time.

A timestamp or duration column carries its own unit; numeric columns may be integers, floats or
decimals (nulls in the rate become NaN).
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._extras import require
from ._columns import column_positions, first_null, warn_own_time_unit
from ._paths import arrow_path
from .units import TIME_UNITS

if TYPE_CHECKING:
    import pyarrow as pa

    from .source import GyroSource


def parquet_file(path: Path) -> Any:
    """The file opened as a pyarrow ``ParquetFile`` (its metadata read, no data yet)."""
    pa = require("pyarrow", f"{path}: reading Parquet files")
    pq = require("pyarrow.parquet", f"{path}: reading Parquet files")

    try:
        return pq.ParquetFile(pa.OSFile(arrow_path(path)))
    except (pa.ArrowInvalid, OSError) as e:
        raise ValueError(f"{path}: not a readable Parquet file ({e})") from None


def warn_given_time_unit(path: Path, pf: Any, time_col: str, given: str | None) -> None:
    """Warn that a time unit the user gave (``given``) is not used where the time column is a
    timestamp or duration type, which carries its own: the user expects the option to act."""
    import pyarrow as pa

    if given is None or time_col not in pf.schema_arrow.names:
        return
    kind = pf.schema_arrow.field(time_col).type
    if pa.types.is_timestamp(kind) or pa.types.is_duration(kind):
        warn_own_time_unit(path, time_col, str(kind), kind.unit, given)


#: The fewest rows a Parquet file is read in at a time (1 MiB for a time and a rate column).
READ_ROWS = 1 << 16


def parquet_chunks(
    src: GyroSource, rows: int, columns: tuple[str, ...]
) -> Iterator[tuple[np.ndarray, list[np.ndarray], float, int]]:
    o = src.options
    pf = parquet_file(src.path)
    header = pf.schema_arrow.names
    import pyarrow as pa

    times = tuple(f.name for f in pf.schema_arrow if pa.types.is_timestamp(f.type))
    column_positions(src.path, header, (o.time, *columns), times=times)

    first = 0
    # read in batches of at least READ_ROWS, which GyroSource.chunks cuts into chunks of ``rows``
    # as it cuts a CSV file's blocks: a batch of one row from pyarrow took 75 us, so one-sample
    # chunks read 25 times slower than from a CSV file
    batches = pf.iter_batches(batch_size=max(rows, READ_ROWS), columns=[o.time, *columns])
    while True:
        try:
            batch = next(batches, None)
        except (pa.ArrowException, OSError) as e:  # a corrupt page or schema
            raise ValueError(f"{src.path}: unreadable Parquet data after row {first} ({e})") from None
        if batch is None:
            return
        if batch.num_columns != 1 + len(columns):
            named = ", ".join(map(repr, (o.time, *columns)))
            raise ValueError(f"{src.path}: columns {named} do not read as {1 + len(columns)} columns")
        t, per_second = _arrow_time(src, batch.column(0), first)
        values = [_arrow_numbers(src, c, batch.column(i + 1)) for i, c in enumerate(columns)]
        first += batch.num_rows
        yield t, values, per_second, first


def _arrow_time(src: GyroSource, array: pa.Array, first: int) -> tuple[np.ndarray, float]:
    """Timestamps as numbers and their counts per second (a timestamp type carries its unit)."""
    import pyarrow as pa

    name = src.options.time
    bad = first_null(array)
    if bad is not None:
        raise ValueError(f"{src.path}: {src.where(first + bad)}, column {name}: empty timestamp")
    if pa.types.is_timestamp(array.type) or pa.types.is_duration(array.type):
        per_second = TIME_UNITS[array.type.unit]
        return array.cast(pa.int64()).to_numpy(), per_second
    return _arrow_numbers(src, name, array), src.options.counts_per_second


def _arrow_numbers(src: GyroSource, name: str, array: pa.Array) -> np.ndarray:
    """A numeric column as numpy (nulls become NaN); other types are an error."""
    import pyarrow as pa

    t = array.type
    if not (pa.types.is_integer(t) or pa.types.is_floating(t) or pa.types.is_decimal(t)):
        raise ValueError(f"{src.path}: column {name} holds {t}, not numbers")
    if array.null_count or pa.types.is_decimal(t):
        array = array.cast(pa.float64())
    values: np.ndarray = array.to_numpy(zero_copy_only=False)
    return values
