"""Three-axis input: the axis a one-axis read takes (bags' ``angular_velocity.x|y|z`` too), and the
vertical projection ``gyro . up`` with up given or measured from the accelerometer at rest."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import io

from .test_cli_reading import gyrocore_cli, one_error, read_heading, write_csv
from .test_io import write_bag

GRAVITY = 9.80665
#: The drive the tests rotate into a sensor frame: 300 s at 100 Hz, a 20 s rest first.
DRIVE = gyrocore.sim.car_drive(duration=300.0, rate_hz=100.0, seed=5)
#: White noise of the gyro's horizontal axes [rad/s] and of each accelerometer axis [m/s^2].
GYRO_NOISE, ACCEL_NOISE = 0.002, 0.05


def rotation(axis: tuple[float, float, float], angle: float) -> np.ndarray:
    """The rotation matrix of ``angle`` [rad] about ``axis`` (Rodrigues)."""
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    cross = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * cross + (1 - math.cos(angle)) * cross @ cross


#: Sensor frame to world frame (z up): x up (EuRoC's mounting), and a tilted mounting.
X_UP = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]).T
TILTED = rotation((0.0, 0.0, 1.0), 0.7) @ rotation((1.0, 1.0, 0.3), math.radians(35.0))


def imu(sensor_to_world: np.ndarray, seed: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A three-axis IMU mounted with ``sensor_to_world`` on :data:`DRIVE` (which turns about the
    vertical only): (world gyro, sensor gyro, sensor accelerometer), samples x 3. The world gyro's
    vertical axis is the drive's one-axis reading, its horizontal axes white noise; the
    accelerometer reads gravity (up) with white noise."""
    rng = np.random.default_rng(seed)
    n = len(DRIVE.t)
    gyro_world = np.column_stack([rng.normal(0, GYRO_NOISE, (n, 2)), DRIVE.rate_measured])
    accel_world = rng.normal(0, ACCEL_NOISE, (n, 3)) + [0.0, 0.0, GRAVITY]
    world_to_sensor = sensor_to_world.T  # each row v becomes R^T v
    return gyro_world, gyro_world @ world_to_sensor.T, accel_world @ world_to_sensor.T


def six_axis_csv(path: Path, gyro: np.ndarray, accel: np.ndarray) -> Path:
    header = ["t", "gx", "gy", "gz", "ax", "ay", "az"]
    return write_csv(path, header, [DRIVE.t, *gyro.T, *accel.T])


THREE_AXES = ("--gyro-cols", "gx,gy,gz")


# --- one axis: the one asked for, in every kind of input --------------------------------------


@pytest.mark.parametrize("command", ["process", "allan", "calibrate", "evaluate", "tune"])
def test_every_command_that_reads_a_file_takes_the_three_axis_options(command: str) -> None:
    out = gyrocore_cli(command, "--help", code=0).stdout
    for option in ("--gyro-cols", "--accel-cols", "--up", "--up-window"):
        assert option in out, f"gyrocore {command} lacks {option}"


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_bag_rate_col_reads_the_axis_named(tmp_path: Path, ros1: bool) -> None:
    n = 300
    stamps = [1_700_000_000_000_000_000 + 10_000_000 * i for i in range(n)]
    gyro = np.column_stack([np.linspace(0.1, 0.4, n), np.linspace(-0.2, 0.1, n), np.linspace(0.0, 0.05, n)])
    bag = tmp_path / ("imu.bag" if ros1 else "imu")
    write_bag(bag, stamps, gyro[:, 2].tolist(), ros1=ros1, gyro=gyro)
    for k, axis in enumerate("xyz"):
        out = tmp_path / f"{axis}.csv"
        proc = gyrocore_cli("process", bag, "--rate-col", f"angular_velocity.{axis}", "--preset", "raw",
                            "--out", out, code=0)
        assert proc.stdout.startswith("ok")
        assert np.array_equal(read_heading(out)[:, 2], gyro[:, k]), axis  # the rate column: the axis read
    assert np.array_equal(read_heading(tmp_path / "z.csv"), read_heading(_default(bag, tmp_path)))
    for bad in ("angular_velocity.w", "linear_acceleration.x", "gyro_z"):
        error = one_error(gyrocore_cli("process", bag, "--rate-col", bad, "--out", tmp_path / "b.csv", code=2))
        assert f"'{bad}' is not a field of sensor_msgs/msg/Imu" in error
        assert "angular_velocity.x, angular_velocity.y, angular_velocity.z" in error and str(bag) in error


def _default(bag: Path, tmp_path: Path) -> Path:
    out = tmp_path / "default.csv"
    gyrocore_cli("process", bag, "--preset", "raw", "--out", out, code=0)
    return out


@pytest.mark.parametrize("suffix", [".csv", ".parquet", ".npz", ".npy"])
def test_every_file_kind_reads_three_axes_and_projects_on_up(tmp_path: Path, suffix: str) -> None:
    _, gyro, accel = imu(TILTED)
    t, names = DRIVE.t[:3000], ["t", "gx", "gy", "gz", "ax", "ay", "az"]
    columns = [t, *gyro[:3000].T, *accel[:3000].T]
    path = tmp_path / f"imu{suffix}"
    if suffix == ".csv":
        write_csv(path, names, columns)
    elif suffix == ".parquet":
        import pyarrow as pa
        import pyarrow.parquet as pq

        pq.write_table(pa.table(dict(zip(names, columns))), path)
    elif suffix == ".npz":
        np.savez(path, **dict(zip(names, columns)))
    else:
        np.save(path, np.rec.fromarrays(columns, names=names))
    up = tuple(TILTED[2])  # the world's z axis in the sensor frame
    given = gyrocore.read_log(path, gyro_cols="gx,gy,gz", up=up)
    expected = gyro[:3000] @ (np.asarray(up) / np.linalg.norm(up))
    np.testing.assert_allclose(given.rate, expected, rtol=0, atol=1e-15)
    source = io.open_source(path, gyro_cols=("gx", "gy", "gz"), accel_cols=("ax", "ay", "az"), up_window=(0.0, 20.0))
    measured = np.asarray(source.up())
    inside = t <= 20.0
    assert np.array_equal(measured, accel[:3000][inside].mean(axis=0))  # the mean over the rest window
    # one axis stays what it was: the column named
    assert np.array_equal(gyrocore.read_log(path, rate_col="gy").rate, gyro[:3000, 1])


# --- the projection ---------------------------------------------------------------------------


def projection_bound(gyro_world: np.ndarray, rest: np.ndarray) -> float:
    """The largest heading difference [rad] between the projected and the z-up log that the
    error of a measured up allows, with the static_bias preset (bias = mean rate over the rest,
    heading = a sum of the rates times intervals).

    The accelerometer's mean over N rest samples is off up by a horizontal error of Rayleigh
    scale s = ACCEL_NOISE / sqrt(N), beyond 6 s with probability exp(-18) = 1.5e-8, so up is off
    by at most delta = atan(6 s / (g - 6 s)). A rate is then off by at most |w| |u' - u| <= |w|
    delta (w the world gyro, u' - u the error of the unit vector), the bias by at most delta max
    |w| over the rest, and the heading at time T by at most delta (sum |w_i| dt_max + T max_rest |w|).
    """
    s = ACCEL_NOISE / math.sqrt(int(rest.sum()))
    delta = math.atan(6 * s / (GRAVITY - 6 * s))
    norms = np.linalg.norm(gyro_world, axis=1)
    dt_max = float(np.diff(DRIVE.t).max())
    return delta * (float(norms.sum()) * dt_max + DRIVE.duration * float(norms[rest].max()))


def test_a_tilted_imu_gives_the_heading_of_the_z_up_log_within_the_projection_error(tmp_path: Path) -> None:
    gyro_world, gyro, accel = imu(TILTED)
    tilted = six_axis_csv(tmp_path / "tilted.csv", gyro, accel)
    z_up = write_csv(tmp_path / "z_up.csv", ["t", "gyro_z"], [DRIVE.t, gyro_world[:, 2]])
    common = ("--preset", "static_bias", "--bias-window", "0", "20")
    gyrocore_cli("process", z_up, *common, "--out", tmp_path / "z.csv", code=0)
    gyrocore_cli("process", tilted, *common, *THREE_AXES, "--accel-cols", "ax,ay,az", "--out", tmp_path / "p.csv",
                 code=0)
    reference, projected = read_heading(tmp_path / "z.csv")[:, 1], read_heading(tmp_path / "p.csv")[:, 1]
    rest = (DRIVE.t >= 0) & (DRIVE.t <= 20)
    bound = projection_bound(gyro_world, rest)
    difference = float(np.abs(projected - reference).max())
    assert difference <= bound, (difference, bound)
    # the bound is tight enough to matter: the drive turns through many times that
    assert float(np.abs(reference).max()) > 100 * bound
    # and the same log read on its tilted z axis alone is far off
    gyrocore_cli("process", tilted, *common, "--rate-col", "gz", "--out", tmp_path / "gz.csv", code=0)
    assert float(np.abs(read_heading(tmp_path / "gz.csv")[:, 1] - reference).max()) > 10 * bound


def test_up_x_on_a_euroc_like_log_is_the_x_axis_exactly(tmp_path: Path) -> None:
    gyro_world, gyro, accel = imu(X_UP)
    t_ns = 1403636579758555392 + np.round(DRIVE.t * 1e9).astype(np.int64)
    names = ["#timestamp [ns]", *(f"w_RS_S_{a} [rad s^-1]" for a in "xyz"), *(f"a_RS_S_{a} [m s^-2]" for a in "xyz")]
    lines = [",".join(names)] + [",".join([str(ti), *map(repr, g), *map(repr, a)])
                                 for ti, g, a in zip(t_ns.tolist(), gyro.tolist(), accel.tolist())]
    euroc = tmp_path / "data.csv"
    euroc.write_text("\n".join(lines) + "\n")
    common = ("--time-col", "timestamp", "--preset", "static_bias", "--bias-window", "+0", "+20")
    gyro_cols = ("--gyro-cols", "w_RS_S_x,w_RS_S_y,w_RS_S_z")
    gyrocore_cli("process", euroc, *common, *gyro_cols, "--up", "x", "--out", tmp_path / "up.csv", code=0)
    gyrocore_cli("process", euroc, *common, "--rate-col", "w_RS_S_x", "--out", tmp_path / "x.csv", code=0)
    assert np.array_equal(read_heading(tmp_path / "up.csv"), read_heading(tmp_path / "x.csv"))
    # measured from the accelerometer: within the projection's error of the x axis
    gyrocore_cli("process", euroc, *common, *gyro_cols, "--accel-cols", "a_RS_S_x,a_RS_S_y,a_RS_S_z",
                 "--out", tmp_path / "measured.csv", code=0)
    rest = DRIVE.t <= 20
    difference = np.abs(read_heading(tmp_path / "measured.csv")[:, 1] - read_heading(tmp_path / "x.csv")[:, 1])
    assert float(difference.max()) <= projection_bound(gyro_world, rest)
    # an axis pointing down reads the rate with its sign turned
    gyrocore_cli("process", euroc, *common, *gyro_cols, "--up=-x", "--out", tmp_path / "down.csv", code=0)
    assert np.array_equal(read_heading(tmp_path / "down.csv")[:, 1], -read_heading(tmp_path / "up.csv")[:, 1])
    # and written as two words, as a user types it
    gyrocore_cli("process", euroc, *common, *gyro_cols, "--up", "-x", "--out", tmp_path / "down2.csv", code=0)
    assert (tmp_path / "down2.csv").read_bytes() == (tmp_path / "down.csv").read_bytes()


def test_a_bag_measures_up_from_linear_acceleration(tmp_path: Path) -> None:
    n = 400
    stamps = [1_700_000_000_000_000_000 + 10_000_000 * i for i in range(n)]
    rng = np.random.default_rng(3)
    gyro = np.column_stack([0.2 * np.sin(np.arange(n) / 40.0), rng.normal(0, 0.01, (n, 2))])
    accel = np.tile([GRAVITY, 0.0, 0.0], (n, 1))  # x up, exactly: the measured up is the x axis
    bag = tmp_path / "imu.bag"
    write_bag(bag, stamps, gyro[:, 2].tolist(), ros1=True, gyro=gyro, accel=accel)
    common = ("--preset", "static_bias", "--bias-duration", "1")
    gyrocore_cli("process", bag, *common, "--up", "accel", "--out", tmp_path / "up.csv", code=0)
    gyrocore_cli("process", bag, *common, "--rate-col", "angular_velocity.x", "--out", tmp_path / "x.csv", code=0)
    assert np.array_equal(read_heading(tmp_path / "up.csv"), read_heading(tmp_path / "x.csv"))
    # a bag's accelerometer that reads nothing: free fall
    write_bag(tmp_path / "fall.bag", stamps, gyro[:, 2].tolist(), ros1=True, gyro=gyro, accel=np.zeros((n, 3)))
    error = one_error(gyrocore_cli("process", tmp_path / "fall.bag", *common, "--up", "accel",
                                   "--out", tmp_path / "f.csv", code=2))
    assert "fall.bag: the rest window +0 .. +1 s, over which up is measured, reads a mean specific force of 0" in error
    assert "free fall" in error


# --- errors -----------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def six_axis(tmp_path_factory: pytest.TempPathFactory) -> Path:
    _, gyro, accel = imu(TILTED)
    accel[(DRIVE.t >= 30) & (DRIVE.t <= 40)] = np.nan  # a stretch without accelerometer readings
    return six_axis_csv(tmp_path_factory.mktemp("axes") / "imu.csv", gyro, accel)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ((*THREE_AXES, "--accel-cols", "ax,ay,az"),
         "imu.csv: up is measured from the accelerometer at rest, and no rest window is given: give one "
         "(--up-window T0 T1, or the command's rest window: --bias-window, --bias-duration, or --window of "
         "calibrate and allan; up_window=), or give up (--up, up=)"),
        ((*THREE_AXES, "--accel-cols", "ax,ay,az", "--bias-window", "30", "40"),
         "imu.csv: the rest window 30 .. 40 s, over which up is measured, holds no accelerometer reading"),
        ((*THREE_AXES, "--accel-cols", "ax,ay,az", "--up-window", "400", "410", "--bias-duration", "20"),
         "the rest window 400 .. 410 s, over which up is measured, holds no accelerometer reading (the log runs "
         "from 0 to"),
        ((*THREE_AXES, "--accel-cols", "gx,gy,gz", "--bias-duration", "20"),
         "reads a mean specific force of 0.0"),
        ((*THREE_AXES, "--up", "0,0,0"), "up '0,0,0': invalid parameter up = 0: must be three finite components"),
        ((*THREE_AXES, "--up", "w"), "up 'w': give x, y, z, -x, -y, -z, a vector X,Y,Z (normalised), or accel"),
        ((*THREE_AXES, "--rate-col", "gz", "--up", "z"), "rate_col 'gz' (--rate-col) reads one axis and gyro_cols"),
        ((*THREE_AXES, "--up", "z", "--accel-cols", "ax,ay,az"), "up is given (--up) and accel_cols (--accel-cols)"),
        (("--up", "z"), "imu.csv: three-axis input (up, accel_cols) needs the gyro's three columns: gyro_cols"),
        ((*THREE_AXES, "--bias-duration", "20"), "imu.csv: up is measured from the accelerometer: give its three"),
        (("--gyro-cols", "gx,gy"), "--gyro-cols) 'gx,gy': give three different column names"),
        (("--gyro-cols", "gx,gy,gw", "--up", "z"), "imu.csv: missing column(s) gw"),
        (("--up-window", "0", "20"), "up_window (--up-window) is where up is measured, for three-axis input"),
    ],
)
def test_three_axis_errors_are_named(six_axis: Path, tmp_path: Path, options: tuple[str, ...], message: str) -> None:
    out = tmp_path / "out.csv"
    error = one_error(gyrocore_cli("process", six_axis, *options, "--preset", "raw", "--out", out, code=2))
    assert message in error
    assert not out.exists()


@pytest.mark.parametrize("command", ["calibrate", "allan"])
def test_the_rest_window_of_calibrate_and_allan_is_where_up_is_measured(six_axis: Path, command: str) -> None:
    # their rest window is --window: the error and the help named --bias-window, which they lack
    options = (*THREE_AXES, "--accel-cols", "ax,ay,az")
    gyrocore_cli(command, six_axis, *options, "--window", "+0", "+20", code=0)
    error = one_error(gyrocore_cli(command, six_axis, *options, code=2))
    assert "--up-window T0 T1" in error and "--window of calibrate and allan" in error


@pytest.mark.parametrize(("command", "rest"), [("process", "--bias-window or --bias-duration"),
                                                ("evaluate", "--bias-duration"), ("tune", "--bias-duration"),
                                                ("calibrate", "--window"), ("allan", "--window")])
def test_up_window_help_names_the_commands_own_rest_window(command: str, rest: str) -> None:
    out = " ".join(gyrocore_cli(command, "--help", code=0).stdout.split())
    assert f"(default: {rest}, else a log folder's rest window)" in out


def test_gyro_columns_in_different_units_are_an_error(tmp_path: Path) -> None:
    path = write_csv(tmp_path / "units.csv", ["t", "gx [deg/s]", "gy [rad/s]", "gz [rad/s]"],
                     [np.arange(10.0), np.zeros(10), np.zeros(10), np.zeros(10)])
    with pytest.raises(ValueError, match=r"units\.csv: the gyro columns read in different units \('gx \[deg/s\]' as"):
        gyrocore.read_log(path, gyro_cols="gx,gy,gz", up="z")
