"""Reading gyro logs and writing heading tables.

Every reader returns SI units: timestamps [s] and yaw rate [rad/s], counter-clockwise positive.

============  =====================================================================================
format        what is read
============  =====================================================================================
CSV           a header line (after ``#`` comment lines), then one sample per line, in UTF-8;
              columns ``time_col`` (default ``t``) and ``rate_col`` (default ``gyro_z``); other
              columns are ignored (pyarrow, streaming)
Parquet       columns ``time_col`` and ``rate_col``; a timestamp column carries its own unit
``.npy``      a structured array with fields ``time_col``/``rate_col``, or a 2-D array
              (samples x columns: time in column 0, rate in column 1 unless numbered otherwise)
``.npz``      1-D arrays named ``time_col`` and ``rate_col`` (streamed member by member)
log folder    ``gyro.csv`` (t, gyro_z), ``reference.csv`` (t, heading, x, y), ``odometry.csv``
              (t, speed) and ``meta.json`` with the ``stationary`` rest window
ROS bag       a ROS 1 ``.bag`` file or a ROS 2 bag folder (``metadata.yaml``): sensor_msgs/Imu
              ``angular_velocity.z`` (or the ``rate_col`` ``angular_velocity.x`` or ``.y``) stamped
              by ``header.stamp`` (needs ``gyrocore[ros]``)
KITTI OXTS    a KITTI raw drive's ``oxts`` folder (or the drive folder): ``wz`` at the times of
              ``timestamps.txt``, with ``yaw`` (and x, y from lat, lon) as the reference and
              ``vf`` as the odometry
============  =====================================================================================

Three-axis input (``gyro_cols``, ``accel_cols``, ``up``): the yaw rate is the gyro's component along
``up``, the sensor axis that points up, given or measured as the mean accelerometer reading over
the rest window (``up_window``, else a log folder's); a bag's gyro is ``angular_velocity`` and its
accelerometer ``linear_acceleration``.

Units of the file are options: ``time_unit`` one of ``s``, ``ms``, ``us``, ``ns`` and ``rate_unit``
``rad/s`` or ``deg/s``; a sanity check warns when the values look like another unit. Malformed
files raise ``ValueError`` naming the file, line and column (or the row of a Parquet or NumPy file,
the message of a bag).

:func:`open_source` reads any of them chunk after chunk with flat memory (what ``gyrocore process``
and :mod:`gyrocore.batch` use); :func:`read_log` reads a whole log into memory. Heading tables are
written by :class:`HeadingWriter` through a temporary file that is renamed at the end.

Modules (import the names from ``gyrocore.io``, which has them all):

==================  ===============================================================================
``source``          :class:`ReadOptions`, :func:`open_source`, :class:`GyroSource` and its chunks
``log``             :func:`read_log` and :class:`Log`: a whole log in memory
``units``           the units of a file and :class:`UnitCheck`
``writer``          :class:`HeadingWriter`, :func:`convert_heading` and the checks of an output path
``atomic``          :class:`StagedFile` and :func:`atomic_path`: files that appear whole or not at all
``_csvfile``        the CSV reader (pyarrow), with :func:`read_csv_columns`
``_parquetfile``    the Parquet reader
``_npyfile``        the ``.npy`` and ``.npz`` reader
``_rosbag``         the ROS bag reader (rosbags)
``_logfolder``      the log-folder layout: ``meta.json``, ``reference.csv``, ``odometry.csv``
``_kitti``          KITTI raw OXTS folders (``timestamps.txt``, ``data/*.txt``, ``dataformat.txt``)
``_columns``        what the readers share: finding the named columns, column data as arrays
``_axes``           three-axis input: ``up`` given or measured, the projection ``gyro . up``
``_paths``          what stands where a file is read: a regular file, nothing, or an error naming it
==================  ===============================================================================
"""

from __future__ import annotations

from .._checks import public_dir
from ._axes import GRAVITY, UP_HELP
from ._csvfile import CSV_BLOCK_BYTES, read_csv_columns
from ._logfolder import read_reference_file
from .atomic import StagedFile, atomic_path
from .log import Log, read_log
from .read_options import ReadOptions
from .source import DEFAULT_CHUNK_ROWS, FILE_SUFFIXES, Chunk, GyroSource, is_input, open_source
from .units import EPOCH_LIMIT, RATE_UNITS, SHORT_INTERVAL, SMALL_RATE_DPS, TIME_UNITS, UnitCheck
from .writer import (
    HEADING_CONVENTIONS,
    OUTPUT_COLUMNS,
    PARQUET_ROW_GROUP,
    HeadingWriter,
    check_columns,
    check_not_input,
    check_output,
    convert_heading,
    output_format,
)

__all__ = [
    "CSV_BLOCK_BYTES",
    "DEFAULT_CHUNK_ROWS",
    "EPOCH_LIMIT",
    "FILE_SUFFIXES",
    "GRAVITY",
    "HEADING_CONVENTIONS",
    "OUTPUT_COLUMNS",
    "PARQUET_ROW_GROUP",
    "RATE_UNITS",
    "SHORT_INTERVAL",
    "SMALL_RATE_DPS",
    "TIME_UNITS",
    "UP_HELP",
    "Chunk",
    "GyroSource",
    "HeadingWriter",
    "Log",
    "ReadOptions",
    "StagedFile",
    "UnitCheck",
    "atomic_path",
    "check_columns",
    "check_not_input",
    "check_output",
    "convert_heading",
    "is_input",
    "open_source",
    "output_format",
    "read_csv_columns",
    "read_log",
    "read_reference_file",
]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__
