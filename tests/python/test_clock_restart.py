"""A clock that jumps back: refused in words that name ``Pipeline.restart_clock``, after which the
stream goes on on the new clock with everything it had learned, integrating nothing across the jump."""

from __future__ import annotations

import pickle
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import gyrocore
import gyrocore.calibration
from gyrocore.fixes import Fixes

from .conftest import gyrocore_cli

BIAS = 0.01


def drive(t0: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """``n`` samples at 128 Hz from ``t0`` (whole seconds: every time and interval exact), a turn whose
    rate is the bias, so its corrected rate 0, at the first and the last sample."""
    t = t0 + np.arange(n) / 128.0
    rate = BIAS + 0.2 * np.sin(np.pi * np.arange(n) / (n - 1))
    rate[[0, -1]] = BIAS
    return t, rate


def test_a_step_back_names_the_way_on_and_restart_clock_takes_the_samples() -> None:
    p = gyrocore.Pipeline("hdr", bias=BIAS)
    ta, ra = drive(100.0, 400)
    before = p.process(ta, ra)
    tb, rb = drive(3.0, 400)
    with pytest.raises(gyrocore.SampleError, match=r"call restart_clock\(\) and give the samples from t\[0\] on") as e:
        p.process(tb, rb)
    assert e.value.index == 0 and e.value.what == "t"
    assert p.last_time == ta[-1], "a refused chunk changes nothing"
    assert p.restart_clock() == 0
    after = p.process(tb, rb)
    assert after.heading[0] == before.heading[-1], "nothing integrated across the jump"
    assert after.drift is not None and before.drift is not None and after.drift[0] == before.drift[-1]
    assert p.bias == BIAS and p.last_time == tb[-1]
    with pytest.raises(gyrocore.SampleError, match="restart_clock"):  # the new clock must increase too
        p.process(tb[:3], rb[:3])


@pytest.mark.parametrize("gap_action", ["bridge", "reset"])
def test_a_restart_runs_as_a_gap_the_vehicle_stood_still_in(gap_action: str) -> None:
    ta, ra = drive(100.0, 300)
    tb, rb = drive(20.0, 300)
    jumped = gyrocore.Pipeline("static_bias", bias=BIAS, gap_action=gap_action)
    jumped.process(ta, ra)
    jumped.restart_clock()
    gap = gyrocore.Pipeline("static_bias", bias=BIAS, gap_action=gap_action)
    gap.process(ta, ra)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)  # the gap is said
        expected = gap.process(tb + 1000.0, rb)
    got = jumped.process(tb, rb)
    np.testing.assert_array_equal(got.heading, expected.heading)
    assert jumped.report["gaps"] == 0 and gap.report["gaps"] == 1


def test_a_restart_survives_a_pickle_and_chunks() -> None:
    ta, ra = drive(100.0, 300)
    tb, rb = drive(-40.0, 300)
    ra[:140] = BIAS  # standing still through the rest window
    p = gyrocore.Pipeline("combined", bias_window=(100.0, 101.0))
    p.process(ta, ra)
    p.restart_clock()
    resumed = pickle.loads(pickle.dumps(p))
    whole = p.process(tb, rb).heading
    parts = np.concatenate([resumed.process(tb[i : i + 37], rb[i : i + 37]).heading for i in range(0, 300, 37)])
    np.testing.assert_array_equal(parts, whole)
    again = pickle.loads(pickle.dumps(resumed))  # on the new clock, before the old window's end
    assert again.last_time == tb[-1]
    again.finish()


def test_a_restart_in_the_rest_window_is_refused() -> None:
    p = gyrocore.Pipeline("static_bias", bias_window=(0.0, 10.0))
    t, rate = drive(0.0, 200)
    p.process(t, rate)
    state = p.__getstate__()["state"]
    with pytest.raises(ValueError, match=r"restart_clock\(\) while the rest window \[0, 10\] s is measured"):
        p.restart_clock()
    assert p.__getstate__()["state"] == state


def test_waiting_fixes_are_dropped_with_a_warning_and_new_ones_taken() -> None:
    p = gyrocore.Pipeline("hdr", bias=BIAS, fusion={})
    ta, ra = drive(100.0, 400)
    fixes = Fixes(np.array([100.5, 101.0, 110.0]), np.zeros(3), np.full(3, 0.05))
    first = p.process(ta, ra, fixes=fixes)
    assert first.fusion is not None and first.fusion.counts["waiting"] == 1
    with pytest.warns(gyrocore.InputWarning, match=r"dropped 1 heading fix\(es\) that waited"):
        assert p.restart_clock() == 1
    tb, rb = drive(5.0, 400)
    new = Fixes(np.array([5.5, 6.0]), np.zeros(2), np.full(2, 0.05))  # before the old clock's fixes
    after = p.process(tb, rb, fixes=new)
    assert after.fusion is not None
    assert after.heading[0] == first.heading[-1]
    assert after.fusion.counts["waiting"] == 0
    assert after.fusion.counts["applied"] + after.fusion.counts["rejected"] == 4


def test_rests_after_a_restart_carry_the_new_clocks_times() -> None:
    n = 6000
    t = 1000.0 + np.arange(n) / 100.0
    rate = np.full(n, 0.004)
    speed = np.where(np.arange(n) < 3000, 5.0, 0.0)
    speed[-500:] = 5.0  # a stop from 30 s to 55 s, then on again
    p = gyrocore.Pipeline("tracked", bias=0.0)
    p.process(t[:1000], rate[:1000], speed=speed[:1000])
    p.restart_clock()
    shifted = t[1000:] - 990.0  # the clock now reads 20 s at 1020 s of the old one
    found = p.process(shifted, rate[1000:], speed=speed[1000:]).tracked_rests
    assert found
    assert 40.0 <= found[0].start < found[0].end <= 65.0


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_a_whole_log_whose_time_steps_back_is_not_sent_to_restart_a_stream(mode: str) -> None:
    t, rate = drive(0.0, 400)
    t[200:] -= 100.0  # one series given at once: split or mended, there is no stream to go on with
    with pytest.raises(gyrocore.SampleError, match=r"\(the clock steps back 99.9922 s here .* process each part\)$") as e:
        gyrocore.process(t, rate, "static_bias", mode=mode, bias=BIAS)
    assert "restart_clock" not in str(e.value)


def test_a_fusion_stream_restarts_its_clock_and_drops_the_waiting_fixes() -> None:
    f = gyrocore.fixes.Fusion()
    assert f.restart_clock() == 0  # before the first sample: nothing to restart
    ta, ra = drive(100.0, 400)
    first = f.process(ta, ra - BIAS, Fixes(np.array([101.0, 120.0]), np.zeros(2), np.full(2, 0.05)))
    with pytest.raises(gyrocore.SampleError, match=r"call restart_clock\(\)") as info:
        f.process(ta - 90.0, ra - BIAS)
    assert (info.value.index, info.value.what) == (0, "t")
    with pytest.warns(gyrocore.InputWarning, match=r"dropped 1 heading fix\(es\)"):
        assert f.restart_clock() == 1
    after = pickle.loads(pickle.dumps(f)).process(ta - 90.0, ra - BIAS, Fixes(np.array([11.0]), np.zeros(1),
                                                                               np.full(1, 0.05)))
    assert after.heading[0] == first.heading[-1] and after.heading_sigma[0] == first.heading_sigma[-1]
    assert after.counts["waiting"] == 0 and after.counts["applied"] + after.counts["rejected"] == 2


def test_a_fusion_streams_bad_sample_is_a_sample_error_while_fixes_wait() -> None:
    """With fixes waiting between blocks, a bad gyro sample's error came back a plain ValueError,
    without its index and what, where without waiting fixes it is a SampleError."""
    f = gyrocore.fixes.Fusion()
    ta, ra = drive(100.0, 400)
    f.process(ta, ra - BIAS, Fixes(np.array([101.0, 120.0]), np.zeros(2), np.full(2, 0.05)))
    tb, rb = drive(104.0, 100)
    rb[7] = np.nan
    with pytest.raises(gyrocore.SampleError, match=r"rate\[7\] is NaN: .* \(fix numbers count 1 fixes still "
                                                   r"waiting from earlier calls first\)$") as info:
        f.process(tb, rb)
    assert (info.value.index, info.value.what) == (7, "rate")


@pytest.mark.parametrize("mode", ["causal", "smoothed"])
def test_fuse_of_a_whole_log_whose_time_steps_back_is_not_sent_to_restart_a_stream(mode: str) -> None:
    # fuse takes a whole log at once and has no clock to restart; it was told to call restart_clock()
    t, rate = drive(0.0, 400)
    t[200:] -= 100.0
    fixes = Fixes(np.array([0.5]), np.zeros(1), np.full(1, 0.05))
    with pytest.raises(gyrocore.SampleError, match=r"t\[200\] = .*\(the clock steps back 99.9922 s .* each part\)$") as e:
        gyrocore.fuse(t, rate, fixes, mode=mode)  # type: ignore[arg-type]
    assert (e.value.index, e.value.what) == (200, "t") and "restart_clock" not in str(e.value)


def test_a_streams_step_back_carries_the_words_of_a_log_beside_its_own() -> None:
    """The binding gives both: a stream's way on, and a whole series' words (a file's reader, a
    whole log), which the Python layer had cut from the stream's with a pattern of its words."""
    p = gyrocore.Pipeline("hdr", bias=BIAS)
    t, rate = drive(100.0, 400)
    p.process(t, rate)
    with pytest.raises(gyrocore.SampleError) as e:
        p.process(t - 50.0, rate)
    series = "timestamps must strictly increase: t[0] = 50 follows 103.1171875 (sort the log and drop duplicate timestamps)"
    assert getattr(e.value, "log_message") == series
    assert str(e.value).startswith(series + "; where the clock jumped back") and "restart_clock()" in str(e.value)


JOINED = ("(the clock steps back 100.117 s here and runs on from there: a clock set back, or two recordings joined; "
          "sorting would interleave them: split the log at this sample and process each part)")


def joined() -> tuple[np.ndarray, np.ndarray]:
    """Two recordings one after the other, the second's clock from 3 s: 400 samples each."""
    ta, ra = drive(100.0, 400)
    tb, rb = drive(3.0, 400)
    return np.concatenate((ta, tb)), np.concatenate((ra, rb))


def test_a_whole_log_whose_clock_starts_again_is_not_told_to_be_sorted(tmp_path: Path) -> None:
    # it was told "sort the log and drop duplicate timestamps", which interleaves the two recordings
    t, rate = joined()
    with pytest.raises(gyrocore.SampleError) as e:
        gyrocore.process(t, rate, "hdr", bias=BIAS)
    assert str(e.value) == f"timestamps must strictly increase: t[400] = 3 follows 103.1171875 {JOINED}"
    with pytest.raises(ValueError, match=re.escape(f"t[400] = 3.0 follows 103.1171875 {JOINED}")):
        gyrocore.calibration.static_bias(t, rate)
    path = tmp_path / "joined.csv"
    path.write_text("t,gyro_z\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(t.tolist(), rate.tolist())))
    proc = gyrocore_cli("process", path, "--out", tmp_path / "h.csv", code=2)
    assert f"{JOINED} ({path}, line 402)" in proc.stderr and "sort" not in proc.stderr.replace("sorting", "")
    for stream in (gyrocore.Pipeline("hdr", bias=BIAS), gyrocore.fixes.Fusion()):  # in a block: both ways on
        with pytest.raises(gyrocore.SampleError) as e:
            stream.process(t, rate)
        assert JOINED in str(e.value) and "call restart_clock() and give the samples from t[400] on" in str(e.value)
    # the advice mends it: each part processed on its own
    assert all(np.isfinite(gyrocore.process(t[part], rate[part], "hdr", bias=BIAS).heading).all()
               for part in (slice(0, 400), slice(400, None)))


@pytest.mark.parametrize("where", ["swapped", "one bad time"])
def test_rows_out_of_place_keep_the_advice_to_sort(where: str) -> None:
    t, rate = drive(100.0, 800)
    if where == "swapped":
        t[[400, 401]] = t[[401, 400]]
    else:
        t[400] = 50.0
    with pytest.raises(gyrocore.SampleError, match=r"\(sort the log and drop duplicate timestamps\)"):
        gyrocore.process(t, rate, "hdr", bias=BIAS)


def test_a_chunk_sent_again_is_named_as_such_not_as_a_clock_set_back() -> None:
    t, rate = drive(100.0, 800)
    p = gyrocore.Pipeline("hdr", bias=BIAS)
    p.process(t, rate)
    with pytest.raises(gyrocore.SampleError) as e:
        p.process(t[200:], rate[200:])
    assert "steps back" not in str(e.value) and "restart_clock" in str(e.value)
