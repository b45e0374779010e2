"""Reading ROS bags: sensor_msgs/Imu ``angular_velocity.z`` stamped by ``header.stamp``.

A ROS 1 ``.bag`` file or a ROS 2 bag folder (``metadata.yaml``), read with rosbags (the optional
dependency ``gyrocore[ros]``), message after message.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._extras import require

if TYPE_CHECKING:
    from .source import GyroSource

_IMU = "sensor_msgs/msg/Imu"


def is_bag_folder(path: Path) -> bool:
    """Whether the folder ``path`` is a ROS 2 bag (it has ``metadata.yaml``)."""
    return (path / "metadata.yaml").is_file()


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
        raise ValueError(f"{path}: not a readable ROS bag ({e})") from None
    except Exception as e:  # rosbags' parser reports some corruption as AssertionError, KeyError, ...
        raise ValueError(f"{path}: not a readable ROS bag ({type(e).__name__}: {e})") from None
    return reader


def imu_topic(path: Path, topic: str | None) -> tuple[str, int]:
    """The Imu topic to read (``topic``, or the only one) and its number of messages."""
    reader = _bag_reader(path)
    try:
        counts: dict[str, int] = {}
        for c in reader.connections:
            if c.msgtype == _IMU:
                counts[c.topic] = counts.get(c.topic, 0) + c.msgcount
    finally:
        reader.close()
    found = ", ".join(sorted(counts)) or "none"
    if topic is None and len(counts) != 1:
        raise ValueError(f"{path}: give the topic (--topic); {_IMU} topics: {found}")
    topic = topic or next(iter(counts))
    if topic not in counts:
        raise ValueError(f"{path}: no {_IMU} messages on {topic} ({_IMU} topics: {found})")
    return topic, counts[topic]


def bag_chunks(src: GyroSource, rows: int) -> Iterator[tuple[np.ndarray, np.ndarray, float, int]]:
    """sensor_msgs/Imu ``angular_velocity.z`` [rad/s] stamped by ``header.stamp`` [ns].

    rosbags deserialises message by message (a Python loop: about 70 000 messages/s).
    """
    reader = _bag_reader(src.path)
    try:
        connections = [c for c in reader.connections if c.msgtype == _IMU and c.topic == src.options.topic]
        stamps: list[int] = []
        rates: list[float] = []
        done = 0
        for connection, _, raw in reader.messages(connections=connections):
            msg: Any = reader.deserialize(raw, connection.msgtype)
            stamps.append(msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec)
            rates.append(msg.angular_velocity.z)
            if len(stamps) == rows:
                done += rows
                yield np.array(stamps, dtype=np.int64), np.array(rates), 1e9, done
                stamps, rates = [], []
        if stamps:
            yield np.array(stamps, dtype=np.int64), np.array(rates), 1e9, done + len(stamps)
    except Exception as e:  # rosbags reports damage as its ReaderErrors, AssertionError, struct.error, ...
        raise ValueError(f"{src.path}: damaged bag ({type(e).__name__}: {e})") from None
    finally:
        reader.close()
