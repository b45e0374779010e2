"""The Python API: process, Pipeline (streaming, pickle, reset), integrate, presets and errors."""

from __future__ import annotations

import inspect
import math
import pickle
import warnings

import numpy as np
import pytest

import gyrocore


def _log(n: int = 3000, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    t = 1.65e9 + np.cumsum(rng.uniform(0.005, 0.02, n))
    rate = 0.01 + 0.3 * np.sin(t / 7.0) * (rng.random(n) < 0.5) + rng.normal(0, 0.01, n)
    return t, rate


def test_process_returns_float64_arrays_of_input_length() -> None:
    t, rate = _log()
    r = gyrocore.process(t, rate, "combined", bias=0.01)
    for name in ("t", "heading", "rate", "drift"):
        a = getattr(r, name)
        assert a.dtype == np.float64 and a.shape == t.shape, name
    assert "HeadingResult(n=3000" in repr(r)
    assert np.array_equal(r.heading_deg, np.degrees(r.heading))


@pytest.mark.parametrize("preset", ["raw", "static_bias", "hong_park", "hdr", "combined", "recommended"])
def test_chunked_streaming_is_bit_identical(preset: str) -> None:
    t, rate = _log()
    whole = gyrocore.Pipeline(preset, bias_duration=2.0).process(t, rate)
    p = gyrocore.Pipeline(preset, bias_duration=2.0)
    parts = [p.process(t[a:b], rate[a:b]) for a, b in [(0, 1), (1, 700), (700, 701), (701, 3000)]]
    for name in ("heading", "rate", "drift"):
        joined = np.concatenate([getattr(x, name) for x in parts])
        assert np.array_equal(joined, getattr(whole, name)), name


@pytest.mark.filterwarnings("ignore:the rest window")  # its synthetic rate turns in the window
def test_long_arrays_written_while_another_core_faults_their_pages_in_are_bit_identical() -> None:
    # From 2**18 samples on, the outputs' pages are faulted in by a helper thread as the pipeline
    # writes them; chunks below that size are written without it.
    t, rate = _log(600_000)
    whole = gyrocore.Pipeline("combined", bias_duration=2.0).process(t, rate)
    p = gyrocore.Pipeline("combined", bias_duration=2.0)
    parts = [p.process(t[a : a + 100_000], rate[a : a + 100_000]) for a in range(0, len(t), 100_000)]
    for name in ("heading", "rate", "drift"):
        joined = np.concatenate([getattr(x, name) for x in parts])
        assert np.array_equal(joined, getattr(whole, name)), name


def test_pickle_mid_stream_continues_bit_identically_and_reset_restarts() -> None:
    t, rate = _log()
    a = gyrocore.Pipeline("combined", bias_window=(t[0], t[200]))
    a.process(t[:1000], rate[:1000])
    b = pickle.loads(pickle.dumps(a))
    assert b.params == a.params and b.preset == "combined"
    ra, rb = a.process(t[1000:], rate[1000:]), b.process(t[1000:], rate[1000:])
    assert np.array_equal(ra.heading, rb.heading) and np.array_equal(ra.drift, rb.drift)
    a.reset()
    fresh = gyrocore.Pipeline("combined", bias_window=(t[0], t[200])).process(t, rate)
    assert np.array_equal(a.process(t, rate).heading, fresh.heading)


def test_noise_scaled_settings_round_trip_and_report_the_rest_window() -> None:
    t = np.arange(0.0, 60.0, 0.01)
    rate = 0.01 + np.random.default_rng(3).normal(0.0, 0.002, len(t))
    p = gyrocore.Pipeline("tuned", bias_window=(0.0, 20.0), threshold_sigmas=1.5, hdr_bound_sigmas=2.0,
                          hdr_turn_threshold=math.inf)
    assert p.rest_statistics is None  # nothing measured yet
    p.process(t[:1000], rate[:1000])
    assert p.rest_statistics is None  # still inside the window
    p.process(t[1000:3000], rate[1000:3000])
    stats = p.rest_statistics
    assert stats is not None
    assert stats["noise"] == pytest.approx(0.002, rel=0.05)
    assert stats["bias_std_error"] == pytest.approx(0.002 / math.sqrt(2000), rel=0.6)
    # Pickling keeps the infinite turn threshold and bound, and the scaled values.
    q = pickle.loads(pickle.dumps(p))
    assert q.params == p.params and q.params["hdr_turn_threshold"] == math.inf
    assert q.params["threshold_sigmas"] == 1.5 and q.params["hdr_bound_sigmas"] == 2.0
    assert np.array_equal(q.process(t[3000:], rate[3000:]).heading, p.process(t[3000:], rate[3000:]).heading)
    with pytest.raises(ValueError, match="hdr_bound_sigmas = -1: must be finite, >= 0 and at most 2\\^20"):
        gyrocore.Pipeline("tuned", bias=0.0, hdr_bound_sigmas=-1.0)
    with pytest.raises(ValueError, match="hdr_bound_sigmas is set but HDR is off"):
        gyrocore.Pipeline("static_bias", bias=0.0, hdr_bound_sigmas=1.0)


def test_any_float_dtype_and_stride_gives_the_same_result() -> None:
    t, rate = _log(500)
    ref = gyrocore.process(t, rate, "hdr", bias=0.0)
    strided_t = np.repeat(t, 2)[::2]
    assert not np.repeat(rate, 2)[::2].flags.c_contiguous
    got = gyrocore.process(strided_t, np.repeat(rate, 2)[::2], "hdr", bias=0.0)
    assert np.array_equal(got.heading, ref.heading)
    got32 = gyrocore.process(t, rate.astype(np.float32), "hdr", bias=0.0)
    assert np.allclose(got32.heading, ref.heading, atol=1e-5)
    ints = gyrocore.process(np.arange(10), np.ones(10, dtype=np.int64), "raw")
    assert ints.heading[-1] == 9.0


def test_bad_input_raises_with_the_first_bad_index() -> None:
    t, rate = _log(100)
    p = gyrocore.Pipeline("hdr", bias=0.0)
    bad_t = t.copy()
    bad_t[37] = bad_t[36]
    with pytest.raises(ValueError, match=r"t\[37\]"):
        p.process(bad_t, rate)
    bad_r = rate.copy()
    bad_r[12] = np.nan
    with pytest.raises(ValueError, match=r"rate\[12\] is NaN"):
        p.process(t, bad_r)
    with pytest.raises(ValueError, match="length mismatch"):
        p.process(t, rate[:-1])
    with pytest.raises(TypeError, match="real numbers"):
        p.process(t, np.array(["a"] * 100))
    with pytest.raises(ValueError, match="one-dimensional"):
        p.process(t.reshape(10, 10), rate.reshape(10, 10))
    # Nothing was processed: the pipeline still accepts the log from its start.
    assert np.array_equal(p.process(t, rate).heading, gyrocore.process(t, rate, "hdr", bias=0.0).heading)
    with pytest.raises(ValueError, match=r"t\[0\] = .* follows"):
        p.process(t, rate)


def test_empty_input_gives_empty_output() -> None:
    r = gyrocore.process(np.array([]), np.array([]), "raw")
    assert len(r) == 0 and repr(r) == "HeadingResult(empty)"


def test_overrides_in_si_and_degrees_and_unknown_names() -> None:
    si = gyrocore.preset_params("hdr", hdr_increment=math.radians(0.05), threshold=math.radians(0.2))
    deg = gyrocore.preset_params("hdr", hdr_increment_dps=0.05, threshold_dps=0.2)
    assert si == deg
    assert gyrocore.preset_params("recommended") == gyrocore.preset_params(gyrocore.recommended_preset())
    with pytest.raises(ValueError, match="unknown parameter 'hdr_gain'"):
        gyrocore.Pipeline("hdr", bias=0.0, hdr_gain=1.0)
    with pytest.raises(ValueError, match="unknown preset 'fast'"):
        gyrocore.Pipeline("fast")
    with pytest.raises(ValueError, match="hdr_c2 = 0: must be finite and > 0"):
        gyrocore.Pipeline("hdr", bias=0.0, hdr_c2=0.0)
    with pytest.raises(ValueError, match="HDR is off; pass hdr=True"):
        gyrocore.Pipeline("static_bias", bias=0.0, hdr_c1=0.1)
    with pytest.raises(ValueError, match="at most one of bias"):
        gyrocore.Pipeline("hdr", bias=0.0, bias_duration=3.0)
    with pytest.raises(ValueError, match="given twice"):
        gyrocore.Pipeline("hdr", bias=0.0, threshold=0.1, threshold_dps=0.1)


def test_presets_match_the_papers() -> None:
    hdr = gyrocore.preset_params("hdr")
    assert math.degrees(hdr["hdr_increment"]) == pytest.approx(0.0422)
    assert math.degrees(hdr["hdr_turn_threshold"]) == pytest.approx(0.564)
    assert (hdr["hdr_c1"], hdr["hdr_c2"], hdr["lowpass_tau"], hdr["delag"]) == (0.16, 1.8, 0.75, True)
    assert math.degrees(gyrocore.preset_params("hong_park")["threshold"]) == pytest.approx(0.3)
    combined = gyrocore.preset_params("combined")
    assert combined["hdr"] and combined["threshold"] == gyrocore.preset_params("hong_park")["threshold"]
    assert not gyrocore.preset_params("raw")["hdr"]
    assert set(gyrocore.parameters()) >= set(hdr)


def test_missing_bias_warns_and_a_window_outside_the_log_is_an_error() -> None:
    t, rate = _log(200)
    pipeline = gyrocore.Pipeline("static_bias")  # said as samples come: a refused first chunk warns of nothing
    with pytest.warns(UserWarning, match="no bias"):
        pipeline.process(t, rate)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gyrocore.Pipeline("raw")
    with pytest.raises(ValueError, match="ends before the first sample"):
        gyrocore.process(t, rate, "static_bias", bias_window=(0.0, 10.0))


def test_static_bias_from_a_rest_window_is_the_mean_there() -> None:
    t = np.arange(0.0, 30.0, 0.01)
    rate = np.where(t < 10.0, 0.02, 0.5) + 0.0
    p = gyrocore.Pipeline("static_bias", bias_window=(0.0, 9.9))
    r = p.process(t, rate)
    assert p.bias == pytest.approx(0.02, abs=1e-15)
    assert r.rate[-1] == pytest.approx(0.48)


def test_temperature_model_is_applied_and_required() -> None:
    t = np.arange(0.0, 10.0, 0.1)
    rate = np.full_like(t, 0.5)
    temp = np.full_like(t, 25.0)
    fog = {"temp_slope": -0.52 / 360, "temp_offset": 19.23 / 360, "bias": 0.0}
    r = gyrocore.process(t, rate, "static_bias", temperature=temp, **fog)
    assert r.rate[0] == pytest.approx(0.5 * 360 / (379.23 - 0.52 * 25))
    with pytest.raises(ValueError, match="no temperature was given"):
        gyrocore.process(t, rate, "static_bias", **fog)


def test_integrate_and_downsample() -> None:
    t = np.array([0.0, 1.0, 3.0])
    r = np.array([1.0, 2.0, 3.0])
    assert gyrocore.integrate(t, r).tolist() == [0.0, 1.5, 6.5]
    assert gyrocore.integrate(t, r, "rectangle", initial_heading=0.5).tolist() == [0.5, 2.5, 8.5]
    with pytest.raises(ValueError, match="unknown integration method"):
        gyrocore.integrate(t, r, "simpson")
    tt = np.arange(0, 31) * 0.1
    tb, rb = gyrocore.downsample(tt, np.arange(31.0), 1.0)
    assert np.allclose(tb, [1, 2, 3]) and np.allclose(rb, [5.5, 15.5, 25.5])


def test_processing_in_threads_gives_the_sequential_result() -> None:
    # The GIL is released while Rust works; each thread must still see only its own pipeline.
    from concurrent.futures import ThreadPoolExecutor

    logs = [_log(20000, seed=s) for s in range(4)]
    seq = [gyrocore.process(t, r, "combined", bias=0.01).heading for t, r in logs]
    with ThreadPoolExecutor(4) as ex:
        par = list(ex.map(lambda x: gyrocore.process(x[0], x[1], "combined", bias=0.01).heading, logs))
    assert all(np.array_equal(a, b) for a, b in zip(seq, par))


def test_outputs_choose_what_is_computed_and_the_heading_is_the_same() -> None:
    drive = gyrocore.sim.car_drive(duration=120.0, rate_hz=50.0, seed=3)
    t, rate = drive.t, drive.rate_measured
    full = gyrocore.process(t, rate, "recommended", bias_duration=10.0)
    alone = gyrocore.process(t, rate, "recommended", bias_duration=10.0, outputs=("heading",))
    assert np.array_equal(alone.heading, full.heading)
    assert alone.rate is None and alone.drift is None
    with_drift = gyrocore.process(t, rate, "recommended", bias_duration=10.0, outputs=("heading", "drift"))
    assert with_drift.rate is None and np.array_equal(with_drift.output("drift"), full.output("drift"))
    with pytest.raises(ValueError, match="'rate' output was not computed"):
        alone.output("rate")
    for bad in (("rate",), ("heading", "speed"), "heading"):
        with pytest.raises(ValueError, match="outputs="):
            gyrocore.process(t, rate, "raw", outputs=bad)  # type: ignore[arg-type]


def test_parameter_rules_are_the_cores_with_its_message() -> None:
    t = np.arange(0.0, 10.0, 0.01)
    # Without a low-pass the de-lag has nothing to invert: an error, not a silent change.
    with pytest.raises(ValueError, match="invalid parameter delag = 1: must be false unless a low-pass"):
        gyrocore.process(t, np.zeros_like(t), "hdr", bias=0.0, lowpass_tau=0.0)
    r = gyrocore.process(t, np.zeros_like(t), "hdr", bias=0.0, lowpass_tau=0.0, delag=False)
    assert np.all(r.heading == 0.0)
    # One tau for the samples and HDR's step means, whatever order the parameters come in.
    for overrides in ({"lowpass_tau": 0.4, "hdr": True}, {"hdr": True, "lowpass_tau": 0.4}):
        p = gyrocore.Pipeline("static_bias", bias=0.0, delag=True, **overrides)
        assert p.params["lowpass_tau"] == 0.4 and p.params["hdr"]


def test_the_pipeline_module_re_exports_every_public_name_of_its_presets_and_parameters_part() -> None:
    # gyrocore.pipeline_params is a part of gyrocore.pipeline: its names are the pipeline's, in
    # its __all__ (from which the docs site renders the module)
    from gyrocore import pipeline, pipeline_params

    own = [name for name, value in vars(pipeline_params).items() if not name.startswith("_")
           and not inspect.ismodule(value) and getattr(value, "__module__", pipeline_params.__name__) == pipeline_params.__name__]
    assert {"preset_params", "parameters", "BIAS_SOURCES"} <= set(own) <= set(pipeline.__all__)
    assert all(getattr(pipeline, name) is getattr(pipeline_params, name) for name in own)
    assert all(hasattr(pipeline, name) for name in pipeline.__all__)


def test_every_rate_parameter_takes_a_deg_per_s_spelling() -> None:
    # docs/python.md promises one for each; hdr_max_correction_dps and rest_noise_dps were unknown
    rates = [name for name, what in gyrocore.parameters().items() if "[rad/s]" in what and "window" not in name]
    assert {"bias", "threshold", "hdr_max_correction", "rest_noise"} <= set(rates)
    for name in rates:
        given = gyrocore.pipeline.preset_params("tracked", **{f"{name}_dps": 0.25})
        assert given[name] == pytest.approx(math.radians(0.25)), name


def test_a_resumed_stream_says_where_it_stopped_and_refuses_samples_sent_again() -> None:
    t, rate = _log()
    whole = gyrocore.Pipeline("combined", bias=0.01).process(t, rate)
    stream = gyrocore.Pipeline("combined", bias=0.01)
    assert stream.last_time is None
    first = stream.process(t[:1000], rate[:1000])
    resumed = pickle.loads(pickle.dumps(stream))
    assert resumed.last_time == t[999]
    # A robot that restarts and sends its last chunk again: the words say what to give, not to sort a log.
    with pytest.raises(gyrocore.SampleError, match=r"the last sample this pipeline processed \(Pipeline.last_time.*"
                       r"give only the samples after it \(1000 of this chunk's 1010\)") as caught:
        resumed.process(t[990:2000], rate[990:2000], index_offset=990)
    assert (caught.value.index, caught.value.what) == (990, "t")
    rest = resumed.process(t[t > resumed.last_time], rate[t > resumed.last_time])
    assert np.concatenate([first.heading, rest.heading]).tobytes() == whole.heading.tobytes()
    # A timestamp going back inside a chunk is a log's problem, told as before.
    with pytest.raises(gyrocore.SampleError) as inside:
        gyrocore.Pipeline("raw").process([0.0, 1.0, 0.5], [0.0, 0.0, 0.0])
    assert "last_time" not in str(inside.value)


def test_a_stream_of_one_sample_chunks_has_its_units_judged() -> None:
    """A robot's first chunk of one sample has no interval: timestamps in ms were never judged
    (only the first chunk was), where one call over the same samples warns."""
    t = np.arange(200) * 20.0  # ms
    rate = np.full(len(t), 0.01)
    stream = gyrocore.Pipeline("raw", gap_limit=100.0)  # the 20 "s" intervals are no gap to say
    stream.process(t[:1], rate[:1])
    stream = pickle.loads(pickle.dumps(stream))  # a restart in between keeps the sample held
    with pytest.warns(gyrocore.InputWarning, match="timestamps look like ms"):
        stream.process(t[1:2], rate[1:2])
    with warnings.catch_warnings():
        warnings.simplefilter("error", gyrocore.InputWarning)
        gyrocore.Pipeline("raw").process(np.arange(5) * 0.02, rate[:5])  # seconds: nothing said


@pytest.mark.parametrize("call", ["integrate", "downsample", "allan"])
@pytest.mark.parametrize("wrong", ["ms", "deg/s"])
def test_every_function_of_a_whole_log_warns_of_its_units_as_process_does(call: str, wrong: str) -> None:
    """integrate, downsample and the Allan deviation of timestamps took times in ms or rates in
    deg/s without a word (a heading 1000 times too large, taus 1000 times too long)."""
    t = np.arange(0.0, 200.0, 0.01)
    rate = np.random.default_rng(3).normal(0.0, 0.01, len(t)) + 0.5 * np.sin(t)
    t, rate = (t * 1000.0, rate) if wrong == "ms" else (t, np.degrees(rate) * 10)
    said = "timestamps look like ms" if wrong == "ms" else "rates look like deg/s"
    from gyrocore import allan
    run = {"integrate": lambda: gyrocore.integrate(t, rate), "downsample": lambda: gyrocore.downsample(t, rate, 1.0),
           "allan": lambda: allan.deviation_from_timestamps(t, rate)}[call]
    with pytest.warns(gyrocore.InputWarning, match=said) as caught:
        run()
    units = [w for w in caught if said in str(w.message)]
    assert len(units) == 1 and units[0].filename == __file__  # once, at the caller's line
    with pytest.warns(gyrocore.InputWarning, match=said):
        gyrocore.process(t, rate, "raw", gap_limit=1e6)
