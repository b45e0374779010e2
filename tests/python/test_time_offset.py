"""gyrocore.calibration.time_offset: the gyro's time offset against its reference heading, found on
drives with a known one (either sign, a fraction of a sample, with a bias, a scale error and
noise), refused where the drive cannot tell it, and carried by a saved calibration."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import calibration as cal
from gyrocore.calibration import offset as offset_module

#: How close the offset is found [s]: 0.3 ms, three times the worst found on these drives (0.09 ms,
#: with a standard error of 0.05). The first-order fit alone (no repeat on the shifted times) is off
#: by 0.5 to 1.4 ms at 0.03-0.06 s and 9 to 35 ms at 0.23-0.45 s; a 10 Hz grid by up to 50 ms; the
#: offset with its sign flipped by twice the offset.
TOLERANCE = 3e-4
BIAS, SCALE_ERROR, NOISE = 0.003, 0.02, 1e-3  # [rad/s], [1], [rad/s]


def drive(offset: float, *, gyro_hz: float = 10.0, ref_hz: float = 10.0, seed: int = 1, still: bool = False,
          duration: float = 300.0) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A gyro whose reading stamped ``t`` is the rate at the reference's ``t + offset`` (read with
    :data:`BIAS`, :data:`SCALE_ERROR` and white :data:`NOISE`), and the reference's wrapped
    heading, exact (the integral of the rate in closed form), at other instants. The rate is a sum
    of sines of 0.01-0.3 Hz of about 0.15 rad/s each; ``still``: no turn at all."""
    rng = np.random.default_rng(seed)
    amp, freq, phase = rng.normal(0.0, 0.15, 7) * (not still), rng.uniform(0.01, 0.3, 7), rng.uniform(0, 2 * np.pi, 7)
    w = 2 * np.pi * freq

    def rate(x: np.ndarray) -> np.ndarray:
        return np.sum(amp * np.sin(w * x[:, None] + phase), axis=1)

    def heading(x: np.ndarray) -> np.ndarray:
        return np.sum(amp / w * (np.cos(phase) - np.cos(w * x[:, None] + phase)), axis=1)

    t = np.arange(0.0, duration, 1.0 / gyro_hz)
    readings = (1 + SCALE_ERROR) * rate(t + offset) + BIAS + rng.normal(0.0, NOISE, len(t))
    t_ref = np.arange(0.0, duration, 1.0 / ref_hz) + 0.013
    return t, readings, t_ref, np.angle(np.exp(1j * heading(t_ref)))


CASES = [(0.06, 10.0, 10.0), (-0.06, 10.0, 10.0), (0.03, 10.0, 10.0), (0.23, 100.0, 20.0), (-0.37, 100.0, 20.0),
         (-0.45, 50.0, 10.0)]


@pytest.mark.parametrize(("offset", "gyro_hz", "ref_hz"), CASES)
def test_a_known_offset_is_found_with_the_bias_and_scale_error(offset: float, gyro_hz: float, ref_hz: float) -> None:
    found = cal.time_offset(*drive(offset, gyro_hz=gyro_hz, ref_hz=ref_hz))
    assert abs(found.offset - offset) < TOLERANCE, found
    assert found.offset_stderr < 1e-4  # the noise's share; the tolerance is the 10 Hz rate's trapezoids
    assert found.scale_error == pytest.approx(SCALE_ERROR, abs=0.002)  # the trapezoid's share at 0.3 Hz
    assert found.bias == pytest.approx(BIAS, abs=2e-5)  # 0.7 %: 1.2e-5 at most on these drives


def test_the_first_order_fit_alone_misses_the_offset_the_repeats_find(monkeypatch: pytest.MonkeyPatch) -> None:
    # what the tolerance above holds the fit to: one step of it is not enough
    monkeypatch.setattr(offset_module, "MAX_STEPS", 1)
    for offset, gyro_hz, ref_hz in CASES:
        assert abs(cal.time_offset(*drive(offset, gyro_hz=gyro_hz, ref_hz=ref_hz)).offset - offset) > TOLERANCE


def test_the_sign_is_what_to_add_to_the_gyros_times() -> None:
    # the gyro read 0.06 s late (its reading stamped t is the rate at the reference's t - 0.06):
    # shifted by the offset found, its times are on the reference's clock and its integral follows it
    t, rate, t_ref, heading_ref = drive(-0.06)
    found = cal.time_offset(t, rate, t_ref, heading_ref)
    assert found.offset == pytest.approx(-0.06, abs=TOLERANCE)
    turned = np.cumsum(np.r_[0.0, 0.5 * (rate[1:] + rate[:-1]) * np.diff(t)]) - BIAS * (t - t[0])
    psi = np.unwrap(heading_ref)

    def misfit(shift: float) -> float:
        gyro = np.interp(t_ref, t + shift, turned) / (1 + SCALE_ERROR)
        inside = (t_ref > 1) & (t_ref < 299)
        step = np.diff(gyro[inside]) - np.diff(psi[inside])
        return float(np.sqrt(np.mean(step**2)))

    assert misfit(found.offset) < 0.2 * misfit(0.0) and misfit(found.offset) < 0.2 * misfit(-found.offset)


@pytest.mark.parametrize("still", [True, False])
def test_a_drive_that_does_not_turn_or_turns_steadily_is_refused(still: bool) -> None:
    t, rate, t_ref, heading_ref = drive(0.06, still=still)
    if not still:  # one steady turn of 0.2 rad/s: the reference's rate never changes
        rate = 0.2 * (1 + SCALE_ERROR) + BIAS + np.random.default_rng(3).normal(0.0, NOISE, len(t))
        heading_ref = np.angle(np.exp(1j * 0.2 * t_ref))
    with pytest.raises(ValueError, match=r"^the rate must change during calibration to tell a time offset: the "
                                         r"reference turns by \S+ rad besides a steady turn, under 0.1 rad"):
        cal.time_offset(t, rate, t_ref, heading_ref)


def test_a_turn_whose_rate_changes_are_mostly_noise_is_refused() -> None:
    # a turn of 0.15 rad, past MIN_TURN, read by a gyro with 0.3 rad/s of noise: the first-order
    # fit saw 0.02 of a shift and found +0.004 s (+- 0.0006) for +0.06
    t, rate, t_ref, heading_ref = drive(0.06, duration=30.0)
    heading_ref = np.angle(np.exp(1j * 0.2 * np.unwrap(heading_ref)))
    rate = 0.2 * (rate - BIAS) + np.random.default_rng(5).normal(0.0, 0.3, len(t))
    # the first-order fit's scale error, 3100 %, is warned of before the fit is refused
    refused = (r"^the rate must change during calibration to tell a time offset: the gyro's rate changes are mostly "
               r"its noise \(a shift of its times by 0.01 s moves the fit by 0.02 of it, under 0.5\)")
    with pytest.warns(gyrocore.InputWarning, match=r"time_offset: the fitted scale error is \+3.13e\+03 %"), \
            pytest.raises(ValueError, match=refused):
        cal.time_offset(t, rate, t_ref, heading_ref)


def test_a_drive_too_short_for_its_noise_is_refused() -> None:
    # 2.5 s of turning at 10 Hz (24 steps): the offset's standard error would be 0.023 s
    t, rate, t_ref, heading_ref = drive(0.06, duration=2.5, seed=7)
    heading_ref = np.angle(np.exp(1j * 3 * np.unwrap(heading_ref)))
    rate = 3 * (rate - BIAS) + np.random.default_rng(5).normal(0.0, 0.02, len(t))
    with pytest.raises(ValueError, match=r"^the rate must change during calibration to tell a time offset: the "
                                         r"offset's standard error is 0.0227 s, over 0.01 s"):
        cal.time_offset(t, rate, t_ref, heading_ref)


def test_an_offset_beyond_max_offset_is_refused_and_found_with_a_larger_one() -> None:
    samples = drive(0.4, gyro_hz=50.0)
    with pytest.raises(ValueError, match=r"^the gyro's time offset against the reference looks larger than "
                                         r"max_offset = 0.2 s \(the fit reached \+0.\d+ s\)"):
        cal.time_offset(*samples, max_offset=0.2)
    assert cal.time_offset(*samples).offset == pytest.approx(0.4, abs=TOLERANCE)
    for bad, error in ((0.0, ValueError), (math.nan, ValueError), ("1", TypeError)):
        with pytest.raises(error, match="max_offset must be"):
            cal.time_offset(*samples, max_offset=bad)  # type: ignore[arg-type]


def _bad_inputs() -> list[tuple[str, tuple[np.ndarray, ...], dict[str, object], str]]:
    """Bad inputs, and what :func:`heading_reference` and :func:`time_offset` both say of them (a
    regular expression; ``METHOD`` is the function's name, ``LEAST`` the fewest samples it takes)."""
    t, rate, t_ref, heading_ref = drive(0.06)
    nan = rate.copy()
    nan[5] = math.nan
    return [
        ("a NaN reading", (t, nan, t_ref, heading_ref), {},
         r"rate_measured\[5\] is nan: samples must be finite \(drop or fill them first\)"),
        ("a reference in degrees", (t, rate, t_ref, np.degrees(heading_ref)), {},
         r"METHOD: the reference changes \S+ times as much as the gyro \(s_bar\), about 180/pi = 57.3: heading_ref "
         r"looks like degrees; convert it to rad \(numpy.radians\)"),
        ("a reference turning the other way", (t, rate, t_ref, -heading_ref), {},
         r"the fit gives s_bar = \S+ <= 0 \(the gyro would read against the motion\): the rate must change during "
         r"calibration, and the reference must match the gyro's axis and sign"),
        ("a reference on another clock", (t, rate, t_ref + 1e4, heading_ref), {},
         r"only 0 reference sample\(s\) fall inside the gyro's span 0.0 .. \S+ s; need at least LEAST \(are both "
         r"in the same time base\?\)"),
        ("a window outside the log", (t, rate, t_ref, heading_ref), {"window": (400.0, 500.0)},
         r"the window \[400.0, 500.0\] s lies outside the gyro's log \(0.0 .. \S+ s\); give it in the log's own "
         r"time base"),
        ("times out of order", (t[::-1], rate, t_ref, heading_ref), {},
         r"t must strictly increase: t\[1\] = 299.8 follows \S+ \(sort them and drop duplicate times\)"),
        ("unequal lengths", (t, rate[:-1], t_ref, heading_ref), {}, r"rate_measured has 2999 samples but t has 3000"),
    ]


@pytest.mark.parametrize(("what", "samples", "options", "message"), _bad_inputs(), ids=[c[0] for c in _bad_inputs()])
def test_what_heading_reference_refuses_is_refused_in_its_words(
    what: str, samples: tuple[np.ndarray, ...], options: dict[str, object], message: str
) -> None:
    for fit, least in ((cal.heading_reference, "3"), (cal.time_offset, "11")):
        with pytest.raises(ValueError) as refused:
            fit(*samples, **options)  # type: ignore[operator]
        assert re.fullmatch(message.replace("METHOD", fit.__name__).replace("LEAST", least), str(refused.value))


def test_too_few_reference_samples_for_the_steps_are_named() -> None:
    t, rate, t_ref, heading_ref = drive(0.06)
    with pytest.raises(ValueError, match=r"^only 8 reference sample\(s\) fall inside the gyro's span .*; need at "
                                         r"least 11 \(the reference has 8 in all\)"):
        cal.time_offset(t, rate, t_ref[:8], heading_ref[:8])


# --- the saved calibration ---------------------------------------------------------------------


def test_a_calibration_carries_the_offset_through_its_file(tmp_path: Path) -> None:
    fit = cal.Calibration("heading_reference", bias=0.001, scale_error=0.01, time_offset=-0.0607,
                          time_offset_stderr=0.0005)
    fit.save(tmp_path / "c.json")
    assert cal.Calibration.load(tmp_path / "c.json") == fit
    assert "time offset = -0.0607 +- 0.0005 s (add to the gyro's times)" in repr(fit)
    saved = json.loads((tmp_path / "c.json").read_text())
    assert saved["calibration"]["time_offset"] == -0.0607 and saved["units"]["time_offset"].startswith("s (add")
    assert fit.overrides() == cal.Calibration("heading_reference", bias=0.001, scale_error=0.01).overrides()


def test_a_calibration_without_an_offset_saves_as_before_and_old_files_load(tmp_path: Path) -> None:
    plain = cal.Calibration("static_bias", bias=0.002, window=(1.0, 5.0), samples=400)
    saved = plain.to_dict()
    assert "time_offset" not in saved["calibration"] and "time_offset_stderr" not in saved["units"]
    # a file saved before the offset was carried (gyrocore 0.x: no such fields)
    old = {"format": "gyrocore-calibration", "version": 1, "units": {"bias": "rad/s"},
           "calibration": {"method": "heading_reference", "bias": 0.001, "scale_error": 0.01, "bias_stderr": 1e-5,
                           "scale_error_stderr": 0.001, "residual_rms": 0.01, "condition_number": 5.0,
                           "window": [0.0, 100.0], "samples": 1000, "c_cw": 1.0, "c_ccw": 1.0, "temp_slope": None,
                           "temp_offset": None, "bias_table": None, "notes": []}}
    (tmp_path / "old.json").write_text(json.dumps(old))
    loaded = cal.Calibration.load(tmp_path / "old.json")
    assert loaded.time_offset is None and loaded.time_offset_stderr is None and loaded.scale_error == 0.01


@pytest.mark.parametrize(("values", "message"), [
    ({"time_offset": math.nan}, "time_offset must be finite, got nan"),
    ({"time_offset": 0.05, "time_offset_stderr": -1.0}, "time_offset_stderr must be >= 0, got -1.0"),
    ({"time_offset_stderr": 0.001}, "time_offset_stderr is the standard error of a time_offset: give the offset too"),
])
def test_an_offset_no_fit_gives_is_refused(values: dict[str, float], message: str) -> None:
    with pytest.raises(ValueError, match="^" + re.escape(message) + "$"):
        cal.Calibration("heading_reference", **values)  # type: ignore[arg-type]


def test_a_saved_offset_that_is_text_is_named(tmp_path: Path) -> None:
    data = cal.Calibration("heading_reference", time_offset=0.05).to_dict()
    data["calibration"]["time_offset"] = "0.05"
    (tmp_path / "c.json").write_text(json.dumps(data))
    with pytest.raises(ValueError, match=r"c.json: not a valid calibration: time_offset must be a number, got '0.05'"):
        cal.Calibration.load(tmp_path / "c.json")
