"""What the simulator states is what it simulates: a stopped car does not turn, and the simulated
GNSS fixes have the noise, the rate and the outage they are given."""

from __future__ import annotations

import hashlib
import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from gyrocore import InputWarning, allan, evaluate, motion, sim
from gyrocore._checks import UnitError
from gyrocore._fixes_eval import SimFixes, _mean_in
from gyrocore.cli import main
from gyrocore.fixes import Fixes
from gyrocore.io import Log, read_log


@pytest.mark.parametrize("mix", ["city", "downtown"])
def test_a_stopped_car_does_not_turn(mix: str) -> None:
    # the swerve of the drive-off after a stop began where the braking did: the car yawed at up to
    # 0.2 deg/s and turned 0.64 deg while standing, where a gyro reads bias and noise only
    route = motion.car(1800.0, mix=mix, seed=2)
    stops = route.segments_of("stop")
    assert len(stops) >= 3
    for stop in stops:
        t = np.linspace(stop.start, stop.end, 200)
        truth = route.sample(t)
        assert np.all(truth.speed == 0.0)
        assert np.abs(truth.rate).max() == 0.0, stop
        assert np.ptp(truth.heading) == 0.0, stop


def _fix_errors_deg(fixes: Fixes, t: np.ndarray, heading: np.ndarray) -> np.ndarray:
    """Each fix's heading minus the reference's there, wrapped to (-180, 180] deg."""
    return np.degrees(np.angle(np.exp(1j * (fixes.heading - np.interp(fixes.t, t, heading)))))


@pytest.mark.parametrize("sigma_deg", [1.0, 10.0, sim.SIGMA_DEG[1]])
def test_the_fixes_noise_is_the_sigma_they_state(sigma_deg: float) -> None:
    # a heading's error wraps at +-180 deg: asked for 180 deg the fixes' error had 104 deg of
    # standard deviation (90: 83), each fix stating 180 (90); up to the limit it is the sigma
    t = np.arange(0.0, 20000.0, 0.5)
    heading = 0.002 * t  # turning: wrapped many times over
    fixes = sim.gnss_fixes(t, heading, seed=4, sigma_deg=sigma_deg)
    assert np.degrees(fixes.sigma) == pytest.approx(sigma_deg, rel=1e-12)
    errors = _fix_errors_deg(fixes, t, heading)
    # 20,000 fixes: the sample standard deviation is within 0.5 % (1 standard error) of the truth
    assert errors.std() == pytest.approx(sigma_deg, rel=0.02)
    assert abs(errors.mean()) < 4 * sigma_deg / np.sqrt(len(errors))


@pytest.mark.parametrize("sigma_deg", [90.0, 180.0])
def test_a_sigma_whose_noise_would_wrap_is_refused(sigma_deg: float) -> None:
    t = np.arange(0.0, 100.0, 1.0)
    with pytest.raises(ValueError, match=r"sigma_deg must be in \[5.73e-11, 60\] deg .*wraps"):
        sim.gnss_fixes(t, np.zeros_like(t), seed=0, sigma_deg=sigma_deg)
    with pytest.raises(ValueError, match=r"--sim-fixes: sigma_deg=90: the fixes' noise must be in \[5.73e-11, 60\]"):
        SimFixes.parse("sigma_deg=90")


def test_vague_simulated_fixes_are_not_said_to_be_in_degrees() -> None:
    # sigma_deg=45 is in degrees by its name, and converted: "sigmas are in rad (if they were
    # written in degrees, convert them with numpy.radians)" sent the caller to convert it again
    t = np.arange(0.0, 100.0, 1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        fixes = sim.gnss_fixes(t, np.zeros_like(t), seed=0, sigma_deg=45.0)
    assert np.degrees(fixes.sigma) == pytest.approx(45.0)


@pytest.mark.parametrize(("samples", "step", "rate_hz"), [(4, 0.7, 10.0), (8, 1.0 / 3.0, 3.0), (8, 0.7, 10.0)])
def test_a_fix_falls_on_the_reference_end_when_the_span_is_whole_periods(samples: int, step: float,
                                                                          rate_hz: float) -> None:
    # 2.1 s at 10 Hz: (t[-1] - t[0]) * rate was 20.999999999999996, and the fix at 2.1 s was lost
    # (21 fixes, not 22; 1723 of 47,968 spans and rates tried)
    t = np.arange(samples) * step
    fixes = sim.gnss_fixes(t, np.zeros(samples), seed=0, rate_hz=rate_hz)
    periods = round((samples - 1) * step * rate_hz)
    assert len(fixes) == periods + 1
    assert fixes.t[-1] == pytest.approx(t[-1], abs=1e-12) and fixes.t[-1] <= t[-1]
    assert np.diff(fixes.t) == pytest.approx(1.0 / rate_hz, abs=1e-12)


def test_no_fix_is_made_inside_a_gap_of_the_reference() -> None:
    # a receiver following the reference knows nothing where the reference says nothing: 39 fixes
    # were interpolated across a 40 s gap in which the car turned 270 deg, with errors up to
    # 180 deg, each stating 1 deg (the fix stage then warned to check the units)
    t = np.arange(0.0, 200.0, 0.1)
    heading = np.clip((t - 100.0) / 30.0, 0.0, 1.0) * np.radians(270.0)
    gap = (t > 95.0) & (t < 135.0)
    t_ref, heading_ref = t[~gap], np.angle(np.exp(1j * heading[~gap]))
    fixes = sim.gnss_fixes(t_ref, heading_ref, seed=0, rate_hz=1.0, sigma_deg=1.0)
    last_before, first_after = t_ref[t_ref <= 95.0][-1], t_ref[t_ref >= 135.0][0]
    assert not np.any((fixes.t > last_before) & (fixes.t < first_after))
    assert len(fixes) == 200 - 39  # a fix each second, those of 96 .. 134 s left out (95 and 135 are reference times)
    errors = _fix_errors_deg(fixes, t, heading)
    assert np.abs(errors).max() < 5.0  # 1 deg noise: every fix within 5 sigma of the truth


def test_the_closed_form_allan_deviation_is_that_of_the_simulated_gyro_below_its_noise_bandwidth() -> None:
    # the XV3500's noise passes a 20 Hz low-pass at 100 Hz: the closed form said N / sqrt(tau) there,
    # 1.6 times the simulated gyro's Allan deviation at tau = 0.01 s (1.3 at 0.02 s, 1.14 at 0.04 s)
    spec = sim.sensor("xv3500", bias_dps_per_c=0.0)
    t = np.arange(0.0, 1800.0, 0.01)
    curve = allan.deviation(sim.measure(spec, t, np.zeros_like(t), seed=2).rate, 0.01, taus=[0.01, 0.02, 0.04, 0.08])
    # 180,000 samples: the Allan deviation at these taus is within 1 % (2 standard errors)
    assert curve.adev / spec.allan_deviation(curve.taus) == pytest.approx(1.0, abs=0.02)


def test_a_reference_in_degrees_is_refused_as_the_scoring_refuses_it() -> None:
    # a heading in degrees wrapping at +-180 made fixes whose error had 55 deg of standard deviation
    # (a 30 min downtown drive), each stating 1 deg, where evaluate.Reference refuses it as degrees
    t = np.arange(0.0, 100.0, 0.1)
    degrees = np.degrees(np.angle(np.exp(1j * 0.1 * t)))  # turning 5.7 deg/s: wraps at 31.4 s
    with pytest.raises(UnitError, match="the reference heading looks like degrees, not radians"):
        sim.gnss_fixes(t, degrees, seed=0)
    with pytest.raises(UnitError, match="the reference heading looks like degrees, not radians"):
        evaluate.Reference(t, degrees)


@pytest.mark.parametrize("outages", [5, 2.5])
def test_outages_that_are_no_sequence_are_named(outages: object) -> None:
    # "TypeError: 'int' object is not iterable", in Python's words
    t = np.arange(0.0, 100.0, 0.1)
    said = rf"outages must be \(start, end\) pairs in seconds, e.g. \(\(100, 160\),\), or \(\) for none; got {outages!r}"
    with pytest.raises(TypeError, match=said):
        sim.gnss_fixes(t, np.zeros_like(t), seed=0, outages=outages)  # type: ignore[arg-type]


def test_no_outages_may_be_given_as_none() -> None:
    t = np.arange(0.0, 100.0, 0.1)
    fixes = sim.gnss_fixes(t, np.zeros_like(t), seed=0, outages=None)
    assert np.array_equal(fixes.t, sim.gnss_fixes(t, np.zeros_like(t), seed=0).t)


def test_the_outage_holds_the_fixes_and_reference_samples_it_states_at_both_edges() -> None:
    # on a clock of 42879.24 s, outage=50.3:49.9 ends at (42879.24 + 50.3) + 49.9, an ulp above
    # 42879.24 + 100.2, where the fix and the reference sample due at its end are: the outage left
    # out 500 fixes at 10 Hz (not 499) and scored 500 reference samples, one past its end
    n = 3000
    t = 42879.24 + np.arange(n) / 10.0
    log = Log(t=t, rate=np.zeros(n), t_ref=t, heading_ref=np.zeros(n), name="clock")
    spec = SimFixes.parse("rate=10,outage=50.3:49.9")
    removed = len(SimFixes.parse("rate=10").fixes(log)) - len(spec.fixes(log))
    assert removed == 499
    window = spec.window(log)
    assert window is not None
    error = np.zeros(n)
    error[503 + 499] = 1.0  # the sample due at the end, the first after the outage
    error[503] = 0.499  # the first in it: due at the start
    assert _mean_in(t, np.radians(error), window) == pytest.approx(0.001)
    # an outage past the log's end holds its last sample, and no fix after the one before it
    past = SimFixes.parse("rate=10,outage=250:1e300")
    window = past.window(log)
    assert window is not None and t[-1] < window[1] < t[-1] + 1e-6
    last = np.zeros(n)
    last[-1] = 2.5
    assert _mean_in(t, np.radians(last), window) == pytest.approx(2.5 / (n - 2500))
    assert past.fixes(log).t[-1] == pytest.approx(t[2499])


def test_an_outage_without_a_reference_sample_says_why_it_has_no_e_psi(tmp_path: Path,
                                                                       capsys: pytest.CaptureFixture[str]) -> None:
    # an outage between two reference samples (10 Hz) printed "nan" in its column, and nothing more
    drive = tmp_path / "drive.csv"
    assert main(["simulate", "--duration", "60", "--rate-hz", "10", "--out", str(drive)]) == 0
    capsys.readouterr()
    assert main(["evaluate", str(drive), "--preset", "raw", "--sim-fixes", "outage=30.01:0.05"]) == 0
    out = capsys.readouterr().out
    row = next(line for line in out.splitlines() if line.startswith(str(drive)))
    assert row.split()[4:6] == ["nan", "nan"]
    assert (f"outage of {drive}: [30.010, 30.060) s holds no reference sample: its E_psi is nan (null in the JSON)"
            in out), out


def test_each_log_s_simulated_fixes_have_their_own_seed_whatever_the_order(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # one seed for every log of a run: two drives of one reference got the very same fix errors,
    # and a log's fixes were the same whichever logs ran beside it
    drives = [tmp_path / "a.csv", tmp_path / "b.csv"]
    for drive in drives:  # the same drive, twice, under two names
        assert main(["simulate", "--duration", "120", "--rate-hz", "10", "--out", str(drive)]) == 0
    capsys.readouterr()
    spec = SimFixes.parse("seed=3")
    a, b = (read_log(drive) for drive in drives)
    fa, fb = spec.fixes(a), spec.fixes(b)
    assert np.array_equal(fa.t, fb.t) and not np.array_equal(fa.heading, fb.heading)
    assert spec.seed_of(a) == int.from_bytes(hashlib.sha256(b"3/a").digest()[:8], "big")  # as docs/fixes_results.md says

    def rows(order: list[Path]) -> dict[str, dict[str, object]]:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", InputWarning)
            assert main(["evaluate", *map(str, order), "--preset", "raw", "--sim-fixes", "seed=3", "--json"]) == 0
        return {row["name"]: row for row in json.loads(capsys.readouterr().out)}

    forward, backward = rows(drives), rows(drives[::-1])
    assert forward == backward
    assert forward["a"]["e_psi_deg"] != forward["b"]["e_psi_deg"]
    assert f"seed {spec.seed_of(b)} (of the run's seed 3 and the log's name b)" in str(forward["b"]["fixes"])
