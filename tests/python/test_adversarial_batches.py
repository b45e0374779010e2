"""Inputs found by adversarial testing of runs over many logs (``gyrocore process``,
``gyrocore.batch``): options left unused without a word, a Dask client that cannot run the batch,
and a causal run that took another heading than the one documented for its log."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import gyrocore

from .conftest import gyrocore_cli


def _small_log(path: Path) -> Path:
    t = np.arange(0.0, 30.0, 0.01)
    path.write_text("t,gyro_z\n" + "".join(f"{a:.2f},0.001\n" for a in t))
    return path


@pytest.mark.parametrize(
    ("options", "said"),
    [(("--scheduler", "tcp://10.0.0.5:8786"), "--scheduler tcp://10.0.0.5:8786: --out {out} is one file, processed "
      "here from one input; it runs the files of a batch into an output folder (--out DIR): leave it out"),
     (("--jobs", "3"), "--jobs 3: --out {out} is one file, processed here from one input; it runs the files of a "
      "batch into an output folder (--out DIR): leave it out")],
    ids=["scheduler", "jobs"],
)
def test_batch_options_given_for_one_output_file_are_refused(tmp_path: Path, options: tuple[str, ...], said: str) -> None:
    """``gyrocore process drive.csv --out h.csv --scheduler ADDRESS`` (or ``--jobs 3``) processed the
    file here, on one thread, without a word: the scheduler was never asked, not even whether it
    answers."""
    out = tmp_path / "h.csv"
    proc = gyrocore_cli("process", _small_log(tmp_path / "drive.csv"), "--out", out, *options, code=2, timeout=20)
    assert proc.stderr == f"gyrocore: error: {said.format(out=out)}\n"
    assert not out.exists()


def test_jobs_beside_a_dask_cluster_is_refused(tmp_path: Path) -> None:
    """``process_many(..., client=..., jobs=2)`` and ``--scheduler ADDRESS --jobs 2`` ran on the
    cluster's workers, the number of jobs left unused without a word."""
    from gyrocore import batch

    log = _small_log(tmp_path / "drive.csv")
    with pytest.raises(ValueError, match=r"^jobs=2 is the number of threads here, and client= runs the files on the "
                                         r"Dask cluster's workers \(as many as it has\): give one of them"):
        batch.process_many([log], out_dir=tmp_path / "out", client="tcp://10.0.0.5:8786", jobs=2)
    proc = gyrocore_cli("process", log, "--out", tmp_path / "out", "--scheduler", "tcp://10.0.0.5:8786", "--jobs", "2",
                        code=2, timeout=20)
    assert proc.stderr == ("gyrocore: error: --jobs 2 --scheduler tcp://10.0.0.5:8786: --jobs is the number of files "
                           "processed at once here, and --scheduler runs them on the Dask cluster's workers (as many "
                           "as it has): give one of them\n")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("kind", ["file", "log folder"])
def test_a_causal_batch_tracks_rests_with_the_logs_speed(tmp_path: Path, kind: str) -> None:
    """``gyrocore process drive.csv --causal --preset tracked`` (``process_file``, ``process_many``)
    streamed the gyro alone: the rest tracker found its rests from the rate, where
    ``Log.process("tracked", mode="causal")`` and ``evaluate --causal`` take them where the speed
    (a file's speed column, a log folder's odometry.csv) is zero: another heading, without a
    word."""
    import warnings

    from gyrocore import batch, motion, sim

    drive = sim.simulate(motion.car(300.0, seed=4), sim.sensor("crs03"), seed=4)
    if kind == "file":
        path = tmp_path / "drive.csv"
        rows = zip(drive.t.tolist(), drive.rate_measured.tolist(), drive.speed.tolist())
        path.write_text("t,gyro_z,speed\n" + "".join(f"{a!r},{b!r},{c!r}\n" for a, b, c in rows))
    else:
        path = tmp_path / "drive"
        path.mkdir()
        t, rate, speed = drive.t.tolist(), drive.rate_measured.tolist(), drive.speed.tolist()
        (path / "gyro.csv").write_text("t,gyro_z\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(t, rate)))
        (path / "odometry.csv").write_text("t,speed\n" + "".join(f"{a!r},{c!r}\n" for a, c in zip(t, speed)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)
        log = gyrocore.read_log(path)
        expected = log.process("tracked", mode="causal").heading
        blind = log.process("tracked", mode="causal", use_speed=False).heading
        assert not np.allclose(expected, blind)  # the speed matters on this drive
        batch.process_file(path, tmp_path / "h.csv", preset="tracked", mode="causal")
        batch.process_file(path, tmp_path / "blind.csv", preset="tracked", mode="causal", use_speed=False)
    written = np.loadtxt(tmp_path / "h.csv", delimiter=",", skiprows=1, usecols=1)
    assert np.allclose(written, expected, rtol=0, atol=1e-12)
    assert np.allclose(np.loadtxt(tmp_path / "blind.csv", delimiter=",", skiprows=1, usecols=1), blind, rtol=0, atol=1e-12)


def test_a_dask_client_that_cannot_run_the_batch_leaves_no_output_folder(tmp_path: Path) -> None:
    """``process_many(..., client=...)`` with a closed client failed with Dask's bare
    ``ClosedClientError: Client is closed. Can't send update-graph message``, with ``client=5``
    with ``Scheduler address must be a string or a Cluster instance``, and with an address Dask
    cannot read (``--scheduler nonsense``) after the output folder was made: an empty folder was
    left behind each time."""
    distributed = pytest.importorskip("dask.distributed")
    from gyrocore import batch

    log = _small_log(tmp_path / "drive.csv")
    out = tmp_path / "out"
    with pytest.raises(TypeError, match=r"^client must be a dask.distributed.Client, a Dask cluster or a scheduler's "
                                        r"address \(tcp://host:8786\), got int 5$"):
        batch.process_many([log], out_dir=out, client=5)
    with pytest.raises(ValueError, match=r"^scheduler address 'nonsense': "):
        batch.process_many([log], out_dir=out, client="nonsense")
    # a client closed already (a real one, closed, is this: a cluster started for it here could
    # not start its event loop in time under the whole suite's load)
    closed = distributed.Client.__new__(distributed.Client)
    closed.status = "closed"
    with pytest.raises(ValueError, match=r"^client= is a Dask client that was closed"):
        batch.process_many([log], out_dir=out, client=closed)
    assert not out.exists()
