"""A reference (or an estimate) in degrees that never wraps, which the wrap check cannot see, is
warned about by heading_errors and the evaluation: never on the real logs as they are, on each one
that turns with its reference in degrees."""

from __future__ import annotations

import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest

import gyrocore

from .conftest import DATA, gyrocore_cli, real_log_path

LOGS = sorted(p.name for p in (DATA / "real").iterdir()) if (DATA / "real").is_dir() else ["kitti_2011_09_30_0027"]
#: The one log that barely turns (a straight highway: its reference 0.19 deg from where it starts,
#: on average, while its estimate drifts 116 deg): a comparison in either unit says nothing there.
STRAIGHT = {"comma_seg40"}


def degree_warnings(run: object) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run()  # type: ignore[operator]
    return [str(w.message) for w in caught if "looks like degrees" in str(w.message)]


def test_a_reference_in_degrees_that_does_not_wrap_is_warned_about() -> None:
    t = np.arange(0, 60, 0.01)
    h = 0.1 * np.sin(t)
    t_ref, h_ref = t[::10], h[::10] + 0.3
    assert not degree_warnings(lambda: gyrocore.heading_errors(t, h, t_ref, h_ref))
    said = degree_warnings(lambda: gyrocore.heading_errors(t, h, t_ref, np.degrees(h_ref)))  # 204 deg, no word
    assert len(said) == 1 and said[0].startswith("the reference heading looks like degrees: E_psi 204.5 deg as given, ")
    assert said[0].endswith(" deg with the reference in degrees; convert with numpy.radians")
    said = degree_warnings(lambda: gyrocore.heading_errors(t, np.degrees(h), t_ref, h_ref))
    assert len(said) == 1 and said[0].startswith("the estimate heading looks like degrees: E_psi ")


@pytest.mark.parametrize("name", LOGS)
def test_the_real_logs_are_never_said_to_be_in_degrees_and_are_with_their_reference_in_degrees(name: str) -> None:
    log = gyrocore.read_log(real_log_path(name))
    t_ref, h_ref = log.reference()
    for preset in ("static_bias", "hdr", "recommended"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = log.process(preset)
        assert not degree_warnings(lambda: gyrocore.heading_errors(r.t, r.heading, t_ref, h_ref)), preset
        in_degrees = np.degrees(np.unwrap(h_ref))  # continuous: no wrap for the wrap check to see
        said = degree_warnings(lambda: gyrocore.heading_errors(r.t, r.heading, t_ref, in_degrees))
        assert (said[0].startswith("the reference heading looks like degrees") if said else name in STRAIGHT), preset


def test_a_log_folders_reference_in_degrees_is_warned_about_by_read_log_and_evaluate(tmp_path: Path) -> None:
    folder = tmp_path / "drive"
    shutil.copytree(real_log_path("kitti_2011_09_30_0027"), folder)
    reference = folder / "reference.csv"
    reference.chmod(0o644)
    table = np.genfromtxt(reference, delimiter=",", names=True)
    table["heading"] = np.degrees(np.unwrap(table["heading"]))  # continuous degrees
    assert np.abs(np.diff(table["heading"])).max() < 180  # no step the wrap check would see
    np.savetxt(reference, table, delimiter=",", header=",".join(table.dtype.names or ()), comments="", fmt="%.9f")
    log = gyrocore.read_log(folder)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = log.process("recommended")
    said = degree_warnings(lambda: gyrocore.heading_errors(r.t, r.heading, *log.reference()))
    assert said and said[0].startswith("the reference heading looks like degrees")
    proc = gyrocore_cli("evaluate", folder, "--preset", "recommended", code=0)
    assert f"gyrocore: warning: {folder}: the reference heading looks like degrees: E_psi " in proc.stderr, proc.stderr
