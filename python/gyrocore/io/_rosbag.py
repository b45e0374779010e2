"""Reading ROS bags: sensor_msgs/Imu ``angular_velocity.x|y|z`` (``z`` unless told, or all three)
and ``linear_acceleration`` stamped by ``header.stamp``.

A ROS 1 ``.bag`` file or a ROS 2 bag folder (``metadata.yaml``), read with rosbags (the optional
dependency ``gyrocore[ros]``), message after message.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._checks import did_you_mean
from .._extras import require

if TYPE_CHECKING:
    from .read_options import ReadOptions
    from .source import GyroSource

_IMU = "sensor_msgs/msg/Imu"
#: The fields of an Imu message read as a column: the gyro's and the accelerometer's axes.
GYRO_FIELDS = ("angular_velocity.x", "angular_velocity.y", "angular_velocity.z")
ACCEL_FIELDS = ("linear_acceleration.x", "linear_acceleration.y", "linear_acceleration.z")


def is_bag_folder(path: Path) -> bool:
    """Whether the folder ``path`` is a ROS 2 bag (it has ``metadata.yaml``)."""
    return (path / "metadata.yaml").is_file()


def storage_file_hint(path: Path) -> str:
    """A hint for a file of a ROS 2 bag (its ``.db3`` or ``.mcap``) given in place of the bag's
    folder, which alone holds what reading it takes (metadata.yaml); else empty."""
    if path.suffix.lower() in (".db3", ".mcap") and is_bag_folder(path.parent):
        return f"; {path.name} is a file of the ROS 2 bag {path.parent}: give the bag's folder"
    return ""


def _bag_reader(path: Path) -> Any:
    """An open rosbags AnyReader (ROS 1 or ROS 2)."""
    highlevel = require("rosbags.highlevel", f"{path}: reading ROS bags")
    typesys = require("rosbags.typesys", f"{path}: reading ROS bags")
    AnyReader, AnyReaderError = highlevel.AnyReader, highlevel.AnyReaderError
    Stores, get_typestore = typesys.Stores, typesys.get_typestore
    try:
        # Bags without embedded definitions (ROS 2 before Iron) use the current standard types.
        reader = AnyReader([path], default_typestore=get_typestore(Stores.LATEST))
        reader.open()
    except AnyReaderError as e:
        yaml = _yaml_error(e)
        if yaml is not None:
            raise ValueError(f"{path / 'metadata.yaml'}: {yaml}: not valid YAML, so {path} is not a readable "
                             "ROS 2 bag; mend the file, or take it from the bag's recording again") from None
        raise ValueError(f"{path}: not a readable ROS bag ({_joined_message(e)})") from None
    except Exception as e:  # rosbags' parser reports some corruption as AssertionError, KeyError, ...
        raise ValueError(f"{path}: not a readable ROS bag ({type(e).__name__}: {_joined_message(e)})") from None
    return reader


def _yaml_error(error: BaseException) -> str | None:
    """Where and what the YAML error behind ``error`` is (``line 5, column 9: expected ',' or ']',
    but got ':' (while parsing a flow sequence)``), or None. The YAML parser's own message spans
    several lines, with a drawing of the spot, which an error of one line cannot carry."""
    cause: BaseException | None = error
    while cause is not None:
        mark, problem = getattr(cause, "problem_mark", None), getattr(cause, "problem", None)
        if mark is not None and problem:
            context = getattr(cause, "context", None)
            return f"line {mark.line + 1}, column {mark.column + 1}: {problem}" + (f" ({context})" if context else "")
        cause = cause.__cause__ or cause.__context__
    return None


def _joined_message(error: BaseException) -> str:
    """``error``'s message on one line (rosbags passes on others' messages of several lines)."""
    return " ".join(str(error).split())


def imu_topic(path: Path, topic: str | None) -> tuple[str, int]:
    """The Imu topic to read (``topic``, or the only one) and its number of messages.

    Raises:
        ValueError: a bag without an Imu topic (naming the topics it has, with their types), a
            ``topic`` that is not one (another type's, or a likely meant one), several Imu topics
            and no ``topic``, or an Imu topic that holds no message.
    """
    reader = _bag_reader(path)
    try:
        counts: dict[str, int] = {}
        others: dict[str, str] = {}  # the other topics and their types, to say what the bag has
        for c in reader.connections:
            if c.msgtype == _IMU:
                counts[c.topic] = counts.get(c.topic, 0) + c.msgcount
            else:
                others.setdefault(c.topic, c.msgtype)
    finally:
        reader.close()
    found = ", ".join(sorted(counts)) or "none"
    if not counts:  # "give the topic (--topic)" would not help: no topic is one
        has = ", ".join(f"{t} ({m})" for t, m in sorted(others.items())) or "no topic at all"
        raise ValueError(f"{path}: no {_IMU} topic, and gyrocore reads a bag's gyro from one; the bag has {has}")
    if topic is None and len(counts) != 1:
        raise ValueError(f"{path}: give the topic (--topic); {_IMU} topics: {found}")
    topic = topic or next(iter(counts))
    if topic not in counts:
        if topic in others:
            raise ValueError(f"{path}: {topic} carries {others[topic]}, not {_IMU} ({_IMU} topics: {found})")
        raise ValueError(f"{path}: no {_IMU} messages on {topic}{did_you_mean(topic, counts)} ({_IMU} topics: {found})")
    if not counts[topic]:
        raise ValueError(f"{path}: the {_IMU} topic {topic} holds no message, so no samples")
    return topic, counts[topic]


def bag_columns(path: Path, options: ReadOptions) -> ReadOptions:
    """``options`` with the Imu fields a bag is read by: ``rate_col`` (default
    ``angular_velocity.z``), or for three-axis input ``gyro_cols`` and, to measure up,
    ``accel_cols`` (default all three axes).

    Raises:
        ValueError: a name that is not such a field, listing the valid ones.
    """
    if not options.three_axis:
        rate = options.rate_col or GYRO_FIELDS[2]
        _check_fields(path, "rate_col", (rate,), GYRO_FIELDS)
        return replace(options, rate_col=rate)
    gyro = options.gyro_cols or GYRO_FIELDS
    _check_fields(path, "gyro_cols", gyro, GYRO_FIELDS)
    accel = options.accel_cols
    if options.measures_up:
        accel = accel or ACCEL_FIELDS
        _check_fields(path, "accel_cols", accel, ACCEL_FIELDS)
    return replace(options, gyro_cols=gyro, accel_cols=accel)


def _check_fields(path: Path, name: str, given: tuple[str, ...], valid: tuple[str, ...]) -> None:
    bad = [v for v in given if v not in valid]
    if bad:
        option = "--" + name.replace("_", "-")
        raise ValueError(
            f"{path}: {name} ({option}) {', '.join(map(repr, bad))} is not a field of {_IMU}; "
            f"a bag reads {', '.join(valid)}"
        )


def bag_chunks(
    src: GyroSource, rows: int, columns: tuple[str, ...]
) -> Iterator[tuple[np.ndarray, list[np.ndarray], float, int]]:
    """The Imu fields ``columns`` (``angular_velocity.z``, ...) stamped by ``header.stamp`` [ns].

    rosbags deserialises message by message (a Python loop: about 70 000 messages/s).
    """
    for stamps, values, done in _messages(src, rows, columns):
        _refuse_unset_stamps(src, stamps, done - len(stamps))
        yield stamps, values, 1e9, done


def _refuse_unset_stamps(src: GyroSource, stamps: np.ndarray, first: int) -> None:
    """Refuse a header.stamp of 0 after the first message: a driver that never sets its stamps
    leaves them 0, and the pipeline's "t[1] = 0 follows 0 (sort the log ...)" would not say so
    (the first message may be stamped 0 by a simulated clock)."""
    unset = np.flatnonzero(stamps == 0)
    unset = unset[unset + first > 0]
    if len(unset):
        k = first + int(unset[0])
        raise ValueError(
            f"{src.path}: message {k} on {src.options.topic}: header.stamp is 0, a stamp its driver never set "
            "(a message is read at its header.stamp): stamp the messages when recording, or restamp the bag"
        )


def _messages(
    src: GyroSource, rows: int, columns: tuple[str, ...]
) -> Iterator[tuple[np.ndarray, list[np.ndarray], int]]:
    """Blocks of ``rows`` messages: their stamps [ns], one array per field, messages read so far."""
    fields = [tuple(c.split(".")) for c in columns]
    reader = _bag_reader(src.path)
    try:
        connections = [c for c in reader.connections if c.msgtype == _IMU and c.topic == src.options.topic]
        stamps: list[int] = []
        values: list[list[float]] = []
        done = 0
        for connection, _, raw in reader.messages(connections=connections):
            msg: Any = reader.deserialize(raw, connection.msgtype)
            stamps.append(msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec)
            values.append([getattr(getattr(msg, vector), axis) for vector, axis in fields])
            if len(stamps) == rows:
                done += rows
                yield _block(stamps, values, len(columns)) + (done,)
                stamps, values = [], []
        if stamps:
            yield _block(stamps, values, len(columns)) + (done + len(stamps),)
    except Exception as e:  # rosbags reports damage as its ReaderErrors, AssertionError, struct.error, ...
        raise ValueError(f"{src.path}: damaged bag ({type(e).__name__}: {_joined_message(e)})") from None
    finally:
        reader.close()


def _block(stamps: list[int], values: list[list[float]], width: int) -> tuple[np.ndarray, list[np.ndarray]]:
    """The stamps and one array per field of a block of messages."""
    table = np.array(values, dtype=np.float64).reshape(len(stamps), width)
    return np.array(stamps, dtype=np.int64), [table[:, j] for j in range(width)]
