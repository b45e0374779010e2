"""A simulated yaw-rate gyro with a known truth: the error model, the papers' sensors, and drives.

The gyro reads ``r_m = (1 + s) r + b + d + w`` (Hong eq 1, with the residual ``d`` of Hong eq 10):
scale error ``s`` (temperature-dependent, different for clockwise and counter-clockwise rates),
bias ``b`` (temperature-dependent), slow stochastic bias ``d`` (bias instability as flicker noise,
and the rate random walk of Hong eq 11), white noise ``w`` (angle random walk), then range clipping
and quantisation. Samples arrive on a jittered grid and some are lost. The per-sample work runs in
Rust (``rust/src/sim.rs``, which documents the model).

A :class:`GyroSpec` holds a sensor's errors in datasheet units (deg/sqrt(h), deg/h, deg/h/sqrt(h),
deg/s, percent as a fraction); :data:`SENSORS` has the papers' three sensors. :func:`simulate` runs a
:class:`gyrocore.motion.Motion` through a sensor and returns a :class:`Drive` with the truth.

The motion and the slow gyro errors are functions of continuous time fixed by the seed, so one
drive can be sampled at any rate; only the white noise depends on the sample interval
(``sigma = ARW sqrt(rate)``), as it does for a real gyro.

    >>> import gyrocore
    >>> d = gyrocore.sim.car_drive(duration=120.0, rate_hz=10.0, seed=1)
    >>> (len(d.t), d.stationary)
    (1200, (0.0, 20.0))
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, fields, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from . import _gyrocore, motion
from ._arrays import FloatArray, as_float_array
from ._checks import check_number, check_seed, public_dir, real_number, require_choice
from ._sim_fields import check_spec, refuse_unknown_keywords
from .window import MIN_WINDOW_READINGS

__all__ = [
    "CAR_REST", "MAX_FIXES", "SENSORS", "SIGMA_DEG", "Drive", "GyroSpec", "Reading", "car_drive", "check_span",
    "gnss_fixes", "measure", "refuse_too_few_samples", "sample_times", "sensor", "simulate",
]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__

_DEG = math.pi / 180.0
_HOUR = 3600.0


@dataclass(frozen=True)
class GyroSpec:
    """A gyro's errors in datasheet units (converted to SI by :meth:`si` for the Rust model).

    Attributes:
        name: label used in tables and plots.
        rate_hz: output data rate [Hz]; also the bandwidth of the white noise.
        arw_deg_per_sqrt_h: angle random walk ``N`` [deg/sqrt(h)] (Allan deviation ``N / sqrt(tau)``).
        bandwidth_hz: corner of the sensor's first-order low-pass on the white noise [Hz]: above
            it, consecutive samples are correlated and each has less noise (infinity: none).
        bias_instability_deg_per_h: bias instability ``B`` [deg/h] (IEEE 952 flicker coefficient:
            the Allan deviation is flat at ``0.664 B``).
        rrw_deg_per_h_per_sqrt_h: rate random walk ``K`` [deg/h/sqrt(h)] (Hong eq 11).
        flicker_band_s: (shortest, longest) correlation time of the flicker approximation [s].
        bias_dps: bias ``b`` at the reference temperature [deg/s] (what the gyro reads at rest).
        bias_dps_per_c: change of the bias per degree [deg/s/degC].
        scale_error: scale error ``s`` at the reference temperature [1] (0.025 reads 2.5 % high).
        scale_asymmetry: scale error of counter-clockwise minus clockwise rates [1].
        scale_per_c: change of the scale error per degree [1/degC].
        temperature_c: sensor temperature (at the first sample, reached in the end) [degC].
        temperature_time_constant_s: time constant of the approach between the two [s].
        reference_temperature_c: temperature at which ``bias_dps`` and ``scale_error`` hold [degC].
        resolution_dps: one least significant bit [deg/s] (0: no quantisation).
        range_dps: measurement range [deg/s] (readings are clipped to +-range).
        jitter_s: standard deviation of each sampling instant about the nominal grid [s].
        drop_probability: probability that a sample is lost before it reaches the log.
        drift_step_s: grid on which the slow bias is generated and interpolated [s].
        source: where the values come from (paper and section, or "assumed").
    """

    name: str = "ideal"
    rate_hz: float = 100.0
    arw_deg_per_sqrt_h: float = 0.0
    bandwidth_hz: float = math.inf
    bias_instability_deg_per_h: float = 0.0
    rrw_deg_per_h_per_sqrt_h: float = 0.0
    flicker_band_s: tuple[float, float] = (1.0, 1.0e5)
    bias_dps: float = 0.0
    bias_dps_per_c: float = 0.0
    scale_error: float = 0.0
    scale_asymmetry: float = 0.0
    scale_per_c: float = 0.0
    temperature_c: tuple[float, float] = (25.0, 25.0)
    temperature_time_constant_s: float = 600.0
    reference_temperature_c: float = 25.0
    resolution_dps: float = 0.0
    range_dps: float = math.inf
    jitter_s: float = 0.0
    drop_probability: float = 0.0
    drift_step_s: float = 0.1
    source: str = field(default="", compare=False)

    def si(self) -> dict[str, float]:
        """The flat SI configuration of the Rust model (rad/s, rad/sqrt(s), rad/s/sqrt(s), s, degC)."""
        return {
            "rate_hz": self.rate_hz,
            "jitter": self.jitter_s,
            "drop_probability": self.drop_probability,
            "scale_error": self.scale_error,
            "scale_asymmetry": self.scale_asymmetry,
            "scale_temperature": self.scale_per_c,
            "bias": self.bias_dps * _DEG,
            "bias_temperature": self.bias_dps_per_c * _DEG,
            "arw": self.arw_deg_per_sqrt_h * _DEG / math.sqrt(_HOUR),
            "bandwidth": self.bandwidth_hz,
            "bias_instability": self.bias_instability_deg_per_h * _DEG / _HOUR,
            "flicker_min": self.flicker_band_s[0],
            "flicker_max": self.flicker_band_s[1],
            "rrw": self.rrw_deg_per_h_per_sqrt_h * _DEG / _HOUR / math.sqrt(_HOUR),
            "drift_step": self.drift_step_s,
            "temperature_start": self.temperature_c[0],
            "temperature_end": self.temperature_c[1],
            "temperature_time_constant": self.temperature_time_constant_s,
            "reference_temperature": self.reference_temperature_c,
            "resolution": self.resolution_dps * _DEG,
            "range": self.range_dps * _DEG,
        }

    def __post_init__(self) -> None:
        """Check each field's kind here, and its range in the core, so that a spec built directly is
        checked as one from :meth:`replace` is, before any of its properties is read
        (``GyroSpec(rate_hz=True)`` was a gyro at 1 Hz; ``noise_rms_dps`` of a rate of 0 failed).

        Raises:
            TypeError: a value of the wrong kind for its field: text or a bool for a number (``True``
                was 1 deg/s), anything but two numbers for a pair.
            ValueError: a number out of its range, named by its field (:func:`~gyrocore._sim_fields.check_spec`).
        """
        for f in fields(self):
            value, kind = getattr(self, f.name), str(f.type)  # the annotation's text (postponed annotations)
            if kind == "str":
                ok, what = isinstance(value, str), "text"
            elif kind.startswith("tuple"):
                ok = isinstance(value, (tuple, list)) and len(value) == 2 and all(real_number(v) is not None for v in value)
                what = "two numbers"
            else:
                ok, what = real_number(value) is not None, "a number"
            if not ok:
                raise TypeError(f"sensor field {f.name} must be {what}, got {value!r}")
        check_spec(self)  # the core's checks of the model, one second of it, naming the field

    def replace(self, **changes: Any) -> GyroSpec:
        """A copy with some fields changed (``spec.replace(rate_hz=10.0)``), checked as any spec is.

        Raises:
            TypeError: a name that is no field, or a value of the wrong kind for its field.
            ValueError: a number out of its range.
        """
        unknown = sorted(set(changes) - {f.name for f in fields(self)})
        if unknown:  # dataclasses' "GyroSpec.__init__() got an unexpected keyword argument"
            raise TypeError(f"unknown sensor field(s) {', '.join(unknown)}; the fields are "
                            f"{', '.join(f.name for f in fields(self))}")
        return replace(self, **changes)

    @property
    def noise_rms_dps(self) -> float:
        """The rms of the white noise in one sample [deg/s]: ``N sqrt(rate_hz)`` through the
        first-order low-pass of ``bandwidth_hz``, whose pole ``a = exp(-2 pi bandwidth / rate)``
        leaves the variance ``N^2 rate (1 - a) / (1 + a)`` (``rust/src/sim.rs``)."""
        a = math.exp(-2.0 * math.pi * self.bandwidth_hz / self.rate_hz)
        return self.arw_deg_per_sqrt_h / math.sqrt(_HOUR) * math.sqrt(self.rate_hz * (1.0 - a) / (1.0 + a))

    def allan_deviation(self, taus: ArrayLike) -> FloatArray:
        """Closed-form Allan deviation [rad/s] of the noise terms at averaging times ``taus`` [s]
        (IEEE 952 Annex C: ARW through the ``bandwidth_hz`` low-pass, the flicker terms, RRW; without
        quantisation and temperature)."""
        adev: FloatArray = _gyrocore.gyro_allan_deviation(self.si(), as_float_array("taus", taus))
        return adev

    def as_dict(self) -> dict[str, Any]:
        """The fields as a plain dict (for JSON)."""
        return asdict(self)


#: The papers' sensors. Values marked "assumed" are not in the papers; they are plausible for the
#: class of sensor and documented here so that results can be traced.
SENSORS: dict[str, GyroSpec] = {
    "xv3500": GyroSpec(
        name="Epson XV3500",
        rate_hz=100.0,
        arw_deg_per_sqrt_h=2.5,
        bandwidth_hz=20.0,
        bias_instability_deg_per_h=18.0,
        rrw_deg_per_h_per_sqrt_h=4.0,
        flicker_band_s=(1.0, 1.0e5),
        bias_dps=0.75,
        bias_dps_per_c=0.01,
        scale_error=0.0253,
        range_dps=100.0,
        source=(
            "Hong & Park: ARW 2.5 deg/sqrt(h), bias instability 18 deg/h (section 2.1), scale error "
            "2.53 % (2.2), bias 0.75 deg/s (their estimate, 4.2), 100 Hz (4.1), +-100 deg/s (the rate "
            "table's span in 2.2); a 20 Hz noise bandwidth gives Figure 8a's 2 deg/s peak-to-peak noise; "
            "assumed: RRW, flicker band, 0.01 deg/s/degC"
        ),
    ),
    "crs03": GyroSpec(
        name="Silicon Sensing CRS03-04",
        rate_hz=10.0,
        arw_deg_per_sqrt_h=3.0,
        bandwidth_hz=10.0,
        bias_instability_deg_per_h=66.0,
        rrw_deg_per_h_per_sqrt_h=10.0,
        flicker_band_s=(1.0, 1.0e5),
        bias_dps=1.432,
        bias_dps_per_c=0.005,
        scale_error=0.01,
        resolution_dps=400.0 / 65536.0,
        range_dps=200.0,
        temperature_c=(20.0, 20.0),
        source=(
            "HDR paper: bias drift < 66 deg/h, +-200 deg/s, 10 Hz bandwidth and sampling (Table I, "
            "section 5), static bias 1.432 deg/s (5.2); assumed: ARW, RRW, flicker band, 1 % scale "
            "error, 0.005 deg/s/degC, a 16-bit converter"
        ),
    ),
    "fog": GyroSpec(
        name="KVH/Andrew Autogyro Navigator (FOG)",
        rate_hz=100.0,
        arw_deg_per_sqrt_h=0.07,
        bandwidth_hz=100.0,
        bias_instability_deg_per_h=18.0,
        rrw_deg_per_h_per_sqrt_h=1.0,
        flicker_band_s=(0.1, 1.0e5),
        bias_dps=0.01,
        bias_dps_per_c=0.0005,
        # FOG eq 5: turn error E_T = -0.52 T + 19.23 deg per 360 deg, i.e. s(T) = E_T / 360.
        scale_error=(19.23 - 0.52 * 25.0) / 360.0,
        scale_per_c=-0.52 / 360.0,
        temperature_c=(22.0, 42.0),
        temperature_time_constant_s=2400.0,
        range_dps=100.0,
        source=(
            "FOG paper: bias drift 18 deg/h rms, +-100 deg/s, 100 Hz bandwidth (Table I), scale error "
            "linear in temperature (eq 5), steady temperature after about 2 h (section 3); the 0.5 % "
            "scale non-linearity is represented by that temperature-linear scale error; assumed: ARW, "
            "RRW, flicker band, bias and its temperature coefficient, 22 -> 42 degC warm-up"
        ),
    ),
}


def sensor(name: str | GyroSpec, **changes: Any) -> GyroSpec:
    """A sensor of :data:`SENSORS` by name (or a spec as given), with ``changes`` applied."""
    if isinstance(name, GyroSpec):
        spec = name
    else:
        require_choice("sensor", name, SENSORS)
        spec = SENSORS[name]
    return spec.replace(**changes) if changes else spec


def sample_times(spec: GyroSpec, start: float, end: float, *, seed: int) -> FloatArray:
    """The instants [s] in ``[start, end)`` at which the log receives samples: the grid of
    ``spec.rate_hz`` with the spec's jitter and dropped samples (the first sample is never moved or
    dropped)."""
    t: FloatArray = _gyrocore.gyro_sample_times(spec.si(), check_seed(seed), float(start), float(end))
    return t


def check_span(spec: GyroSpec, start: float, end: float) -> None:
    """Refuses the span ``[start, end)`` as :func:`sample_times` would (not finite, empty, or more
    samples than the simulator makes: a duration in the wrong unit), without making the samples:
    asked before a long route is built manoeuvre by manoeuvre."""
    _gyrocore.gyro_check_span(spec.si(), float(start), float(end))


@dataclass(frozen=True, repr=False, eq=False)
class Reading:
    """What the simulated gyro reads and the truth about its errors, per sample.

    Attributes:
        rate: the reading ``r_m`` [rad/s].
        temperature: sensor temperature [degC].
        bias: everything it would read at rest apart from white noise, ``b + d`` [rad/s].
        scale: the scale error ``s`` applied [1].
    """

    rate: FloatArray
    temperature: FloatArray
    bias: FloatArray
    scale: FloatArray

    def __repr__(self) -> str:
        return f"Reading(n={len(self.rate)})"


def measure(spec: GyroSpec, t: ArrayLike, rate_true: ArrayLike, *, seed: int) -> Reading:
    """Readings of the gyro ``spec`` for the true rate [rad/s] at times ``t`` [s] (strictly
    increasing; the first is the model's time origin)."""
    ta, ra = as_float_array("t", t), as_float_array("rate_true", rate_true, unit="rad/s")
    rate, temperature, bias, scale = _gyrocore.gyro_measure(spec.si(), check_seed(seed), ta, ra)
    return Reading(rate, temperature, bias, scale)


@dataclass(frozen=True, repr=False, eq=False)
class Drive:
    """A simulated run: the true motion, the gyro's reading and its (known) errors, per sample.

    Units: s, rad/s, rad, m, m/s, degC; counter-clockwise positive.

    Attributes:
        t: sample times [s].
        rate_true: true yaw rate [rad/s].
        heading_true: true heading [rad] (continuous, 0 at the start).
        rate_measured: the gyro's reading [rad/s].
        drift: the slow error ``eps_d`` (HDR eq 1) at each sample: the gyro's bias ``b + d`` minus
            :attr:`bias` [rad/s]. Scale error and white noise are not part of it.
        bias: the static bias ``eps0`` [rad/s]: the mean of ``b + d`` over the rest window (what a
            noise-free static bias test there would measure), or its value at the first sample.
        stationary: rest window at the start [s], or None.
        x, y: true position [m]. speed: true forward speed [m/s].
        temperature: sensor temperature [degC]. scale: scale error ``s`` per sample [1].
        motion: the motion that was sampled. sensor: the gyro. seed: the seed.
    """

    t: FloatArray
    rate_true: FloatArray
    heading_true: FloatArray
    rate_measured: FloatArray
    drift: FloatArray
    bias: float
    stationary: tuple[float, float] | None
    x: FloatArray
    y: FloatArray
    speed: FloatArray
    temperature: FloatArray
    scale: FloatArray
    motion: motion.Motion
    sensor: GyroSpec
    seed: int

    @property
    def duration(self) -> float:
        """Length of the record [s]."""
        return float(self.t[-1] - self.t[0])

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:
        return (
            f"Drive({self.motion.name!r}, {self.sensor.name!r} at {self.sensor.rate_hz:g} Hz, "
            f"seed {self.seed}, n={len(self.t)}, {self.duration:.1f} s, "
            f"static bias {math.degrees(self.bias):.4f} deg/s, "
            f"drift within +-{math.degrees(float(np.abs(self.drift).max())):.4f} deg/s)"
        )


def simulate(trajectory: motion.Motion, spec: GyroSpec | str, *, seed: int, rate_hz: float | None = None) -> Drive:
    """Sample ``trajectory`` with the gyro ``spec`` (a :class:`GyroSpec` or a name in :data:`SENSORS`).

    The samples fall on the spec's grid (with its jitter and drops) over the motion's duration.
    ``rate_hz`` overrides the spec's rate. Same arguments, same drive.

    Raises:
        TypeError: a ``trajectory`` that is no :class:`gyrocore.motion.Motion` (None was "'NoneType'
            object has no attribute 'duration'"), a ``rate_hz`` that is no number.
        ValueError: an unknown sensor, a ``seed`` outside [0, 2^64), a span the simulator refuses,
            a rate that gives fewer than two samples or fewer than three in the motion's rest.
    """
    if not isinstance(trajectory, motion.Motion):
        raise TypeError(f"trajectory must be a gyrocore.motion.Motion (e.g. gyrocore.motion.car(600)), got "
                        f"{type(trajectory).__name__}")
    spec = sensor(spec) if rate_hz is None else sensor(spec, rate_hz=rate_hz)
    seed = check_seed(seed)
    t = sample_times(spec, 0.0, trajectory.duration, seed=seed)
    refuse_too_few_samples(t, trajectory.rest, spec.rate_hz)
    truth = trajectory.sample(t)
    reading = measure(spec, t, truth.rate, seed=seed)
    window = trajectory.rest
    if window is not None:
        inside = (t >= window[0]) & (t <= window[1])
        bias = float(reading.bias[inside].mean())
    else:
        bias = float(reading.bias[0])
    return Drive(
        t=t,
        rate_true=truth.rate,
        heading_true=truth.heading,
        rate_measured=reading.rate,
        drift=reading.bias - bias,
        bias=bias,
        stationary=window,
        x=truth.x,
        y=truth.y,
        speed=truth.speed,
        temperature=reading.temperature,
        scale=reading.scale,
        motion=trajectory,
        sensor=spec,
        seed=seed,
    )


def refuse_too_few_samples(t: FloatArray, window: tuple[float, float] | None, rate_hz: float) -> None:
    """Refuse a drive (sample times ``t``) whose rest ``window`` holds too few samples to measure
    its bias, or of fewer than two samples: a rate of 0.01 Hz gave a one-sample drive without a
    word, which every command that read it refused later (a heading error needs two samples)."""
    if window is not None:
        start, end = window
        readings = int(np.count_nonzero((t >= start) & (t <= end)))
        if readings < MIN_WINDOW_READINGS:
            raise ValueError(
                f"rate_hz {rate_hz:g} puts {readings} sample(s) in the drive's rest window [{start:g}, {end:g}] s, "
                f"and its bias needs at least {MIN_WINDOW_READINGS}: give a higher rate (--rate-hz)"
            )
    if len(t) < 2:
        raise ValueError(f"rate_hz {rate_hz:g} gives {len(t)} sample(s), and a drive needs at least 2: "
                         "give a higher rate (--rate-hz)")


#: The rest that begins a car drive by default [s] (its static bias test).
CAR_REST = 20.0


def car_drive(
    duration: float = 600.0,
    rate_hz: float = 100.0,
    *,
    seed: int = 0,
    rest: float = CAR_REST,
    mix: str = "mixed",
    sensor_name: str | GyroSpec = "crs03",
    **changes: Any,
) -> Drive:
    """A car drive: a rest of ``rest`` seconds (the static bias test), then the road mix ``mix``
    of :data:`gyrocore.motion.ROAD_MIXES` (straight stretches with a slight swerve, swaying,
    curves, 90-degree turns, stops), read by the gyro ``sensor_name`` (default the HDR paper's
    CRS03-04) at ``rate_hz``. ``changes`` modify the sensor (``bias_dps=0.5``, ...).

    One seed fixes the route, the drift and the noise; the route and the drift do not depend on
    ``rate_hz``.

    Raises:
        TypeError: a ``duration``, ``rate_hz`` or ``rest`` that is no number (a bool, text).
        ValueError: a ``duration`` or ``rate_hz`` that is not finite and > 0, a ``rest`` that is not
            finite and >= 0 or not shorter than the drive, a ``seed`` outside [0, 2^64).
    """
    # each named as given: text was a bare "'<' not supported", True a drive of 1 s or a gyro at 1 Hz,
    # a negative rest "must be shorter than the drive", and seed=-1 numpy's "expected non-negative integer"
    duration, rate_hz = check_number("duration", duration, unit=" [s]"), check_number("rate_hz", rate_hz, unit=" [Hz]")
    rest, seed = check_number("rest", rest, strict=False, unit=" [s]"), check_seed(seed)
    refuse_unknown_keywords(car_drive, changes, [f.name for f in fields(GyroSpec)])
    spec = sensor(sensor_name, rate_hz=rate_hz, **changes)
    # a drive of 1e12 s was built manoeuvre by manoeuvre before the simulator refused it
    check_span(spec, 0.0, duration)
    route = motion.car(duration, mix=mix, seed=seed, rest=rest)
    return simulate(route, spec, seed=seed)


# the simulated receiver lives in its own module; gyrocore.sim is where users find it
from .sim_gnss import MAX_FIXES, SIGMA_DEG, gnss_fixes  # noqa: E402
