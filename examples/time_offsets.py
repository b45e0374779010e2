"""The gyro's time offset against its reference on every real log with one
(:func:`gyrocore.calibration.time_offset`), and what shifting the gyro's times by it does to
E_psi [deg] of static-bias removal (whole mode, the log's own rests, as ``gyrocore evaluate`` scores
``static_bias``) and of raw integration. Prints the table of docs/calibration.md "A gyro's time
offset", with the lag the KITTI logs' meta.json fits (``checks.clean_steps_fit``, of the rate
behind the yaw: the offset's opposite) where there is one.

    python examples/time_offsets.py [DATA_DIR]     # default ../shared/data/real; a few seconds
"""

import sys
import warnings
from pathlib import Path

import gyrocore
from gyrocore import calibration


def meta_lag(log: gyrocore.Log) -> float | None:
    """The lag of the gyro's rate behind the reference's yaw [s] that meta.json's checks fit, if any."""
    fit = (log.meta.get("checks") or {}).get("clean_steps_fit") or {}
    return fit.get("wz_lag_behind_yaw_s")


def e_psi(log: gyrocore.Log, result: gyrocore.HeadingResult, offset: float) -> float:
    """E_psi [deg] of ``result`` with its times shifted by ``offset`` onto the reference's clock."""
    return gyrocore.heading_errors(result.t + offset, result.heading, *log.reference()).e_psi_deg


def row(log: gyrocore.Log) -> str:
    """The table's row of ``log``: the offset, its standard error, E_psi before and after."""
    try:
        found = calibration.time_offset(log.t, log.rate, *log.reference()[:2])
    except ValueError as e:
        return f"| {log.name} | refused: {str(e).split(': ', 1)[1].split(';')[0]} | | | | | | |"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)  # rests refused, or none found
        static, raw = log.process("static_bias", mode="whole"), log.process("raw", mode="causal")
    lag = meta_lag(log)
    cells = [f"{found.offset:+.4f}", f"{1e3 * found.offset_stderr:.2g}",
             *(f"{e_psi(log, result, offset):.3f}" for result in (static, raw) for offset in (0.0, found.offset)),
             "" if lag is None else f"{-lag:+.4f}"]
    return f"| {log.name} | " + " | ".join(cells) + " |"


def main(data: Path) -> None:
    print("| log | offset [s] | its standard error [ms] | static_bias E_psi | shifted | raw E_psi | shifted "
          "| meta.json's fit [s] |")
    print("|---|---|---|---|---|---|---|---|")
    for path in sorted(data.iterdir()):
        if (path / "gyro.csv").is_file():
            log = gyrocore.read_log(path)
            if log.t_ref is not None:
                print(row(log))


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[2] / "shared" / "data" / "real")
