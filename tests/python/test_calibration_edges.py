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
