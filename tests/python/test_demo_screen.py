"""What `gyrocore demo` shows a newcomer: why the recommended preset sits where it does in the table,
said on screen, and a plot titled with the drive and the gyro."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from gyrocore import recommended_preset, sim
from gyrocore.cli import main

ROW = re.compile(r"^(\w+) +(\d+\.\d+) ")


def test_the_demo_says_why_the_recommended_preset_is_where_it_is(tmp_path: Path) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "gyrocore.cli", "demo", "--duration", "300", "--drives", "3", "--plot", ""],
        cwd=tmp_path, capture_output=True, text=True, timeout=300,
    )
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
    lines = done.stdout.splitlines()
    rows = {m.group(1): float(m.group(2)) for line in lines if (m := ROW.match(line))}
    assert {"raw", "static_bias", "hdr", "combined", recommended_preset()} <= set(rows)
    recommended = recommended_preset()
    assert f"recommended = {recommended}" in done.stdout
    lowest = min(rows, key=rows.__getitem__)
    why = lines[lines.index(next(line for line in lines if line.startswith("(means over the drives)"))) + 1]
    if lowest == recommended:
        assert why == f"{recommended} has the lowest E_psi here"
    else:
        # the line names the preset that is lower, and the reason, on screen
        assert why.startswith(f"{recommended} is not the lowest E_psi here ({lowest} is): it was chosen to do no harm")
        assert "docs/results.md" in why


def test_the_demo_plot_is_titled_with_the_drive_and_the_gyro(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    figure = pytest.importorskip("matplotlib.figure")
    titles: list[str] = []
    savefig = figure.Figure.savefig

    def recording(self: Any, *args: Any, **kwargs: Any) -> None:
        titles.extend(ax.get_title() for ax in self.axes)
        savefig(self, *args, **kwargs)

    monkeypatch.setattr(figure.Figure, "savefig", recording)
    plot = tmp_path / "demo.png"
    assert main(["demo", "--duration", "120", "--drives", "1", "--seed", "4", "--mix", "suburbs",
                 "--sensor", "crs03", "--plot", str(plot)]) == 0
    gyro = sim.SENSORS["crs03"].name
    assert f"roads, {gyro} at 100 Hz" in capsys.readouterr().out  # the drive the table is about
    assert plot.read_bytes()[:4] == b"\x89PNG"
    assert titles[0] == f"simulated car drive: 120 s of 'suburbs' roads (seed 4); gyro {gyro} at 100 Hz"
