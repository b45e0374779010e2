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


def test_the_improvement_column_names_its_baseline_plain_integration(tmp_path: Path) -> None:
    """The column was headed "vs raw", and the raw row given a bias (--bias-dps) read 0.8x "vs raw":
    its baseline is plain integration, no bias removed, which that row no longer is. The header
    names the baseline, a line under the table says why the raw row is not 1.0x, and the factor is
    the one against plain integration."""
    from gyrocore import datasets

    log = datasets.write_sample(tmp_path / "drive")
    table = gyrocore_cli("evaluate", log, "--preset", "raw", "--bias-dps", "0.5", code=0).stdout
    header, _, row, note = table.splitlines()[:4]
    assert header.split()[6] == "vs" and header.split()[7] == "plain" and "vs raw" not in table
    assert note == ("raw: removes the bias given, so it is not plain integration, the baseline of 'vs plain' "
                    "(the readings integrated as they are, no bias removed)")
    read = gyrocore.read_log(log)
    plain = gyrocore.process(read.t, read.rate, "raw")
    given = gyrocore.process(read.t, read.rate, "raw", bias_dps=0.5)
    expected = gyrocore.evaluate.improvement(gyrocore.heading_errors(plain.t, plain.heading, *read.reference()),
                                             gyrocore.heading_errors(given.t, given.heading, *read.reference()))
    assert expected != pytest.approx(1.0, abs=0.05)  # the bias given changes the row
    assert row.split()[6] == f"{expected:.1f}x"
    # without a bias the raw row is plain integration, 1.0x, and nothing is said under the table
    plain_table = gyrocore_cli("evaluate", log, "--preset", "raw", code=0).stdout.splitlines()
    assert plain_table[2].split()[6] == "1.0x" and plain_table[3].startswith("bias source:")
