"""A result's ``bias_source`` names the bias its heading had removed, whatever the preset:
``raw`` removes none of its own, but a bias given to it is removed, and its words said "none (the
preset removes no static bias)" while ``gyrocore evaluate --preset raw --bias-dps B`` scored the
heading with B removed (docs/evaluation.md: "bias source" says which bias each method used)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore.cli import main


def _drive() -> tuple[np.ndarray, np.ndarray]:
    t = np.arange(0.0, 60.0, 0.01)
    return t, 0.01 + 0.2 * np.sin(t / 5.0)


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_raw_given_a_bias_says_it_removed_it(mode: str) -> None:
    t, rate = _drive()
    plain = gyrocore.process(t, rate, "raw", mode=mode)
    given = gyrocore.process(t, rate, "raw", mode=mode, bias=math.radians(0.1))
    assert plain.bias_source == "none (the preset removes no static bias)"
    assert given.heading[-1] == pytest.approx(plain.heading[-1] - math.radians(0.1) * (t[-1] - t[0]), abs=1e-9)
    assert given.bias_source == "given: 0.10000 deg/s"
    windowed = gyrocore.process(t, rate, "raw", mode=mode, bias_window=(0.0, 5.0))
    assert not np.array_equal(windowed.heading, plain.heading)
    assert windowed.bias_source.startswith("rest window [0.000, 5.000] s (given)"), windowed.bias_source


def test_evaluate_names_the_bias_given_to_raw(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    t, rate = _drive()
    drive = tmp_path / "drive.csv"
    np.savetxt(drive, np.column_stack([t, rate, np.cumsum(rate) * 0.01]), delimiter=",",
               header="t,gyro_z,heading_true", comments="")
    assert main(["evaluate", str(drive), "--preset", "raw", "--bias-dps", "0.1"]) == 0
    out = capsys.readouterr().out
    assert "raw: given: 0.10000 deg/s" in out, out
    assert "the preset removes no static bias" not in out, out
