"""A 10 Hz log whose rests are looked for from the rate alone: none was used, and the warning did
not say that the sample rate is what leaves its rests too short in readings."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

import gyrocore

from .conftest import gyrocore_cli, real_log_path

SLOW = "at this sample rate a rest is too short in readings to be found from the rate alone"


def _warnings(log: gyrocore.Log) -> str:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        log.process("recommended", use_speed=False)
    return " | ".join(str(w.message) for w in caught)


@pytest.mark.parametrize("hz", [10, 100])
def test_a_slow_logs_rest_not_found_from_the_rate_names_the_sample_rate(tmp_path: Path, hz: int) -> None:
    path = tmp_path / "d.csv"
    gyrocore_cli("simulate", "--out", path, "--rate-hz", str(hz), "--duration", "150")
    said = _warnings(gyrocore.read_log(path))
    if hz == 10:  # its first 20 s are a rest, not found from blocks of 4 readings (a chance run of them is refused)
        assert "at this log's 10 Hz its blocks of 0.4 s" in said, said
        assert SLOW in said, said
    else:  # 25 readings a block: the rest is found
        assert SLOW not in said and "too short in readings" not in said, said


def test_a_slow_real_logs_rest_refused_as_short_names_the_sample_rate() -> None:
    path = real_log_path("kitti_2011_09_30_0018")
    if not path.exists():
        pytest.skip(f"{path} is not here")
    said = _warnings(gyrocore.read_log(path))
    # 2.71 s spans 10.8 blocks of 0.25 s, but its 27 readings only 6.5 blocks of 4
    assert "its 2.71 s are long enough, but at this log's 9.59 Hz they hold too few readings: a rest too short in " \
           "readings at this sample rate (one of 3.34 s or more is used)" in said, said
