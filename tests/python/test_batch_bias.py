"""How a batch job hands whole mode's bias to the pipeline: one constant bias as the core's
``bias=`` (the file's readings as they are read), a bias that varies subtracted chunk by chunk."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.csv as pa_csv
import pyarrow.parquet as pq
import pytest

import gyrocore
from gyrocore import wholelog
from gyrocore.batch import process_file

from .test_wholelog import drive, stop_speed, window

COLUMNS = ("heading", "rate", "drift")

# (rests in the drive, its bias [rad/s] as a function of t, overrides, mode, whether the bias is one number)
LOGS = {
    "a given rest window": ([(0.0, 12.0), (50.0, 60.0)], None, "window", "whole", True),
    "the one rest found": ([(40.0, 52.0)], None, {}, "whole", True),
    # its stops shown by the file's speed: two rests the rate alone found, this far apart, disagree
    "two stops, the bias drifting between them": (
        [(10.0, 25.0), (120.0, 135.0)], lambda t: 0.004 + 0.0002 * (t - t[0]), "speed", "whole", False,
    ),
    "causal, its own rest window": ([(0.0, 12.0)], None, "window", "causal", True),
}


@pytest.mark.parametrize("log", LOGS)
def test_batch_gives_what_subtracting_the_planned_bias_from_every_chunk_gave(
    log: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    rests, bias, options, mode, constant = LOGS[log]
    t, rate, _ = drive(150.0, rests, **({} if bias is None else {"bias": bias}))
    overrides = {"bias_window": window(t, 0.0, 12.0)} if options == "window" else {}
    src = tmp_path / "in.csv"
    columns = {"t": t, "gyro_z": rate} | ({"speed": stop_speed(t, rests)} if options == "speed" else {})
    pa_csv.write_csv(pa.table(columns), src)
    read = pa_csv.read_csv(src)
    t_read, r_read = read["t"].to_numpy(), read["gyro_z"].to_numpy()  # what the reader gives
    s_read = read["speed"].to_numpy() if options == "speed" else None

    seen: list[tuple[float, np.ndarray]] = []  # per chunk: the pipeline's bias, the readings it got
    process = gyrocore.Pipeline.process

    def spy(self: gyrocore.Pipeline, t: np.ndarray, rate: np.ndarray, **kwargs: object) -> gyrocore.HeadingResult:
        seen.append((self.bias, rate))
        return process(self, t, rate, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(gyrocore.Pipeline, "process", spy)
    out = tmp_path / "h.parquet"
    report = process_file(src, out, preset="recommended", mode=mode, chunk_rows=700, **overrides)
    monkeypatch.undo()
    assert report.ok, report.error

    # The output as the batch gave it before: the plan's overrides (causal: the user's), and the
    # planned bias (causal: 0) subtracted from every chunk's readings.
    plan = wholelog.plan_stream("recommended", overrides, lambda: [(t_read, r_read)], lambda: (t_read, r_read, s_read))
    planned = plan.bias(t_read) if mode == "whole" else 0.0
    assert isinstance(planned, float) == constant
    pipeline = gyrocore.Pipeline("recommended", **(plan.overrides if mode == "whole" else overrides))
    before = pipeline.process(t_read, r_read - planned, outputs=COLUMNS)
    table = pq.read_table(out)
    for name in COLUMNS:
        assert table[name].to_numpy().tobytes() == before.output(name).tobytes(), name

    given, biases = np.concatenate([r for _, r in seen]), {b for b, _ in seen}
    if constant:  # the readings as read, not a copy less the bias
        assert given.tobytes() == r_read.tobytes()
    if constant and mode == "whole":  # the bias in the core (causal: the core measures its window)
        assert biases == {planned}
    if not constant:  # the smoothed bias taken off each reading, the core's bias 0
        np.testing.assert_array_equal(given, r_read - planned)
        assert biases == {0.0}


def test_a_plan_hands_its_rate_on_without_a_copy_unless_the_bias_varies() -> None:
    t, rate, _ = drive(150.0, [(40.0, 52.0)])
    found = wholelog.plan_arrays("static_bias", {}, t, rate, None, wholelog.Options())
    assert found.corrected(t, rate) is rate and found.pipeline("static_bias").bias == found.bias(t)
    none = wholelog.BiasPlan("none", overrides={"bias": 0.0})
    assert none.corrected(t, rate) is rate and none.pipeline("static_bias").bias == 0.0
    t2, rate2, _ = drive(150.0, [(10.0, 25.0), (120.0, 135.0)], bias=lambda t: 0.004 + 0.0002 * (t - t[0]))
    drifting = wholelog.plan_arrays("static_bias", {}, t2, rate2, None, wholelog.Options())
    np.testing.assert_array_equal(drifting.corrected(t2, rate2), rate2 - drifting.bias(t2))
    assert drifting.pipeline("static_bias").bias == 0.0
