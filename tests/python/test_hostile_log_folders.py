"""A log folder's files under hostile input: each bad value named by its file, line and column,
each file's source named where its value is refused, and a reference that scores only part of
the log said so."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import gyrocore

from .test_hostile_inputs import log_folder_with

#: Odometry samples inside the synthetic drive of :func:`log_folder_with` (1.7e9 s on, 30 s).
ODOMETRY = ["1700000000.5,0", "1700000010.5,1", "1700000020.5,2"]


@pytest.mark.parametrize(
    ("line", "value", "message"),
    [
        (3, "1700000010.5,nan", "line 3, column 2 (speed): nan; the odometry's t and speed must be finite numbers"),
        (4, "inf,2", "line 4, column 1 (t): inf; the odometry's t and speed must be finite numbers"),
        (4, "1700000010.5,2", "line 4, column 1 (t): 1700000010.5 does not come after 1700000010.5 on line 3; "
                              "the odometry's times must strictly increase"),
        (3, "1700000000.25,1", "line 3, column 1 (t): 1700000000.25 does not come after 1700000000.5 on line 2; "
                               "the odometry's times must strictly increase"),
    ],
)
def test_a_bad_odometry_sample_is_named_by_its_file_line_and_column(
    tmp_path: Path, line: int, value: str, message: str
) -> None:
    # it was "odometry speed: speed[1] is nan", an index, read as the log's
    rows = list(ODOMETRY)
    rows[line - 2] = value
    folder = log_folder_with(tmp_path, "odometry.csv", "t,speed\n" + "\n".join(rows) + "\n")
    where = folder / "odometry.csv"
    with pytest.raises(ValueError, match=f"^{re.escape(f'{where}: {message}')}"):
        gyrocore.read_log(folder)
