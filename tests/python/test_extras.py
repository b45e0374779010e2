"""A light install: numpy only, and a missing extra named by what needs it.

Each case runs in a fresh interpreter whose import system refuses the optional packages, as if
they were not installed."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from .conftest import real_log_path

OPTIONAL = ("pyarrow", "tqdm", "scipy", "matplotlib", "rosbags", "dask", "distributed")

_BLOCK = """
import sys

class NotInstalled:
    def find_spec(self, name, path=None, target=None):
        if name.partition(".")[0] in {blocked!r}:
            raise ModuleNotFoundError(f"No module named {{name!r}}", name=name)
        return None

sys.meta_path.insert(0, NotInstalled())
"""


def without(blocked: tuple[str, ...], code: str, *args: str | Path) -> subprocess.CompletedProcess[str]:
    """Run ``code`` in a fresh interpreter where the ``blocked`` packages cannot be imported."""
    script = _BLOCK.format(blocked=set(blocked)) + textwrap.dedent(code)
    proc = subprocess.run(
        [sys.executable, "-c", script, *map(str, args)], capture_output=True, text=True, timeout=300
    )
    assert "Traceback" not in proc.stderr, proc.stderr
    return proc


def cli_without(blocked: tuple[str, ...], *args: str | Path, code: int) -> str:
    """``gyrocore ARGS`` without the ``blocked`` packages; returns stderr after checking the exit code."""
    proc = without(blocked, "from gyrocore.cli import main\nsys.exit(main(sys.argv[1:]))", *args)
    assert proc.returncode == code, proc.stderr
    return proc.stderr


def test_numpy_alone_imports_gyrocore_and_processes_arrays() -> None:
    proc = without(OPTIONAL, """
        import numpy as np, gyrocore
        t = np.arange(0, 60, 0.01)
        result = gyrocore.process(t, np.full_like(t, 0.002), "static_bias", bias_duration=20.0)
        assert abs(result.heading[-1]) < 1e-9
        assert abs(gyrocore.integrate(t, np.ones_like(t))[-1] - t[-1]) < 1e-9
        loaded = sorted(m for m in sys.modules if m.partition(".")[0] in {optional!r})
        print("loaded:", loaded)
    """.format(optional=set(OPTIONAL)))
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "loaded: []"


def test_import_gyrocore_loads_no_optional_package_even_when_installed() -> None:
    # import time: the optional packages (scipy.stats alone took 3 s under load) load only when used
    code = "import gyrocore, sys; print(sorted(m for m in sys.modules if m.partition('.')[0] in %r))" % (set(OPTIONAL),)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0 and proc.stdout.strip() == "[]", proc.stdout + proc.stderr


def test_the_quick_start_demo_needs_only_the_plot_extra(tmp_path: Path) -> None:
    plot = tmp_path / "demo.png"
    stderr = cli_without(tuple(m for m in OPTIONAL if m != "matplotlib"),
                         "demo", "--duration", "120", "--drives", "1", "--plot", plot, code=0)
    assert stderr == "" and plot.read_bytes()[:4] == b"\x89PNG"
    stderr = cli_without(OPTIONAL, "demo", "--duration", "120", "--drives", "1", "--plot", tmp_path / "no.png", code=0)
    assert not (tmp_path / "no.png").exists()
    assert "(no plot: the demo's plot needs matplotlib: pip install 'gyrocore[plot]')" in stderr


@pytest.fixture()
def npz(tmp_path: Path) -> Path:
    t = np.arange(0, 60, 0.01)
    np.savez(tmp_path / "rest.npz", t=t, gyro_z=np.random.default_rng(0).normal(0.002, 0.01, len(t)))
    return tmp_path / "rest.npz"


def test_each_command_names_the_extra_it_misses(tmp_path: Path, npz: Path) -> None:
    bag = tmp_path / "drive.bag"
    bag.write_bytes(b"")
    cases = [
        (("pyarrow",), ("process", real_log_path("f110_ds3"), "--out", tmp_path / "o.csv"),
         "f110_ds3/gyro.csv: reading CSV files needs pyarrow: pip install 'gyrocore[io]'"),
        (("pyarrow",), ("process", npz, "--out", tmp_path / "o.parquet", "--preset", "raw"),
         "o.parquet: writing Parquet files needs pyarrow: pip install 'gyrocore[io]'"),
        (("scipy",), ("allan", npz), "the Allan deviation needs scipy: pip install 'gyrocore[fit]'"),
        (("scipy",), ("tune", "--sim-drive", "mixed:1", "--max-evals", "5", "--no-harm"),
         "tuning needs scipy: pip install 'gyrocore[fit]'"),
        (("matplotlib",), ("allan", npz, "--plot", tmp_path / "a.png"),
         "--plot needs matplotlib: pip install 'gyrocore[plot]'"),
        (("rosbags",), ("process", bag, "--out", tmp_path / "b.csv"),
         "drive.bag: reading ROS bags needs rosbags: pip install 'gyrocore[ros]'"),
        (("dask", "distributed"), ("process", npz, "--out", tmp_path / "out", "--scheduler", "tcp://127.0.0.1:1"),
         "running on a Dask cluster needs dask: pip install 'gyrocore[dask]'"),
    ]
    for blocked, args, message in cases:
        stderr = cli_without(blocked, *args, code=2)
        assert message in stderr and stderr.startswith("gyrocore: error: "), (args, stderr)
    assert not (tmp_path / "o.parquet").exists() and not (tmp_path / "a.png").exists()


def test_csv_output_and_npz_input_need_no_extra(tmp_path: Path, npz: Path) -> None:
    out = tmp_path / "heading.csv"
    cli_without(OPTIONAL, "process", npz, "--out", out, "--preset", "raw", code=0)
    assert len(out.read_text().splitlines()) == 6001


def test_functions_name_the_extra_they_miss() -> None:
    proc = without(("scipy", "matplotlib"), """
        import numpy as np
        from gyrocore import allan, deadband
        from gyrocore._extras import MissingExtra
        for call in (lambda: deadband.bias_leak(1.0, 1.0), lambda: allan.deviation(np.zeros(100), 0.01)):
            try:
                call()
            except MissingExtra as e:
                print(e)
    """)
    assert proc.stdout.splitlines() == [
        "the dead band's bias leak needs scipy: pip install 'gyrocore[fit]'",
        "the Allan deviation needs scipy: pip install 'gyrocore[fit]'",
    ]


def test_the_guide_pages_name_the_extras_their_commands_need(tmp_path: Path) -> None:
    # docs/calibration.md, evaluation.md and simulation.md ran `gyrocore allan`, `--plot`,
    # `--plot-dir`, `tune` and `reproduce` without saying they need scipy or matplotlib
    stderr = cli_without(("scipy", "matplotlib"), "reproduce", "hong-calibration", "--out", tmp_path, code=0)
    assert "(no plot: drawing the figures needs matplotlib: pip install 'gyrocore[plot]')" in stderr, stderr
    stderr = cli_without(("scipy",), "reproduce", "hong-allan", "--no-figures", code=2)
    assert "the Allan deviation needs scipy: pip install 'gyrocore[fit]'" in stderr, stderr
    docs = Path(__file__).resolve().parents[2] / "docs"
    text = {page: " ".join((docs / f"{page}.md").read_text(encoding="utf-8").split())
            for page in ("calibration", "evaluation", "simulation")}
    assert ("The Allan deviation (`gyrocore allan`, `allan.deviation`) needs scipy, `pip install 'gyrocore[fit]'`, "
            "and `--plot` (`allan.plot`) matplotlib, `gyrocore[plot]`") in text["calibration"]
    assert "`--plot-dir` draws with matplotlib (`pip install 'gyrocore[plot]'`" in text["evaluation"]
    assert "scipy's differential evolution (`pip install 'gyrocore[fit]'`)" in text["evaluation"]
    assert ("`hong-allan` and `hong-table-1-sensitivity` need scipy (`pip install 'gyrocore[fit]'`), and the figures "
            "matplotlib (`gyrocore[plot]`)") in text["simulation"]
