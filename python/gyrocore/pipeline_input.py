"""What a streaming :class:`~gyrocore.Pipeline` says of a chunk's input around the core: a chunk
that would close the rest window without a reading in it, what the input policy repaired, a
chunk sent again, and a stream too slow for the rest tracker's blocks."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from . import _gyrocore
from ._arrays import FloatArray
from ._checks import MAX_READING, keep_readings, usable, warn, warn_units
from ._time_steps import name_time_step
from .window import RestWindowError, ends_before_first, no_usable_reading, refuse_start_before


def refuse_window_without_reading(
    core: _gyrocore.Pipeline, t: FloatArray, rate: FloatArray, temperature: FloatArray | None, first: float | None = None
) -> None:
    """Refuse, before the ``core`` processes anything, a chunk that would close the rest window with no
    reading in it (the bias would silently be 0): the core's rule, that the first reading it
    takes after the window's end closes it, applied to the chunk's timestamps.

    Only a chunk whose timestamps the core accepts is checked; it rejects the others itself.
    ``first``: the log's first time, if an earlier chunk gave it.
    """
    p = core.params()
    _, count, learning = core.bias()
    if "bias_window" not in p or not learning or count > 0 or len(t) == 0:
        return
    last = core.last_time()
    if not (np.isfinite(t).all() and (np.diff(t) > 0).all() and (last is None or t[0] > last)):
        return
    taken = usable(rate)  # the readings the filters see: skipped ones are not
    if temperature is not None and len(temperature) == len(t):
        taken &= usable(temperature)
    if p["nonfinite"] == "hold":  # held once there was a finite reading
        taken |= np.logical_or.accumulate(taken) | (last is not None)
    start, end = p["bias_window"]
    if last is None:  # the log's first chunk
        refuse_start_before(start, end, float(t[0]))
    after = np.flatnonzero(taken & (t > end))
    if len(after) == 0:
        return
    k = int(after[0])
    if (taken[:k] & (t[:k] >= start)).any():
        return
    before = t[k - 1] if k > 0 else last
    if before is None:
        raise ends_before_first(start, end, float(t[0]))
    # samples in the window (here, or an earlier chunk's at or after its start), none of them taken
    # (skipped): the log does not jump, as the error below would say
    if ((t[:k] >= start) & (t[:k] <= end)).any() or (last is not None and last >= start):
        error = no_usable_reading(start, end, float(t[0]) if first is None else first)
        raise RestWindowError(f"{error}; nothing of this chunk was processed", error.span)
    raise RestWindowError(
        f"the bias window [{start}, {end}] s holds no sample of the log, which jumps from t = {before} "
        f"to t = {t[k]} s (index {k} of this chunk); give a window where the log has readings at rest. "
        "Nothing of this chunk was processed"
    )


def warn_repairs(
    core: _gyrocore.Pipeline,
    before: dict[str, float],
    after: dict[str, float],
    t: FloatArray,
    rate: FloatArray,
    temperature: FloatArray | None,
    said: set[str],
) -> None:
    """Say what the input policy of the ``core`` repaired in this chunk (indices are within the chunk): the
    readings the core does not take, NaN and infinities as well as finite ones beyond its
    limit (:data:`~gyrocore._checks.MAX_READING`, a wrong unit or a corrupt sample), and the gaps
    beyond ``gap_limit``. Each policy's repairs, and the gaps, are said once per stream (``said``
    holds the ones said): a warning per chunk flooded the log of a stream of many chunks; the
    report counts them all."""
    for key, verb in (("held", "replaced by the last usable reading"), ("skipped", "skipped")):
        n = int(after[key] - before[key])
        if n and key not in said:
            said.add(key)
            where = _first_unusable(t, rate, temperature)
            warn(f"{n} reading(s) not finite or beyond +-{MAX_READING:.0f} {verb} ({where}); said once per "
                 f"pipeline: its report['{key}'] counts those of later chunks too")
    gaps = int(after["gaps"] - before["gaps"])
    if gaps and "gaps" not in said:
        said.add("gaps")
        params = core.params()
        warn(
            f"{gaps} gap(s) longer than {params['gap_limit']} s (longest so far {after['longest_gap']:.6g} s); "
            f"gap_action={params['gap_action']!r}; said once per pipeline: its report['gaps'] and "
            "report['longest_gap'] count those of later chunks too"
        )


def say_what_to_do(error: _gyrocore.SampleError, t: FloatArray, last: float | None, index_offset: int,
                   nonfinite: str) -> None:
    """Adds to the core's error about a bad sample what the caller can do about it: for a reading
    the pipeline does not take, the policy that takes it (the core's words, "drop or fill them
    first", sent a user with a file to edit it); for a time that a counter's wrap sent back or
    float32 rounding repeated, :func:`name_time_step`; for a chunk that starts at or before the
    last sample processed, :func:`name_samples_sent_again`. A file's reader gives its own words,
    with the file's line (``log_message``: the core's, a step back's as a series' from the binding)."""
    if error.what in ("rate", "temperature") and nonfinite == "error":
        error.log_message = str(error)  # type: ignore[attr-defined]
        error.args = (f"{error}; " + keep_readings("them", "nonfinite='hold'", "'skip'"),)
    if not name_time_step(error, t, last, index_offset):
        name_samples_sent_again(error, t, last, index_offset)


def name_samples_sent_again(error: _gyrocore.SampleError, t: FloatArray, last: float | None,
                            index_offset: int) -> None:
    """Adds to the core's error about a chunk whose first sample comes at or before the last one
    processed what a stream does about it: the core's words ask to sort a log, but a stream that
    sends a chunk again, or resumes from a pickle and sends what the pickle holds already, has no
    log to sort; it gives the samples after :attr:`Pipeline.last_time`."""
    if error.what != "t" or error.index != index_offset or last is None or not len(t) or not t[0] <= last:
        return
    newer = int(np.count_nonzero(t > last))
    # a file's reader sorts the log instead: the core's words, a step back's as a series' (the binding's)
    error.log_message = getattr(error, "log_message", str(error))  # type: ignore[attr-defined]
    error.args = (f"{error}; the chunk starts at or before t = {last!r}, the last sample this pipeline processed "
                  f"(Pipeline.last_time; a pipeline resumed from a pickle holds every sample up to it): give only "
                  f"the samples after it ({newer} of this chunk's {len(t)}). Nothing of this chunk was processed",)


def _first_unusable(t: FloatArray, rate: FloatArray, temperature: FloatArray | None) -> str:
    """Where the first reading the core does not take is, and what it reads."""
    readings = [("rate", rate, "rad/s")] + ([] if temperature is None else [("temperature", temperature, "degC")])
    bad = np.logical_or.reduce([~usable(values) for _, values, _ in readings])
    i = int(np.argmax(bad))  # the core counted at least one
    what, values, unit = next(r for r in readings if not usable(r[1][i : i + 1])[0])
    return f"first at index {i}, t = {t[i]}: {what} {values[i]} {unit}"


def warn_speed_outside(t: FloatArray, speed: FloatArray, speed_t: ArrayLike) -> bool:
    """Warns of a stream's chunk whose samples lie outside the times of the speed given with it
    (``speed`` is NaN there); true if it did. Their speed is unknown, so the tracker judged them by
    the rate alone, and a robot that gave each chunk the odometry received so far found no rest
    where one call over its log found one."""
    unknown = int(np.count_nonzero(np.isnan(speed)))
    if not unknown:
        return False
    st = np.asarray(speed_t, dtype=np.float64)
    span = f"{float(st[0])!r} to {float(st[-1])!r} s" if len(st) else "none"
    warn(f"{unknown} of this chunk's {len(t)} gyro samples lie outside the times of the speed given with it "
         f"({span}): their speed is unknown and the rest tracker judges them by the rate alone; where the speed "
         "goes on, a stream then finds other rests than one call over the same samples: hold the gyro back "
         "until the speed covers it, and give the speed from its last sample before the chunk's first on "
         "(docs/python.md)")
    return True


#: Parameters of FOG eq 5's temperature model: without one, a temperature given is not used.
TEMPERATURE_MODEL = ("temp_slope", "temp_offset")

#: Samples a stream's unit check waits for (one interval): a first chunk of one sample has none.
UNIT_SAMPLES = 2


def check_units(held: tuple[FloatArray, FloatArray], t: FloatArray, rate: FloatArray,
                temperature: FloatArray | None, params: dict[str, Any]) -> tuple[FloatArray, FloatArray] | None:
    """Warns of rates or timestamps that look like another unit, and of a rest tracker whose
    blocks are too short for the stream's rate, once the stream has an interval to judge: a
    robot's first chunk of one sample has none, and its timestamps in ms were never judged
    (the later chunks were not looked at), where one call warned. ``held`` are the samples of the
    stream kept so far for it; returns those to keep, or None once the stream is judged."""
    held_t, held_rate = held
    if not len(held_t) and temperature is not None and not any(params.get(k) is not None for k in TEMPERATURE_MODEL):
        warn(
            f"temperature is given but no temperature model ({', '.join(TEMPERATURE_MODEL)}) is set: it is "
            "not used; set the model (e.g. calibration.rotary_table's) or leave the temperature out"
        )
    # a first chunk is judged as it is: copied whole behind nothing held, a long log's times and
    # readings took two more arrays as long as the log (2.1 s of a call of 5*10^7 samples)
    head_t, head_rate = (t, rate) if not len(held_t) else (np.concatenate((held_t, t)),
                                                            np.concatenate((held_rate, rate)))
    if len(head_t) < UNIT_SAMPLES:  # held as copies: a caller may fill its arrays anew for the next chunk
        return (np.array(head_t), np.array(head_rate))
    warn_units(head_t, head_rate)
    warn_slow_tracker(head_t, params)
    return None


def warn_slow_tracker(t: FloatArray, params: dict[str, Any]) -> None:
    """Warns where the rest tracker of ``params`` can find no rest in a stream sampled as ``t`` is
    (its first samples, strictly increasing): each detection block of ``rest_block`` seconds
    measures its noise from the differences of its readings, so it needs two, and a block with
    one is never still (a 3.5 Hz stream with blocks of 0.5 s found no rest in a drive where 4 Hz
    found nine)."""
    if not params.get("track_rests") or len(t) < 2:
        return
    interval, block = float(np.median(np.diff(t))), float(params["rest_block"])
    if 2.0 * interval > block:
        warn(f"the rest tracker's blocks of rest_block = {block:g} s hold fewer than two readings at this stream's "
             f"rate ({1.0 / interval:.3g} Hz), and a block needs two to measure its noise: it finds no rest; give "
             f"rest_block of at least two sample intervals ({2.0 * interval:.3g} s) and rest_min_duration of at least "
             "twice that")
