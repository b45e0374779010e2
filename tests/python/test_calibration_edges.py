"""gyrocore.calibration at the edges of its inputs: what a refusal says is what went wrong."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gyrocore import calibration


def test_temperature_bins_too_narrow_are_said_to_be_so_not_a_span_too_short() -> None:
    """A warm-up from 20 to 30 degC in 300 s at 10 Hz, in bins of 0.01 degC: each holds 3 readings,
    and the refusal said the temperature "spans only 10 degC"."""
    t = np.arange(3000) * 0.1
    temperature = np.linspace(20.0, 30.0, len(t))
    rate = np.random.default_rng(0).normal(0.01, 0.001, len(t))
    with pytest.raises(ValueError, match=r"^no temperature bin of 0\.01 degC holds 10 readings \(the fullest holds 3\): "
                                         r"give a wider bin_width or a smaller min_samples$"):
        calibration.bias_temperature_table(t, rate, temperature, bin_width=0.01)
    assert len(calibration.bias_temperature_table(t, rate, temperature, bin_width=0.1).temperatures) == 100
    with pytest.raises(ValueError, match=r"^fewer than 2 temperature bins of 1 degC hold 10 readings: the temperature "
                                         r"spans only 0 degC"):
        calibration.bias_temperature_table(t, rate, np.full(len(t), 25.0))


def test_a_rate_reference_fit_has_no_window_in_seconds(tmp_path: Path) -> None:
    """``rate_reference`` takes no times: its window was the sample indices, printed and saved as
    seconds ("window 0 .. 99 s" for 100 readings, whatever their rate)."""
    reference = np.sin(np.arange(100) * 0.1)
    fit = calibration.rate_reference(1.02 * reference + 0.01, reference)
    assert fit.window is None and fit.samples == 100
    assert " s," not in repr(fit) and "window" not in repr(fit)
    fit.save(tmp_path / "c.json")
    assert calibration.Calibration.load(tmp_path / "c.json").window is None


def table_turn(dps: float, sign: float, dt: float = 0.01) -> np.ndarray:
    """A 360 deg table turn at ``dps`` deg/s, read by a gyro 2 % high."""
    rate = np.radians(dps)
    return sign * np.full(int(round(2 * np.pi / rate / dt)), rate) * 1.02


@pytest.mark.parametrize("slow", [2.0, 1.0])
def test_a_table_turn_slower_than_max_rate_is_no_rest(slow: float) -> None:
    """A cw turn at 2 deg/s reads as steady as a rest and within max_rate (2.9 deg/s) of zero: it
    was taken as the static bias test (bias -1.98 deg/s), the ccw turns after it read 31.7 deg
    over 360 (c_ccw 0.919 for 0.980) and c_cw was 1 from no cw turn. All slow: "no turn found"."""
    rng = np.random.default_rng(0)
    for cw in (table_turn(slow, -1.0), table_turn(30.0, -1.0)):
        log = np.concatenate([np.zeros(2000), cw, np.zeros(300), table_turn(slow, 1.0), np.zeros(300)] * 2)
        t = np.arange(len(log)) * 0.01
        with pytest.raises(ValueError, match=r"^the stretch from \d+\.?\d* to \d+\.?\d* s, found as a rest, turns "
                                             r"[-\d.]+ deg at [-\d.]+ deg/s from the first rest's level: a turn slower "
                                             r"than max_rate = 0\.05 rad/s \(2\.86 deg/s\) reads as steady as a rest; "
                                             r"give a smaller max_rate \(max_rate=0\.0"):
            calibration.rotary_table(t, log + 0.001 + rng.normal(0.0, 0.002, len(log)))
        table = calibration.rotary_table(t, log + 0.001 + rng.normal(0.0, 0.002, len(log)), max_rate=0.01)
        assert table.calibration.c_cw == pytest.approx(1 / 1.02, rel=0.005)
        assert table.calibration.c_ccw == pytest.approx(1 / 1.02, rel=0.005)
