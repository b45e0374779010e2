"""A sample log to try every command on, made on the spot: nothing is downloaded.

The sample is **simulated** (:func:`gyrocore.sim.car_drive`, always the same seed, so always the
same samples): a 60 s rest, then four minutes of downtown streets, read by the HDR paper's CRS03-04
gyro at 100 Hz, with the true heading and track as its reference. Being simulated, its truth is
known exactly; it is not a recording and says nothing of how a method does on real logs.

:func:`sample_drive` returns it as a :class:`gyrocore.io.Log` (numpy only);
:func:`write_sample` writes it as a log folder (``gyro.csv``, ``reference.csv``, ``odometry.csv``,
``meta.json``) that ``gyrocore process``, ``evaluate``, ``calibrate`` and ``allan`` read; from a
shell, ``python -m gyrocore.datasets FOLDER`` does the same.

    >>> from gyrocore import datasets
    >>> log = datasets.sample_drive()
    >>> log.stationary, len(log.t), log.meta["simulated"]
    ((0.0, 60.0), 30000, True)
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from . import __version__, sim
from ._arrays import FloatArray
from ._checks import did_you_mean, public_dir, require_flag
from .io.atomic import make_folder, write_text_atomically
from .io.log import Log

__all__ = ["FILES", "REFERENCE_EVERY", "SAMPLE", "main", "sample_drive", "write_sample"]
__dir__ = public_dir(__name__)  # dir() and tab completion: __all__

#: What :func:`sample_drive` simulates: ``gyrocore.sim.car_drive(**SAMPLE)``. Downtown streets, the
#: first seed: a drive with many corners (it turns through 11 rad), so that the scale fit and the
#: heading methods have something to show.
SAMPLE: dict[str, Any] = {
    "duration": 300.0, "rate_hz": 100.0, "seed": 0, "rest": 60.0, "mix": "downtown", "sensor_name": "crs03",
}
#: The reference and the odometry hold every this many gyro samples (10 Hz, as a real reference
#: runs slower than its gyro).
REFERENCE_EVERY = 10
#: The files :func:`write_sample` writes, in the log-folder layout of :mod:`gyrocore.io`.
FILES = ("gyro.csv", "reference.csv", "odometry.csv", "meta.json")


def sample_drive() -> Log:
    """The simulated sample log (the same every call), with its reference, odometry and rest window.

    Needs numpy only: nothing is read from disk.
    """
    gyro, reference, odometry, meta = _sample()
    return Log(
        name=meta["name"],
        t=gyro["t"],
        rate=gyro["gyro_z"],
        t_ref=reference["t"],
        heading_ref=reference["heading"],
        x_ref=reference["x"],
        y_ref=reference["y"],
        t_odometry=odometry["t"],
        speed=odometry["speed"],
        stationary=(meta["stationary"][0], meta["stationary"][1]),
        meta=meta,
    )


def write_sample(folder: str | Path = "sample_drive", *, overwrite: bool = False) -> Path:
    """Write the sample log as a log folder (created if missing) and return its path.

    Numbers are written in full (shortest round-trip form), so the folder reads back as
    :func:`sample_drive` exactly. The files appear whole or not at all: an error or an interrupt
    removes those this call wrote where there was none before. ``overwrite`` replaces the
    sample's files already in ``folder`` (each whole or not at all); nothing else there is touched.

    Raises:
        FileExistsError: one of :data:`FILES` is already in ``folder`` (unless ``overwrite``);
            nothing is written.
        NotADirectoryError: ``folder`` is a file.
    """
    path = Path(folder)
    if path.exists() and not path.is_dir():
        raise NotADirectoryError(f"{path}: not a folder; give a new or existing folder for the sample log")
    require_flag("overwrite", overwrite)
    taken = [name for name in FILES if (path / name).exists()]
    if taken and not overwrite:
        raise FileExistsError(f"{path}: already holds {', '.join(taken)}; give another folder, or replace them "
                              "(--overwrite; overwrite=True in Python) (nothing was written)")
    gyro, reference, odometry, meta = _sample()
    make_folder(path)
    texts = [_csv(columns) for columns in (gyro, reference, odometry)] + [json.dumps(meta, indent=2) + "\n"]
    written: list[Path] = []
    try:
        for name, text in zip(FILES, texts):
            write_text_atomically(path / name, text)
            written.append(path / name)
    except BaseException:
        for done in written:
            if done.name not in taken:  # a file replaced keeps its new content: the old one is gone
                done.unlink(missing_ok=True)
        raise
    return path


def _sample() -> tuple[dict[str, FloatArray], dict[str, FloatArray], dict[str, FloatArray], dict[str, Any]]:
    """The sample's gyro, reference and odometry columns and its meta.json."""
    drive = sim.car_drive(**SAMPLE)
    assert drive.stationary is not None, "a car drive starts with its rest"
    ref = slice(None, None, REFERENCE_EVERY)
    gyro = {"t": drive.t, "gyro_z": drive.rate_measured}
    reference = {"t": drive.t[ref], "heading": drive.heading_true[ref], "x": drive.x[ref], "y": drive.y[ref]}
    odometry = {"t": drive.t[ref], "speed": drive.speed[ref]}
    args = ", ".join(f"{k}={v!r}" for k, v in SAMPLE.items())
    meta = {
        "name": "sample_drive",
        "simulated": True,
        "platform": f"a simulated car, not a recording: gyrocore.sim.car_drive({args}), gyrocore {__version__}",
        "gyro": f"simulated {drive.sensor.name} at {drive.sensor.rate_hz:g} Hz (gyrocore.sim.SENSORS)",
        "reference": "the simulation's true heading and track, exact",
        "stationary": list(drive.stationary),
        "static_bias_rad_s": drive.bias,
        "units": {"t": "s", "gyro_z": "rad/s, counter-clockwise positive",
                  "heading": "rad, counter-clockwise positive, continuous", "x": "m", "y": "m", "speed": "m/s"},
        "samples": len(drive.t),
        "duration_s": drive.duration,
    }
    return gyro, reference, odometry, meta


def _csv(columns: dict[str, FloatArray]) -> str:
    # repr of a float is its shortest form that reads back as the same number
    rows = zip(*(np.asarray(c).tolist() for c in columns.values()))
    return ",".join(columns) + "\n" + "".join(",".join(map(repr, row)) + "\n" for row in rows)


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m gyrocore.datasets [FOLDER]``: write the sample log (default ``sample_drive``)."""
    parser = argparse.ArgumentParser(prog="python -m gyrocore.datasets",
                                     description="Write the simulated sample log as a log folder.")
    parser.add_argument("folder", nargs="?", default="sample_drive",
                        help="folder to write (created if missing; default sample_drive)")
    parser.add_argument("--overwrite", action="store_true", help="replace the sample's files already in the folder")
    args, extras = parser.parse_known_args(argv)
    if extras:  # with the option a typo is likely of, as the gyrocore command says it (`--overwite`)
        options = [o for action in parser._actions for o in action.option_strings]
        parser.error(f"unrecognized arguments: {' '.join(extras)}"
                     + "".join(did_you_mean(e.split("=")[0], options) for e in extras if e.startswith("-")))
    try:
        folder = write_sample(args.folder, overwrite=args.overwrite)
    except OSError as e:
        print(f"gyrocore.datasets: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("gyrocore.datasets: interrupted; no file was left", file=sys.stderr)
        return 130
    print(f"wrote the simulated sample log to {folder}: {', '.join(FILES)}; try "
          f"gyrocore process {folder} --out heading.csv")
    return 0


if __name__ == "__main__":
    sys.exit(main())
