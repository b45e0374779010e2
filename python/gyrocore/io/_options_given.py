"""The reading options given for an input, judged once it is open (:func:`checked_options`): one
that the input needs and lacks is an error, one that it would ignore is an error or a warning."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._checks import warn

if TYPE_CHECKING:
    from .read_options import ReadOptions
    from .source import GyroSource


def checked_options(source: GyroSource, given: ReadOptions) -> GyroSource:
    """``source`` once the options ``given`` (before the input's own, such as a bag's) are judged."""
    return _note_bag_times(_note_delimiter(_check_topic(_check_axes(source))), given)


def _check_axes(source: GyroSource) -> GyroSource:
    """A three-axis file names its gyro columns, and its accelerometer's where up is measured
    (a bag has them by name)."""
    o = source.options
    if o.three_axis and o.gyro_cols is None:
        raise ValueError(
            f"{source.data_path}: three-axis input (up, accel_cols) needs the gyro's three columns: "
            "gyro_cols (--gyro-cols GX,GY,GZ)"
        )
    if o.three_axis and o.measures_up and o.accel_cols is None:
        raise ValueError(
            f"{source.data_path}: up is measured from the accelerometer: give its three columns, accel_cols "
            "(--accel-cols AX,AY,AZ), or give up (--up x|y|z|-x|-y|-z|X,Y,Z)"
        )
    return source


_KIND_NAMES = {"csv": "CSV file", "parquet": "Parquet file", "npy": ".npy file", "npz": ".npz file",
               "kitti oxts": "KITTI OXTS folder"}


def _check_topic(source: GyroSource) -> GyroSource:
    """A topic is a bag's: given for another input, it would be ignored without a word."""
    if source.options.topic is not None and source.kind != "bag":
        raise ValueError(
            f"{source.path}: topic {source.options.topic!r} (--topic) picks a ROS bag's Imu topic, and this "
            f"is a {_KIND_NAMES.get(source.kind, source.kind)}: leave it out for this input"
        )
    return source


def _note_delimiter(source: GyroSource) -> GyroSource:
    """A delimiter given for an input that is no CSV file was ignored without a word: a warning
    says so (not an error: a batch of CSV and Parquet files takes one ``--delimiter`` for its CSV
    files)."""
    if source.options.delimiter is not None and source.kind not in ("csv", "log folder"):
        warn(
            f"{source.path}: delimiter {source.options.delimiter!r} (--delimiter) separates a CSV file's fields, "
            f"and this is a {_KIND_NAMES.get(source.kind, source.kind)}: it is read without one"
        )
    return source


def _note_bag_times(source: GyroSource, given: ReadOptions) -> GyroSource:
    """A time column or unit ``given`` for a ROS bag was ignored without a word (its messages are
    read at their ``header.stamp``, in ns): a warning says so (not an error, as for a delimiter: a
    batch of CSV files and bags takes one ``--time-unit`` for its CSV files). Seconds, what the
    stamps are read as (and what a bag's own options say once it is open), say nothing."""
    if source.kind != "bag":
        return source
    for name, value in (("time_col", given.time_col), ("time_unit", given.time_unit)):
        if value is not None and value != "s":
            warn(f"{source.path}: {name} {value!r} (--{name.replace('_', '-')}) is not used: a ROS bag's messages "
                 "are read at their header.stamp (seconds and nanoseconds)")
    return source
