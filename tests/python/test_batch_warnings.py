"""The warnings ``process_file`` and ``process_many`` raise again for a caller of the API name the
file each came from, as the command line prints them (the files of a batch often say the same
words, which without the name told no file from another), from the caller's line."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore.batch import process_file, process_many


def turning_csv(path: Path) -> Path:
    """A minute of steady turning at 100 Hz: no rest to measure a bias in."""
    t = np.arange(6000) * 0.01
    rate = 0.3 * np.sin(t)
    path.write_text("t,gyro_z\n" + "".join(f"{a:.2f},{b:.6f}\n" for a, b in zip(t, rate)))
    return path


def no_rest_warnings(caught: list[warnings.WarningMessage]) -> list[str]:
    return [str(w.message) for w in caught
            if issubclass(w.category, gyrocore.InputWarning) and "removes a static bias" in str(w.message)]


@pytest.mark.parametrize("jobs", [1, 2])
def test_each_files_warning_names_the_file_in_a_batch(tmp_path: Path, jobs: int) -> None:
    a, b = turning_csv(tmp_path / "a.csv"), turning_csv(tmp_path / "b.csv")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        summary = process_many([a, b], out_dir=tmp_path / "out", jobs=jobs)
    assert len(summary.succeeded) == 2
    said = no_rest_warnings(caught)
    assert sorted(m.split(": ", 1)[0] for m in said) == [str(a), str(b)], said
    # from the line that called, not from the worker thread's (concurrent/futures/thread.py)
    assert {w.filename for w in caught if issubclass(w.category, gyrocore.InputWarning)} == {__file__}
    # the report keeps the words alone: the command line adds the name as it prints them
    assert all(not w.startswith(str(a)) for w in summary.files[0].warnings), summary.files[0].warnings


def test_a_files_warning_names_it_once(tmp_path: Path) -> None:
    a = turning_csv(tmp_path / "a.csv")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        process_file(a, tmp_path / "h.csv")
    said = no_rest_warnings(caught)
    assert len(said) == 1 and said[0].startswith(f"{a}: preset 'recommended' removes a static bias"), said
    assert not said[0].startswith(f"{a}: {a}: ")
