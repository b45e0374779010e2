"""Each method's baseline, plain integration, is scored on the samples the method took: with heading
fixes too, where ``--param nonfinite=hold`` let every method through a NaN reading that the
baseline refused, so the log could not be scored at all."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import gyrocore

from .conftest import gyrocore_cli


@pytest.mark.parametrize("policy", ["hold", "skip"])
def test_the_baseline_with_fixes_takes_a_nan_reading_as_the_methods_do(tmp_path: Path, policy: str) -> None:
    from gyrocore import datasets

    log = datasets.write_sample(tmp_path / "drive")
    lines = (log / "gyro.csv").read_text().splitlines()
    lines[499] = lines[499].split(",")[0] + ",nan"
    (log / "gyro.csv").write_text("\n".join(lines) + "\n")
    args = ("evaluate", log, "--preset", "static_bias", "--sim-fixes", "rate=1,outage=100:60", "--json")
    error = gyrocore_cli(*args, code=2).stderr
    assert "rate[498] is NaN: samples must be finite" in error
    row = json.loads(gyrocore_cli(*args, "--param", f"nonfinite={policy}", code=0).stdout)[0]
    read = gyrocore.read_log(log)
    with pytest.warns(gyrocore.InputWarning):
        raw = gyrocore.process(read.t, read.rate, "raw", nonfinite=policy)
    expected = gyrocore.heading_errors(raw.t, raw.heading, *read.reference())
    assert row["raw_e_psi_deg"] == pytest.approx(expected.e_psi_deg, rel=1e-12)
    # and as without fixes, where the baseline took the policy already
    plain = json.loads(gyrocore_cli("evaluate", log, "--preset", "raw", "--param", f"nonfinite={policy}", "--json",
                                    code=0).stdout)[0]
    assert plain["e_psi_deg"] == pytest.approx(row["raw_e_psi_deg"], rel=1e-12)
