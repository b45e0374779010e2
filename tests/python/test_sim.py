"""The simulated gyro and the motion profiles: datasheet units, the Allan deviation of a static log,
exact truth, reproducibility, sampling, car drives, and the ``simulate`` command."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import allan, motion, sim
from gyrocore.cli import main


def test_datasheet_units_convert_to_si() -> None:
    spec = sim.GyroSpec(
        arw_deg_per_sqrt_h=2.5, bias_instability_deg_per_h=18.0, rrw_deg_per_h_per_sqrt_h=3.0,
        bias_dps=0.75, resolution_dps=0.01, range_dps=100.0,
    )
    si = spec.si()
    # 2.5 deg/sqrt(h) = 2.5 * pi/180 / 60 rad/sqrt(s); 18 deg/h = 18 * pi/180 / 3600 rad/s;
    # 3 deg/h/sqrt(h) = 3 * pi/180 / 3600 / 60 rad/s/sqrt(s).
    assert si["arw"] == pytest.approx(math.radians(2.5) / 60.0, rel=1e-15)
    assert si["bias_instability"] == pytest.approx(math.radians(18.0) / 3600.0, rel=1e-15)
    assert si["rrw"] == pytest.approx(math.radians(3.0) / 216000.0, rel=1e-15)
    assert si["bias"] == pytest.approx(math.radians(0.75))
    assert si["range"] == pytest.approx(math.radians(100.0))
    names = {n for n, _ in gyrocore._gyrocore.gyro_parameter_names()}
    assert set(si) == names, "GyroSpec.si() must give every parameter of the Rust model"


def test_presets_carry_the_papers_figures() -> None:
    xv, crs, fog = sim.SENSORS["xv3500"], sim.SENSORS["crs03"], sim.SENSORS["fog"]
    assert (xv.arw_deg_per_sqrt_h, xv.bias_instability_deg_per_h, xv.rate_hz) == (2.5, 18.0, 100.0)
    assert xv.scale_error == pytest.approx(0.0253)
    assert (crs.bias_instability_deg_per_h, crs.range_dps, crs.rate_hz, crs.bias_dps) == (66.0, 200.0, 10.0, 1.432)
    assert fog.bias_instability_deg_per_h == 18.0
    # FOG eq 5: the turn error per 360 deg is -0.52 T + 19.23 deg.
    for celsius in (20.0, 37.0, 45.0):
        s = fog.scale_error + fog.scale_per_c * (celsius - fog.reference_temperature_c)
        assert 360.0 * s == pytest.approx(-0.52 * celsius + 19.23)
    assert sim.sensor("xv3500", rate_hz=10.0).rate_hz == 10.0
    with pytest.raises(ValueError, match="unknown sensor 'adxrs'"):
        sim.sensor("adxrs")


def test_static_xv3500_log_shows_the_specified_arw_and_bias_instability() -> None:
    # Hong section 2.1 averaged ten gyros; so do we: ten 48 h static logs at 1 Hz, each read by
    # gyrocore.allan. The floor is read where the angle random walk adds under 10 % of the variance.
    spec = sim.sensor("xv3500", rate_hz=1.0, drift_step_s=1.0)
    n = 48 * 3600
    t = np.arange(n, dtype=np.float64)
    taus = 2.0 ** np.arange(13)
    arw, bias, curves = [], [], []
    for seed in range(10):
        curve = allan.deviation(sim.measure(spec, t, np.zeros(n), seed=seed).rate, 1.0, taus=taus)
        p = allan.noise_parameters(curve, slope_tolerance=0.05)
        assert p.arw is not None and p.bias_instability is not None
        arw.append(p.arw.value_deg)
        bias.append(p.bias_instability.value_deg)
        curves.append(curve.adev)
    assert np.mean(arw) == pytest.approx(2.5, rel=0.10)
    assert np.mean(bias) == pytest.approx(18.0, rel=0.10)
    # The mean curve follows the closed form of IEEE 952 (ARW + Gauss-Markov sum + RRW) at every tau.
    ratio = np.mean(curves, axis=0) / spec.allan_deviation(taus)
    assert np.all(np.abs(ratio - 1.0) < 0.05), ratio


def test_noise_free_reading_is_hong_eq_1_exactly() -> None:
    route = motion.robot_run()
    spec = sim.GyroSpec(scale_error=-0.1, bias_dps=math.degrees(0.1), scale_asymmetry=0.004, bias_dps_per_c=0.01,
                        temperature_c=(20.0, 30.0), temperature_time_constant_s=50.0)
    d = sim.simulate(route, spec, seed=1)
    expected = (1.0 + d.scale) * d.rate_true + d.bias + d.drift
    assert np.max(np.abs(d.rate_measured - expected)) < 1e-14
    # The scale error is -10 % plus half the asymmetry by direction; the drift is the temperature's.
    moving = d.rate_true != 0
    assert np.allclose(d.scale[moving], -0.1 + 0.002 * np.sign(d.rate_true[moving]))
    warm = math.radians(0.01) * (d.temperature - spec.reference_temperature_c)
    assert np.allclose(d.drift + d.bias, 0.1 + warm, rtol=0, atol=1e-15)


def test_same_seed_same_drive_and_the_drift_does_not_depend_on_the_rate() -> None:
    a = sim.car_drive(duration=300.0, rate_hz=100.0, seed=5)
    b = sim.car_drive(duration=300.0, rate_hz=100.0, seed=5)
    c = sim.car_drive(duration=300.0, rate_hz=100.0, seed=6)
    assert np.array_equal(a.rate_measured, b.rate_measured) and a.bias == b.bias
    assert not np.array_equal(a.rate_measured, c.rate_measured)
    slow = sim.car_drive(duration=300.0, rate_hz=10.0, seed=5)
    # Every 10th sample of the 100 Hz drive is an instant of the 10 Hz drive: same truth, same drift.
    assert np.allclose(slow.t, a.t[::10], atol=1e-9)
    assert np.allclose(slow.heading_true, a.heading_true[::10], atol=1e-12)
    assert np.allclose(slow.drift + slow.bias, (a.drift + a.bias)[::10], atol=1e-15)


def test_car_drive_keeps_its_interface() -> None:
    d = sim.car_drive(duration=200.0, rate_hz=50.0, seed=2, rest=15.0)
    assert isinstance(d, sim.Drive) and d.stationary == (0.0, 15.0)
    assert len(d.t) == 10000 and d.t[0] == 0.0 and d.t[-1] < 200.0
    for name in ("t", "rate_true", "heading_true", "rate_measured", "drift", "x", "y", "speed", "temperature"):
        assert getattr(d, name).shape == d.t.shape, name
    rest = d.t <= 15.0
    assert np.all(d.rate_true[rest] == 0.0) and np.all(d.speed[rest] == 0.0)
    # The static bias is the mean of the gyro's bias over the rest window, so the drift averages 0 there.
    assert abs(np.mean(d.drift[rest])) < 1e-12
    assert "CRS03-04" in repr(d)


def test_jitter_and_drops_make_an_irregular_increasing_log() -> None:
    spec = sim.sensor("crs03", rate_hz=50.0, jitter_s=0.002, drop_probability=0.05)
    d = sim.simulate(motion.car(300.0, seed=1), spec, seed=3)
    dt = np.diff(d.t)
    assert np.all(dt > 0)
    assert abs(len(d.t) / 15000 - 0.95) < 0.01
    assert dt.max() > 0.035 and dt.std() > 0.001  # dropped samples double an interval; jitter spreads them
    # The pipeline takes it as it comes (actual intervals): the heading is still near the truth.
    r = gyrocore.process(d.t, d.rate_measured, "static_bias", bias_window=d.stationary)
    assert gyrocore.heading_errors(d.t, r.heading, d.t, d.heading_true).e_psi_deg < 30.0


@pytest.mark.parametrize("bad", [{"jitter_s": 0.1}, {"drop_probability": 1.0}, {"scale_error": -1.5}, {"arw_deg_per_sqrt_h": -1.0}])
def test_invalid_spec_names_the_parameter(bad: dict[str, float]) -> None:
    name = {"jitter_s": "jitter", "drop_probability": "drop_probability", "scale_error": "scale_error",
            "arw_deg_per_sqrt_h": "arw"}[next(iter(bad))]
    with pytest.raises(ValueError, match=f"gyro model: invalid parameter {name}"):
        sim.simulate(motion.robot_run(), sim.sensor("xv3500", **bad), seed=0)


def test_bad_seeds_and_times_are_refused() -> None:
    spec = sim.sensor("xv3500")
    with pytest.raises(ValueError, match="seed must be an integer"):
        sim.measure(spec, [0.0, 1.0], [0.0, 0.0], seed=-1)
    with pytest.raises(ValueError, match=r"t\[2\]"):
        sim.measure(spec, [0.0, 1.0, 1.0], [0.0, 0.0, 0.0], seed=0)
    with pytest.raises(ValueError, match="is the duration in seconds"):
        sim.sample_times(spec, 0.0, 1e9, seed=0)

def test_a_rate_too_high_for_the_clock_is_refused() -> None:
    # at 1e7 Hz on a Unix-epoch clock the instants rounded to repeats, which the pipeline refused
    fast = sim.sensor("xv3500", rate_hz=1e7)
    with pytest.raises(ValueError, match=r"timestamps would repeat; start the clock nearer 0 or lower rate_hz"):
        sim.sample_times(fast, 1.7e9, 1.7e9 + 1e-3, seed=0)
    t = sim.sample_times(fast, 0.0, 1e-3, seed=0)  # near 0 the clock resolves them
    assert len(t) == 10_000 and np.all(np.diff(t) > 0)
    jittered = sim.sample_times(sim.sensor("xv3500", rate_hz=2e5, jitter_s=1e-6), 1.7e9, 1.7e9 + 0.05, seed=0)
    assert np.all(np.diff(jittered) > 0)  # below the limit (2.6e5 Hz there): every instant its own


def test_motion_heading_is_exact_and_laps_close() -> None:
    table = motion.rotary_table(runs=2)
    for seg in table.segments:
        if seg.kind.startswith("turn"):
            h = table.sample(np.array([seg.start, seg.end])).heading
            assert h[1] - h[0] == pytest.approx(seg.angle, abs=1e-12)
            assert abs(seg.angle) == pytest.approx(2 * math.pi)
    assert table.duration == pytest.approx(2 * 48.0)
    square = motion.square_path(runs=1)
    laps = square.segments_of("lap_cw") + square.segments_of("lap_ccw")
    assert [lap.end - lap.start for lap in laps] == pytest.approx([64.0, 64.0])  # FOG section 4.1
    ends = square.sample(np.array([laps[0].start, laps[0].end, laps[1].end]))
    assert np.allclose(ends.x, 0.0, atol=1e-9) and np.allclose(ends.y, 0.0, atol=1e-9)
    assert ends.heading[1] - ends.heading[0] == pytest.approx(-2 * math.pi, abs=1e-12)
    corner = square.sample(np.array([20.0 + 12.0]))  # after the first 4 m side, before the turn
    assert (corner.x[0], corner.y[0]) == pytest.approx((4.0, 0.0), abs=1e-6)
    assert square.sample(np.linspace(0, square.duration, 5000)).speed.max() == pytest.approx(0.4)


def test_hdr_figure3_curves_40_degrees_and_robot_run_follows_hong() -> None:
    m = motion.hdr_figure3()
    h = m.sample(np.array([659.0, 681.0])).heading
    assert h[1] - h[0] == pytest.approx(math.radians(40.0), abs=math.radians(0.5))  # 2 deg/s for 20 s, plus swerve
    curve = m.segments_of("curve")[0]
    assert (curve.start + 0.5, curve.end - 0.5) == pytest.approx((660.0, 680.0))
    # The swerve: 0.1 Hz while driving.
    t = np.arange(100.0, 600.0, 0.05)
    spectrum = np.abs(np.fft.rfft(m.sample(t).rate))
    assert np.fft.rfftfreq(len(t), 0.05)[np.argmax(spectrum[1:]) + 1] == pytest.approx(0.1, abs=0.005)
    robot = motion.robot_run()
    assert robot.duration == 160.0
    cal = robot.segments_of("calibration")[0]
    assert (cal.start, cal.end) == (5.0, 20.0)
    truth = robot.sample(np.arange(0.0, 160.0, 0.01))
    assert truth.speed.max() == pytest.approx(2.0)  # Hong section 4.1: up to 2 m/s
    assert len(np.unique(np.round(np.abs(truth.rate[(truth.t > 5) & (truth.t < 20)]), 3))) > 10
    # Smaller turns keep the heading closer to the start: within +-turn_deg after calibration.
    for turn in (90.0, 20.0):
        heading = motion.robot_run(turn_deg=turn).sample(np.arange(20.0, 160.0, 0.01)).heading
        assert np.degrees(np.abs(heading - heading[0])).max() == pytest.approx(turn, abs=1e-6)
    for bad in (0.0, -10.0, 270.0, math.nan):
        with pytest.raises(ValueError, match="turn_deg"):
            motion.robot_run(turn_deg=bad)


@pytest.mark.parametrize("mix", sorted(motion.ROAD_MIXES))
def test_car_mixes_are_drivable(mix: str) -> None:
    m = motion.car(900.0, mix=mix, seed=4)
    truth = m.sample(np.arange(0.0, 900.0, 0.1))
    assert m.duration == 900.0
    assert truth.speed.min() >= 0.0 and truth.speed.max() <= 33.0
    assert np.abs(truth.rate).max() < math.radians(25.0)
    # The heading is the rate's integral: a 1 ms trapezoid sum agrees to within its own error (at
    # the phase corners, about 1e-8 rad in all).
    fine = m.sample(np.arange(0.0, 900.0, 0.001))
    numeric = np.concatenate(([0.0], np.cumsum(0.5 * (fine.rate[1:] + fine.rate[:-1]) * np.diff(fine.t))))
    assert np.max(np.abs(numeric - fine.heading)) < 1e-7
    kinds = {s.kind for s in m.segments}
    assert "straight" in kinds
    if mix == "downtown":
        assert len(m.segments_of("turn")) >= 10
    if mix == "suburbs":
        assert len(m.segments_of("curve")) >= 10


def test_simulate_command_writes_a_log_the_process_command_reads(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "robot.csv"
    assert main(["simulate", "--profile", "robot", "--sensor", "xv3500", "--out", str(out)]) == 0
    assert "rest window 0 .. 5 s" in capsys.readouterr().out
    lines = out.read_text().splitlines()
    assert lines[0] == "t,gyro_z,temperature,rate_true,heading_true,x,y,speed,drift"
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert data.shape == (16000, 9)
    again = sim.simulate(motion.robot_run(), "xv3500", seed=0)
    assert np.allclose(data[:, 1], again.rate_measured, rtol=1e-9, atol=1e-12)
    heading = tmp_path / "heading.csv"
    assert main(["process", str(out), "--out", str(heading), "--preset", "raw"]) == 0
    assert not list(tmp_path.glob(".*tmp"))


def test_simulate_command_refuses_bad_output(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["simulate", "--out", str(tmp_path / "x.txt")]) == 2
    assert main(["simulate", "--out", str(tmp_path / "missing" / "x.csv")]) == 2
    err = capsys.readouterr().err  # (a bad --runs is refused as it is read: test_cli)
    assert "must end in .csv" in err and "does not exist; create it or write elsewhere" in err


def test_demo_takes_a_sensor_and_a_road_mix(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["demo", "--duration", "240", "--rate-hz", "20", "--sensor", "xv3500", "--mix", "downtown",
                 "--plot", ""]) == 0
    out = capsys.readouterr().out
    assert "'downtown' roads, Epson XV3500 at 20 Hz" in out
    assert "\nhdr " in out


@pytest.mark.parametrize("sigma_deg", [1e-20, 181.0, 1e9])
def test_simulated_fixes_refuse_a_noise_the_filter_cannot_use(sigma_deg: float) -> None:
    # below 1e-12 rad the filter refused the fixes made; beyond half a turn the noise wraps
    t = np.arange(100.0)
    with pytest.raises(ValueError, match=r"sigma_deg must be in \[5.73e-11, 60\] deg"):
        sim.gnss_fixes(t, 0.01 * t, seed=0, sigma_deg=sigma_deg)


@pytest.mark.parametrize(
    ("t", "heading", "message"),
    [
        # one NaN heading made 90 of the 100 fixes NaN (numpy.unwrap carries it on)
        (np.arange(100.0), np.where(np.arange(100) == 10, np.nan, 0.0), r"heading_ref\[10\] is nan"),
        # times in reverse made no fix at all, without a word
        (np.arange(100.0)[::-1], np.zeros(100), r"t_ref must strictly increase: t_ref\[1\] = 98.0 follows 99.0"),
        (np.arange(100.0), np.zeros(99), "heading_ref has 99 samples but t_ref has 100"),
    ],
)
def test_simulated_fixes_refuse_a_reference_that_is_no_track(t: np.ndarray, heading: np.ndarray, message: str) -> None:
    with pytest.raises(ValueError, match=r"the reference: " + message):
        sim.gnss_fixes(t, heading, seed=0)


@pytest.mark.parametrize(
    ("build", "message"),
    [
        # each gave a one-sample drive without a word, which every command that read it refused later
        (lambda: sim.car_drive(60, rate_hz=0.01),
         "rate_hz 0.01 puts 1 sample(s) in the drive's rest window [0, 20] s, and its bias needs at least 3"),
        (lambda: sim.simulate(motion.car(60), "crs03", seed=0, rate_hz=0.001), "rate_hz 0.001 puts 1 sample(s)"),
        (lambda: sim.simulate(motion.car(60, rest=0), "crs03", seed=0, rate_hz=0.001),
         "rate_hz 0.001 gives 1 sample(s), and a drive needs at least 2"),
    ],
)
def test_a_rate_too_low_for_a_drive_is_refused(build: object, message: str) -> None:
    with pytest.raises(ValueError, match=re.escape(message)):
        build()  # type: ignore[operator]


@pytest.mark.parametrize("profile", [motion.square_path, motion.rotary_table, motion.hdr_figure3])
def test_a_motion_without_rest_has_no_rest_window(profile: object) -> None:
    # rest=0 gave the window [0, 0], one sample, which no bias can come from
    trajectory = profile(rest=0)  # type: ignore[operator]
    assert trajectory.rest is None
    assert len(sim.simulate(trajectory, "crs03", seed=0)) > 2


@pytest.mark.parametrize(("keyword", "meant"), [("durration", "duration"), ("bias_dsp", "bias_dps"), ("sensor", "sensor_name")])
def test_car_drives_misspelt_keyword_is_named_with_the_closest_of_its_own_and_the_sensors(keyword: str, meant: str) -> None:
    # "unknown sensor field(s) durration; the fields are name, rate_hz, ...": duration was not suggested
    with pytest.raises(TypeError, match=rf"^unknown keyword\(s\) '{keyword}' \(did you mean '{meant}'\?\): neither a "
                                        r"keyword of car_drive \(duration, rate_hz, seed, rest, mix, sensor_name\) nor "
                                        r"a sensor field \(name, rate_hz, "):
        sim.car_drive(**{keyword: 30})
