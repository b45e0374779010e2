"""Coverage-guided fuzzing of gyrocore's file readers with atheris: arbitrary bytes written as a
CSV, .npy, .npz, Parquet or ROS 1 bag file, read whole and streamed through the pipeline. A reader may reject
a file only with ValueError (or OSError / UnicodeDecodeError for undecodable bytes), naming the
file; anything else, a crash or a hang, is a finding.

    pip install atheris
    python fuzz/python/readers.py csv -max_total_time=60
    python fuzz/python/readers.py npy -max_total_time=60 corpus_dir/
"""

from __future__ import annotations

import sys
import tempfile
import warnings
from pathlib import Path

import atheris

with atheris.instrument_imports():
    from gyrocore import batch, io

FORMATS = {"csv": ".csv", "npy": ".npy", "npz": ".npz", "parquet": ".parquet", "bag": ".bag"}
ACCEPTED = (ValueError, OSError, UnicodeDecodeError)

kind = sys.argv.pop(1) if len(sys.argv) > 1 and sys.argv[1] in FORMATS else "csv"
folder = Path(tempfile.mkdtemp(prefix="gyrocore-fuzz-"))
path = folder / f"input{FORMATS[kind]}"


def one_input(data: bytes) -> None:
    path.write_bytes(data)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            log = io.read_log(path)
        except ACCEPTED as e:
            assert str(path) in str(e) or kind != "csv", f"error does not name the file: {e}"
            return
        assert len(log.t) == len(log.rate)
        try:
            report = batch.process_file(path, folder / "out.csv", preset="raw", chunk_rows=7)
        except ACCEPTED:
            return
        assert report.rows_in == report.rows_out == len(log.t)


atheris.Setup(sys.argv, one_input)
atheris.Fuzz()
