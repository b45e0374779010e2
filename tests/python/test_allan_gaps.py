"""An Allan deviation across a long gap is refused, naming the gap and what to do instead (it had
resampled the whole record at the gap's scale); the advice names options that exist."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from gyrocore import allan

STEP = 0.01
PART = np.arange(0, 100, STEP)


def record(gap: float) -> tuple[np.ndarray, np.ndarray]:
    t = np.concatenate([PART, PART[-1] + gap + PART])
    return t, np.random.default_rng(0).normal(0.0, 0.01, len(t))


def test_a_gap_is_refused_with_where_it_is() -> None:
    t, r = record(gap=5.0)  # 500 intervals
    with pytest.raises(ValueError) as e:
        allan.deviation_from_timestamps(t, r)
    assert str(e.value).startswith(
        f"the record has a gap of 5 s from t[9999] = {t[9999]} to t[10000] = {t[10000]} s, 500 times its median "
        "interval (0.01 s); an Allan deviation needs a continuous record"
    )
    # either part alone is analysed at the sampling interval
    part = allan.deviation_from_timestamps(t[:10000], r[:10000])
    assert part.dt == pytest.approx(STEP)


def test_jitter_and_short_dropouts_are_not_gaps() -> None:
    t, r = record(gap=allan.GAP_FACTOR * STEP * 0.99)
    assert allan.deviation_from_timestamps(t, r).dt == pytest.approx((t[-1] - t[0]) / (len(t) - 1))


def test_the_command_line_says_what_to_do_with_options_it_has(tmp_path: Path) -> None:
    t, r = record(gap=4900.0)
    src = tmp_path / "gap.csv"
    src.write_text("t,gyro_z\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(t.tolist(), r.tolist())))
    proc = subprocess.run([sys.executable, "-m", "gyrocore.cli", "allan", str(src)], capture_output=True, text=True)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert len(proc.stderr.splitlines()) == 1 and "a gap of 4900 s" in proc.stderr
    # every option the message suggests is one the command takes (the unit check, which may also
    # speak, suggests --time-unit and --rate-unit)
    help_text = subprocess.run(
        [sys.executable, "-m", "gyrocore.cli", "allan", "--help"], capture_output=True, text=True
    ).stdout
    suggested = set(re.findall(r"--[a-z][a-z-]*", proc.stderr))
    assert "--window" in suggested
    for option in suggested | {"--time-unit", "--rate-unit"}:
        assert f"{option} " in help_text
    proc = subprocess.run(
        [sys.executable, "-m", "gyrocore.cli", "allan", str(src), "--window", "0", str(PART[-1]), "--json"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
