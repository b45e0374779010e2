"""What the command line says of its own arguments and of what it did: an empty name is refused
as one, a message states only what is so of the file, and a value is named as the user wrote it."""

from __future__ import annotations

from pathlib import Path

import pytest

from .test_batch import synthetic_csv
from .test_errors_named import run_cli

_BLANK = "no name (an empty shell variable?)"


@pytest.mark.parametrize("args, option", [
    (("process", "", "-o", "OUT/"), "IN"),
    (("process", "LOG", "-o", "h.csv", "--calibration", ""), "--calibration"),
    (("process", "LOG", "-o", "h.csv", "--fixes", ""), "--fixes"),
    (("process", "LOG", "-o", "h.csv", "--params", " "), "--params"),
    (("allan", ""), "input"),
    (("allan", "LOG", "--plot", ""), "--plot"),
    (("calibrate", "LOG", "--save", ""), "--save"),
    (("calibrate", "LOG", "--reference", ""), "--reference"),
    (("evaluate", "", "--preset", "raw"), "LOGDIR"),
    (("evaluate", "LOG", "--preset", "raw", "--plot-dir", ""), "--plot-dir"),
    (("simulate", "-o", ""), "-o/--out"),
    (("tune", "LOG", "-o", ""), "-o/--out"),
    (("reproduce", "-o", ""), "-o/--out"),
])
def test_an_empty_name_is_refused_for_every_path(tmp_path: Path, args: tuple[str, ...], option: str,
                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    # "" (an unset shell variable) was the current folder: every log in it processed, a plot written there
    log = synthetic_csv(tmp_path / "log.csv", 3000)
    monkeypatch.chdir(tmp_path)
    proc = run_cli(*(str(log) if a == "LOG" else a for a in args))
    assert proc.returncode == 2
    blank = next(a for a in args if not a.strip())
    assert proc.stderr.splitlines()[-1].endswith(f"error: argument {option}: {blank!r}: {_BLANK}")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["log.csv"]
