"""Long logs and large fleets: work and memory that grow with the log, not faster.

Each test counts memory (tracemalloc peaks) or compares the cost of two stretches of one run, with
margins far from what a defect gives, so that a busy machine does not fail them."""

from __future__ import annotations

import itertools
import pickle
import time
import tracemalloc
import warnings
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore._motion import WATCHED, WindowWatch
from gyrocore.io import OUTPUT_COLUMNS, HeadingWriter
from gyrocore.io.writer import PARQUET_ROW_GROUP


def _stream_per_sample(p: gyrocore.Pipeline, t: np.ndarray, rate: np.ndarray) -> float:
    """Seconds to stream ``(t, rate)`` into ``p`` one sample a call, as a robot's loop does."""
    start = time.perf_counter()
    for i in range(len(t)):
        p.process(t[i:i + 1], rate[i:i + 1], outputs=("heading",))
    return time.perf_counter() - start


def test_a_long_rest_window_streamed_a_sample_a_call_costs_what_the_drive_after_it_costs() -> None:
    # A rest window of 12 s at 1 kHz, one sample a call: each call counted every chunk kept before
    # it (0.41 ms a call on average over a 20 s window, 1.07 ms over an 80 s one, 86 s, against
    # 25 us after it) and kept an array per sample (280 bytes a reading).
    hz, window, calls = 1000.0, 12.0, 3000
    inside = int(window * hz)
    n = inside + calls
    t = np.arange(n) / hz
    rate = 0.003 + np.random.default_rng(1).normal(0.0, 0.002, n)
    p = gyrocore.Pipeline("recommended", bias_duration=window)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)
        _stream_per_sample(p, t[:10], rate[:10])  # the unit check's first chunks
        tracemalloc.start()
        try:
            _stream_per_sample(p, t[10:inside - calls], rate[10:inside - calls])
            peak = tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()
        late = _stream_per_sample(p, t[inside - calls:inside], rate[inside - calls:inside])
        after = _stream_per_sample(p, t[inside:], rate[inside:])
    assert p.bias is not None
    # the window's last 3000 calls against the 3000 after it: 5 to 10 times as long with the count
    assert late < 3.0 * after, (late, after)
    # the window's readings, 8 bytes each, in a buffer that doubles, and a chunk's passing arrays
    assert peak < 64 * inside, peak / inside


def test_a_window_watch_keeps_its_readings_in_order_up_to_its_limit_and_through_a_pickle() -> None:
    watch = WindowWatch()
    t = np.arange(10.0)
    for i in range(10):
        watch.add((2.0, 6.0), t[i:i + 1], t[i:i + 1] * 0.1)
    assert watch.readings is not None
    kept = np.concatenate(watch.readings)
    assert np.array_equal(kept, t[2:7] * 0.1)
    again = pickle.loads(pickle.dumps(WindowWatch.restored(watch.readings)))
    assert again.readings is not None and np.array_equal(np.concatenate(again.readings), kept)
    # a pickle of the list of chunks an earlier version kept reads back as one
    old = WindowWatch.restored([np.array([1.0]), np.array([]), np.array([2.0, 3.0])])
    assert old.readings is not None and np.array_equal(np.concatenate(old.readings), [1.0, 2.0, 3.0])
    big = WindowWatch()
    big.add((0.0, np.inf), np.arange(WATCHED + 10.0), np.full(WATCHED + 10, 0.01))
    big.add((0.0, np.inf), np.arange(5.0), np.full(5, 0.01))
    assert big.readings is not None and len(np.concatenate(big.readings)) == WATCHED
    big.close((0.0, 1.0), 0.01)
    assert big.readings is None


def test_a_parquet_table_written_a_row_a_call_costs_as_much_late_as_early(tmp_path: Path) -> None:
    # One-row results (a robot's loop) into a Parquet table: the rows waiting for their row group
    # were counted again on each call, 28.5 s for 40,000 rows (0.15 s as CSV), and kept 3.4 kB a row.
    pq = pytest.importorskip("pyarrow.parquet")
    n, timed = 40_000, 5_000
    t = np.arange(n) * 0.01
    rate = 0.003 + np.random.default_rng(3).normal(0.0, 0.002, n)
    p = gyrocore.Pipeline("static_bias", bias=0.003)
    rows = [p.process(t[i:i + 1], rate[i:i + 1]) for i in range(n)]
    out = tmp_path / "heading.parquet"
    with HeadingWriter(out) as writer:
        start = time.perf_counter()
        for r in rows[:timed]:
            writer.write(r)
        early = time.perf_counter() - start
        for r in rows[timed:n - timed]:
            writer.write(r)
        start = time.perf_counter()
        for r in rows[n - timed:]:
            writer.write(r)
        late = time.perf_counter() - start
    # the last 5000 rows against the first: 15 times as long when every call counts the rows before
    assert late < 4.0 * early, (late, early)
    whole = gyrocore.process(t, rate, "static_bias", bias=0.003, mode="causal")
    table = pq.read_table(out)
    for name in OUTPUT_COLUMNS:
        assert np.array_equal(table[name].to_numpy(), getattr(whole, name), equal_nan=True), name


def test_a_parquet_table_is_written_in_row_groups_of_its_stated_size_whatever_the_chunks(tmp_path: Path) -> None:
    pq = pytest.importorskip("pyarrow.parquet")
    n = 2 * PARQUET_ROW_GROUP + 1000
    t = np.arange(n) * 0.01
    rate = 0.003 + np.random.default_rng(4).normal(0.0, 0.002, n)
    whole = gyrocore.process(t, rate, "static_bias", bias=0.003, mode="causal")
    for cuts in ([0, n], [0, 1000, PARQUET_ROW_GROUP + 7, n], [0, 5, 10, 3 * PARQUET_ROW_GROUP // 2, n]):
        out = tmp_path / f"h{len(cuts)}.parquet"
        with HeadingWriter(out) as writer:
            for a, b in zip(cuts[:-1], cuts[1:]):
                writer.write(_part(whole, a, b))
        meta = pq.ParquetFile(out).metadata
        assert [meta.row_group(i).num_rows for i in range(meta.num_row_groups)] == [
            PARQUET_ROW_GROUP, PARQUET_ROW_GROUP, 1000]
        table = pq.read_table(out)
        for name in OUTPUT_COLUMNS:
            assert np.array_equal(table[name].to_numpy(), getattr(whole, name)), (cuts, name)


def _part(result: gyrocore.HeadingResult, a: int, b: int) -> gyrocore.HeadingResult:
    """The rows ``a:b`` of ``result``, as a chunk of them."""
    return gyrocore.HeadingResult(result.t[a:b], result.heading[a:b], result.rate[a:b], result.drift[a:b])


def _gapped(n: int, every: int) -> tuple[np.ndarray, np.ndarray]:
    """``n`` times at 100 Hz with a 2 s gap after every ``every`` samples, and a heading turning
    past several turns (wrapped), as a reference logged with dropouts gives them."""
    t = np.arange(n) * 0.01 + np.repeat(np.arange(n // every + 1) * 2.0, every)[:n]
    return t, np.angle(np.exp(1j * 0.05 * t))


def _scoring_time(t: np.ndarray, heading: np.ndarray) -> float:
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)
        gyrocore.heading_errors(t, np.unwrap(heading), t[::5], heading[::5])
    return time.perf_counter() - start


def test_a_reference_with_thousands_of_gaps_is_scored_in_about_the_time_of_one_with_a_few() -> None:
    # Each of the reference's stretches between gaps was unwrapped by a pass over the whole
    # reference, and each gap's turn count added to everything after it: with a gap every
    # second, 10^6 samples took 1.3 s, 2*10^6 5.6 s and 4*10^6 21.8 s.
    n = 800_000
    few = _scoring_time(*_gapped(n, n // 4))
    many = _scoring_time(*_gapped(n, 100))  # 8000 gaps, in the estimate and in the reference
    assert many < 3.0 * few + 0.05, (many, few)


def test_a_gapped_reference_is_unwrapped_and_its_turns_counted_within_each_stretch() -> None:
    t, wrapped = _gapped(3000, 700)
    heading = 0.05 * t
    reference = gyrocore.evaluate.Reference(t, wrapped)
    starts = np.flatnonzero(np.diff(t) > 1.0) + 1
    for a, b in zip(np.r_[0, starts], np.r_[starts, len(t)]):
        assert np.allclose(reference.heading[a:b], np.unwrap(wrapped[a:b]), rtol=0.0, atol=1e-12)
    # the estimate turns as the reference does, across each gap too: no error at all
    tr, error, gap_after = reference.compared(t, heading)
    assert len(tr) == len(t) and gap_after.sum() == len(starts)
    assert np.max(np.abs(error)) < 1e-9
    # an estimate a turn behind after the second gap keeps its error of 0 there (the turn count
    # across a gap follows the estimate), and a 0.1 rad step after the third shows from there on
    late = heading - 2 * np.pi * (t >= t[starts[1]]) + 0.1 * (t >= t[starts[2]])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)  # its turn back across the gap looks wrapped
        _, error, _ = reference.compared(t, late)
    assert np.max(np.abs(error[: starts[2]])) < 1e-9
    assert np.allclose(error[starts[2]:], 0.1, atol=1e-9)


def test_a_gapped_reference_unwraps_each_stretch_as_numpy_unwrap_does_even_at_half_a_turn() -> None:
    rng = np.random.default_rng(5)
    t = np.cumsum(np.where(rng.random(5000) < 0.02, 5.0, 0.01))
    wrapped = np.angle(np.exp(1j * np.cumsum(rng.normal(0.0, 1.5, 5000))))
    wrapped[100:104] = [np.pi, 0.0, -np.pi, 0.0]  # steps of exactly half a turn, either way
    reference = gyrocore.evaluate.Reference(t, wrapped)
    starts = np.flatnonzero(np.diff(t) > 1.0) + 1
    assert len(starts) > 50
    for a, b in zip(np.r_[0, starts], np.r_[starts, len(t)]):
        assert np.allclose(reference.heading[a:b], np.unwrap(wrapped[a:b]), rtol=0.0, atol=1e-9)


def test_a_long_log_into_the_callers_array_copies_only_its_times() -> None:
    # The first chunk's unit check copied its times and readings whole (two more arrays as long as
    # the log, 2.1 s of a 5*10^7-sample call whose pipeline took 1.1 s) to judge a subset of them.
    n = 2_000_000
    t = np.arange(n) * 1e-3
    rate = 0.003 + np.random.default_rng(6).normal(0.0, 0.002, n)
    heading = np.empty(n)
    for call in (lambda: gyrocore.process(t, rate, "combined", bias=0.003, mode="causal", outputs=("heading",),
                                          out=heading),
                 lambda: gyrocore.Pipeline("combined", bias=0.003).process(t, rate, outputs=("heading",), out=heading)):
        tracemalloc.start()
        try:
            result = call()
            peak = tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()
        assert result.heading is heading
        # the result's own times (8 bytes a sample) and what a chunk's checks take of a subset
        assert peak < 1.5 * 8 * n, peak / (8 * n)


def test_a_stream_that_fills_one_buffer_anew_for_each_sample_is_judged_on_the_samples_it_gave() -> None:
    def said(chunks: list[tuple[float, float]]) -> list[str]:
        p = gyrocore.Pipeline("raw")
        t_buffer, rate_buffer = np.empty(1), np.empty(1)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", gyrocore.InputWarning)
            for t, rate in chunks:
                t_buffer[0], rate_buffer[0] = t, rate
                p.process(t_buffer, rate_buffer)
        return [str(w.message) for w in caught]

    one_call = gyrocore.Pipeline("raw")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", gyrocore.InputWarning)
        one_call.process([0.0, 0.01], [30.0, 0.001])
    assert [str(w.message) for w in caught] == said([(0.0, 30.0), (0.01, 0.001)])
    assert any("deg/s" in m for m in said([(0.0, 30.0), (0.01, 0.001)]))


def _compare_peak(log: gyrocore.Log, presets: list[str]) -> int:
    tracemalloc.start()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", gyrocore.InputWarning)
            rows = gyrocore.evaluate.compare([log], presets, mode="causal")
        assert len(rows) == len(presets)
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_comparing_many_methods_on_a_long_log_keeps_one_methods_heading_at_a_time() -> None:
    # Every method's result (times, heading, rate, drift) was kept to the end of the log, for a
    # plot that was not asked for: the 7 presets of gyrocore evaluate held 28 arrays as long as the
    # log beside it (224 bytes a sample).
    n = 200_000
    t = np.arange(n) * 0.01
    truth = 0.2 * np.sin(t / 7.0)
    rate = truth + 0.003 + np.random.default_rng(7).normal(0.0, 0.002, n)
    log = gyrocore.Log("long", t, rate, t_ref=t[::10], heading_ref=np.cumsum(truth)[::10] * 0.01)
    one = _compare_peak(log, ["hdr"])
    six = _compare_peak(log, ["hdr", "raw", "static_bias", "hong_park", "combined", "tuned"])
    assert six - one < 4 * 8 * n, (six - one) / (8 * n)


def _evaluate_peak(files: list[Path], capsys: pytest.CaptureFixture[str]) -> int:
    from gyrocore.cli import main

    tracemalloc.start()
    try:
        assert main(["evaluate", *map(str, files), "--preset", "static_bias"]) == 0
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
        assert f"{files[-1]}" in capsys.readouterr().out


def test_gyrocore_evaluate_of_a_fleet_holds_one_log_at_a_time(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # Every log was read before the first was scored: a fleet's logs all in memory at once.
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    n = 100_000
    t = np.arange(n) * 0.01
    truth = 0.2 * np.sin(t / 7.0)
    files = []
    for k in range(8):
        rate = truth + 0.003 + np.random.default_rng(k).normal(0.0, 0.002, n)
        files.append(tmp_path / f"drive{k}.parquet")
        pq.write_table(pa.table({"t": t, "gyro_z": rate, "heading_true": np.cumsum(truth) * 0.01}), files[-1])
    two, eight = _evaluate_peak(files[:2], capsys), _evaluate_peak(files, capsys)
    # a log read is 3 arrays as long as it (times, readings, reference heading): 6 more logs held
    # 18 of them
    assert eight < two + 6 * 8 * n, (eight - two) / (8 * n)


def test_a_long_result_written_as_csv_in_one_call_is_formatted_a_block_at_a_time(tmp_path: Path) -> None:
    # A result written whole (a log with heading fixes, read and processed in one piece) was
    # copied column by column and formatted into one text as long as the file: 1.1 GB resident
    # for a 4*10^6-sample log folder's CSV output, 847 MB for its Parquet output.
    n = 1_000_000
    t = np.arange(n) * 0.01
    rate = 0.003 + np.random.default_rng(8).normal(0.0, 0.002, n)
    whole = gyrocore.process(t, rate, "static_bias", bias=0.003, mode="causal")
    out = tmp_path / "heading.csv"
    with HeadingWriter(out) as writer:
        tracemalloc.start()
        try:
            writer.write(whole)
            peak = tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()
    assert peak < 16 * 2**20, peak / n
    back = np.loadtxt(out, delimiter=",", skiprows=1)
    assert back.shape == (n, 4)
    for k, name in enumerate(OUTPUT_COLUMNS):
        assert np.array_equal(back[:, k], getattr(whole, name)), name


@pytest.mark.parametrize("seed", [0, 1, 4])
def test_raw_integration_drifting_over_hours_is_not_said_to_be_in_degrees(seed: int) -> None:
    # 2.8 hours of a simulated car: raw integration drifts 7000 deg, its drift divided by 57 came
    # near the reference, and "the estimate heading looks like degrees" was said of a heading in rad.
    drive = gyrocore.sim.car_drive(duration=10_000.0, rate_hz=10.0, seed=seed)

    def said(heading: np.ndarray) -> list[str]:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", gyrocore.InputWarning)
            gyrocore.heading_errors(drive.t, heading, drive.t, drive.heading_true)
        return [str(w.message) for w in caught if "looks like degrees" in str(w.message)]

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)
        raw = gyrocore.process(drive.t, drive.rate_measured, "raw").heading
        corrected = gyrocore.process(drive.t, drive.rate_measured, "static_bias").heading
    assert said(raw) == []
    assert said(corrected) == []
    # one in degrees still is (the true heading in degrees)
    in_degrees = said(np.degrees(drive.heading_true))
    assert len(in_degrees) == 1 and in_degrees[0].startswith("the estimate heading looks like degrees: E_psi ")


def _chunk_time(path: Path, rows: int, count: int) -> float:
    chunks = gyrocore.io.open_source(path).chunks(rows)
    start = time.perf_counter()
    got = sum(len(c) for c in itertools.islice(chunks, count))
    assert got == rows * count
    return time.perf_counter() - start


def test_a_parquet_file_read_a_sample_a_chunk_costs_about_what_a_csv_file_does(tmp_path: Path) -> None:
    # pyarrow was asked for batches of the chunk's size: one row a batch took 75 us (1 to 3 us from
    # a CSV file, whose blocks are sliced), so `--chunk-rows 10` of 10^6 rows took 19.4 s against 5.3.
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    pc = pytest.importorskip("pyarrow.csv")
    n = 50_000
    table = pa.table({"t": np.arange(n) * 0.01, "gyro_z": np.random.default_rng(9).normal(0.0, 0.002, n)})
    pq.write_table(table, tmp_path / "drive.parquet")
    pc.write_csv(table, tmp_path / "drive.csv")
    csv, parquet = _chunk_time(tmp_path / "drive.csv", 1, 20_000), _chunk_time(tmp_path / "drive.parquet", 1, 20_000)
    assert parquet < 5.0 * csv + 0.1, (parquet, csv)
    # the same samples, whatever the chunks
    whole = next(gyrocore.io.open_source(tmp_path / "drive.parquet").chunks(n))
    small = list(gyrocore.io.open_source(tmp_path / "drive.parquet").chunks(7))
    assert np.array_equal(np.concatenate([c.t for c in small]), whole.t)
    assert np.array_equal(np.concatenate([c.rate for c in small]), whole.rate)
    assert [c.first_row for c in small[:3]] == [0, 7, 14]


def test_a_files_unit_check_holds_a_bounded_subset_however_small_the_chunks() -> None:
    # A chunk of one row between the samples of the subset's stride was kept as an empty array:
    # the list grew with the stream (360,000 arrays and 45 MB after 10^6 one-row chunks).
    from gyrocore._checks import SUBSET_SIZE
    from gyrocore.io.units import UnitCheck

    check = UnitCheck(gyrocore.io.ReadOptions(rate_unit="rad/s"))
    n = 200_000
    t, rate = np.arange(n) * 0.001, np.random.default_rng(10).normal(0.0, 0.001, n)
    longest = 0
    for i in range(n):
        check.update(t[i:i + 1], rate[i:i + 1])
        longest = max(longest, len(check._subset))
    assert longest <= 2 * SUBSET_SIZE + 1, longest
    assert check.problems() == []


def test_a_long_logs_plot_draws_what_its_pixels_show(tmp_path: Path) -> None:
    # Every sample of every method was drawn, twice (heading and error) on a plot 1000 pixels
    # wide: `gyrocore evaluate --plot-dir` of 4*10^6 samples and 7 presets took 21.5 s and 2.9 GB
    # resident, against 5.5 s and 838 MB without the plot.
    pytest.importorskip("matplotlib")
    from gyrocore.evaluate_compare import plot_log

    n = 1_000_000
    t = np.arange(n) * 0.01
    truth = 0.2 * np.sin(t / 7.0)
    rate = truth + 0.003 + np.random.default_rng(11).normal(0.0, 0.002, n)
    log = gyrocore.Log("long", t, rate, t_ref=t[::10], heading_ref=np.cumsum(truth)[::10] * 0.01)
    results = {p: gyrocore.process(t, rate, p, bias=0.003, mode="causal") for p in ("static_bias", "hdr")}
    tracemalloc.start()
    try:
        start = time.perf_counter()
        plot_log(tmp_path / "long.png", log, results)
        seconds = time.perf_counter() - start
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert (tmp_path / "long.png").stat().st_size > 10_000
    # what scoring a heading takes (its checks pass over the times) and a few thousand points a
    # line, where every line held its samples: 16.6 arrays as long as the log
    assert peak < 8 * 8 * n, peak / (8 * n)
    assert seconds < 20.0
