"""The fix stage's outputs are computed only where asked for (``outputs=`` of Pipeline.process and
gyrocore.process): the ones asked for equal those of a run with every output, bit for bit; and the
table gyrocore evaluate prints with fixes names their units."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore.cli import main
from gyrocore.result import ALL_OUTPUTS, FIX_OUTPUTS

from .conftest import real_log_path
from .test_fixes import BIAS, drive
from .test_fixes_entry import fixes_of

#: Each fix output and where a result holds it.
WHERE = {"heading_sigma": ("heading_sigma",), "fusion_bias": ("fusion", "bias"), "fusion_scale": ("fusion", "scale")}


def column(result: gyrocore.HeadingResult, name: str) -> np.ndarray | None:
    value: object = result
    for attribute in WHERE[name]:
        value = getattr(value, attribute)
    assert value is None or isinstance(value, np.ndarray)
    return value


@pytest.mark.parametrize("outputs", [("heading",), ("heading", "heading_sigma"), ("heading", "rate", "fusion_scale"),
                                     ("heading", "drift", "fusion_bias", "fusion_scale")])
def test_the_pipeline_computes_the_fix_outputs_asked_for(outputs: tuple[str, ...]) -> None:
    t, heading, rate = drive(90.0)
    rate[2500] = np.nan  # skipped: its row repeats the one before, in every column asked for
    fixes = fixes_of(t, heading)
    with pytest.warns(gyrocore.InputWarning, match="1 reading.s. not finite"):
        every = gyrocore.Pipeline("hdr", bias=BIAS, nonfinite="skip").process(t, rate, fixes=fixes)
    with pytest.warns(gyrocore.InputWarning, match="1 reading.s. not finite"):
        some = gyrocore.Pipeline("hdr", bias=BIAS, nonfinite="skip").process(t, rate, fixes=fixes, outputs=outputs)
    assert some.heading.tobytes() == every.heading.tobytes()
    assert some.fusion is not None and every.fusion is not None
    assert some.fusion.heading.tobytes() == every.heading.tobytes()
    assert some.fusion.counts == every.fusion.counts
    for name in ("rate", "drift"):
        asked = getattr(some, name)
        assert (asked is not None) == (name in outputs), name
    for name in FIX_OUTPUTS:
        asked, full = column(some, name), column(every, name)
        assert full is not None
        if name in outputs:
            assert asked is not None and asked.tobytes() == full.tobytes(), name
            assert asked[2500] == asked[2499]
        else:
            assert asked is None, name
    if "heading_sigma" not in outputs:
        with pytest.raises(ValueError, match="'heading_sigma' output was not computed: ask for it in outputs="):
            some.output("heading_sigma")


@pytest.mark.parametrize("mode", ["whole", "causal"])
def test_process_returns_only_the_fix_outputs_asked_for(mode: str) -> None:
    t, heading, rate = drive(120.0)
    fixes = fixes_of(t, heading)
    every = gyrocore.process(t, rate, "hdr", mode=mode, fixes=fixes, bias=BIAS)
    lean = gyrocore.process(t, rate, "hdr", mode=mode, fixes=fixes, bias=BIAS, outputs=("heading", "fusion_bias"))
    assert lean.heading.tobytes() == every.heading.tobytes()
    assert lean.rate is None and lean.drift is None and lean.heading_sigma is None
    assert lean.fusion is not None and every.fusion is not None and every.fusion.bias is not None
    assert lean.fusion.bias is not None and lean.fusion.bias.tobytes() == every.fusion.bias.tobytes()
    assert lean.fusion.scale is None and lean.fusion.heading_sigma is None
    # the default is every output
    assert every.heading_sigma is not None and every.fusion.scale is not None and every.rate is not None


def test_fix_outputs_without_fixes_and_unknown_names() -> None:
    t, _, rate = drive(20.0)
    plain = gyrocore.Pipeline("hdr", bias=BIAS).process(t, rate, outputs=("heading", "heading_sigma"))
    assert plain.heading_sigma is None and plain.fusion is None and plain.rate is None
    with pytest.raises(ValueError, match="comes with heading fixes, and there were none"):
        plain.output("heading_sigma")
    with pytest.raises(ValueError, match="give a tuple of names from " + ", ".join(ALL_OUTPUTS)):
        gyrocore.Pipeline("hdr", bias=BIAS).process(t, rate, outputs=("heading", "sigma"))


def test_the_evaluate_table_with_fixes_has_a_units_row(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # "bias dps" and a bare "scale" (0.0018) read as a scale factor near 1; the table without fixes
    # has a units row
    folder = gyrocore.datasets.write_sample(tmp_path / "drive")
    assert main(["evaluate", str(folder), "--preset", "raw", "--sim-fixes", "rate=1"]) == 0
    lines = capsys.readouterr().out.splitlines()
    k = next(i for i, line in enumerate(lines) if line.startswith("log "))
    assert lines[k].split()[-3:] == ["bias", "scale", "fixes"]
    assert lines[k + 1].split()[:6] == ["[deg]"] * 4 + ["[deg/s]", "[1]"]


def test_fixes_the_gate_rejects_one_after_another_are_warned_about() -> None:
    """comma_seg40 with its own u-blox course: fix headings in degrees (a straight drive never wraps,
    so the degrees check did not see them), times in ms, or rates in deg/s had 97 % of the fixes
    rejected and the heading 90-129 deg off, without a word; right, none is rejected and no word."""
    comma = real_log_path("comma_seg40")
    log = gyrocore.read_log(comma)
    fixes = gyrocore.fixes.read_gnss_csv(comma / "gnss.csv")
    degrees = (fixes.t, np.degrees(fixes.heading), fixes.sigma)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        right = gyrocore.fuse(log.t, log.rate, fixes)
    assert right.counts["rejected"] == 0
    said = r"the outlier gate rejected (\d+) of the 579 heading fixes it reached: .* Check the units"
    cases = {
        "fuse, degrees": lambda: gyrocore.fuse(log.t, log.rate, degrees),
        "fuse, deg/s": lambda: gyrocore.fuse(log.t, np.degrees(log.rate), fixes),
        "whole, degrees": lambda: gyrocore.process(log.t, log.rate, "raw", fixes=degrees),
        "causal, degrees": lambda: gyrocore.process(log.t, log.rate, "raw", mode="causal", fixes=degrees),
    }
    for name, run in cases.items():
        with pytest.warns(gyrocore.InputWarning, match=said) as caught:
            run()
        assert any("rejected 5" in str(w.message) for w in caught), name  # 55x or 56x of 579
    with pytest.warns(gyrocore.InputWarning) as caught:
        gyrocore.fuse(log.t * 1000.0, log.rate, (fixes.t * 1000.0, fixes.heading, fixes.sigma))
    said_all = " ".join(str(w.message) for w in caught)
    assert "timestamps look like ms, us or ns" in said_all
    # the gate's own word: 274 of 579 rejected, so it re-admitted them after its lock-outs
    assert "the gate rejected every heading fix for readmit_after seconds" in said_all
