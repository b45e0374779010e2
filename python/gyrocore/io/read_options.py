"""Where the samples are in a file and in which units: the reading options every reader shares."""

from __future__ import annotations

from dataclasses import dataclass

from .._checks import require_choice, require_flag
from ..window import Window
from ._axes import MEASURED, parse_up, parse_up_window, three_names
from .units import RATE_UNITS, TIME_UNITS, rate_unit_named, time_unit_named


@dataclass(frozen=True)
class ReadOptions:
    """Where the samples are in a file and in which units.

    Attributes:
        time_col: time column (field, array) name; ``None``: ``t``, or column 0 of a plain 2-D
            ``.npy`` array (whose columns are numbered from 0).
        rate_col: rate column name; ``None``: ``gyro_z``, or column 1 of a plain 2-D array.
        time_unit: ``s``, ``ms``, ``us`` or ``ns`` (a Parquet timestamp column and bag stamps
            carry their own unit); ``None``: the unit the column's name states (``t [ms]``,
            ``#timestamp [ns]``, ``t_us``), else ``s``.
        rate_unit: ``rad/s`` or ``deg/s``; ``None``: the unit the column's name states
            (``w_z [rad s^-1]``, ``gyro_z_dps``), else ``rad/s``.
        topic: the bag topic with sensor_msgs/Imu messages (``None``: the only one).
        delimiter: CSV field delimiter; ``None``: a tab for a ``.tsv`` file, else ``,``.
        static: the log was recorded at rest (for an Allan deviation): rates that stay small do
            not suggest a log in rad/s read as deg/s.
        gyro_cols: three-axis input: the gyro's x, y and z columns (in ``rate_unit``; a text
            ``gx,gy,gz`` is split); the yaw rate is their component along ``up``. A bag's are
            ``angular_velocity.x``, ``.y``, ``.z``.
        accel_cols: the accelerometer's x, y and z columns [m/s^2], to measure ``up`` over the
            rest window (a bag's are ``linear_acceleration.x``, ``.y``, ``.z``).
        up: the sensor axis that points up (``x``, ``-y``, ...), a vector ``(x, y, z)`` or
            ``"x,y,z"`` (normalised), or ``accel``: measured from the accelerometer (the
            default when ``accel_cols`` is given). Giving any of the three reads three axes.
        up_window: the rest window ``(t0, t1)`` [s] or :class:`gyrocore.window.Window` over
            which ``up`` is measured; ``None``: the rest window of a log folder's meta.json.
    """

    time_col: str | None = None
    rate_col: str | None = None
    time_unit: str | None = None
    rate_unit: str | None = None
    topic: str | None = None
    delimiter: str | None = None
    static: bool = False
    gyro_cols: tuple[str, str, str] | None = None
    accel_cols: tuple[str, str, str] | None = None
    up: str | tuple[float, float, float] | None = None
    up_window: tuple[float, float] | Window | None = None

    def __post_init__(self) -> None:
        for name in ("time_col", "rate_col"):
            value = getattr(self, name)
            if value is not None and not isinstance(value, str):  # a number failed deep in the reader
                raise TypeError(
                    f"{name} must be text: a column name, or a plain .npy array's column number as text "
                    f"({name}='{value}'), got {value!r}"
                )
            if value is not None and not value.strip():  # an empty shell variable read the default column
                raise ValueError(f"{name} (--{name.replace('_', '-')}) {value!r}: no column name; give one, or leave "
                                 "the option out for the default column")
        require_flag("static", self.static)  # "no" was read as True, and hid a unit warning
        # normalised forms (the dataclass is frozen): column triples as tuples, up parsed
        if self.gyro_cols is not None:
            object.__setattr__(self, "gyro_cols", three_names(self.gyro_cols, "gyro_cols (--gyro-cols)"))
        if self.accel_cols is not None:
            object.__setattr__(self, "accel_cols", three_names(self.accel_cols, "accel_cols (--accel-cols)"))
        if self.up is not None:
            object.__setattr__(self, "up", parse_up(self.up))
        if self.up_window is not None:
            object.__setattr__(self, "up_window", parse_up_window(self.up_window))
        if self.gyro_cols is not None and self.rate_col is not None:
            raise ValueError(
                f"rate_col {self.rate_col!r} (--rate-col) reads one axis and gyro_cols (--gyro-cols) three: give one"
            )
        if self.up_window is not None and not self.three_axis:
            raise ValueError(
                "up_window (--up-window) is where up is measured, for three-axis input: give gyro_cols and "
                "accel_cols (--gyro-cols, --accel-cols) too"
            )
        if self.accel_cols is not None and self.up not in (None, MEASURED):
            raise ValueError(
                "up is given (--up) and accel_cols (--accel-cols) would measure it: give one "
                f"(--up {MEASURED} with --accel-cols measures it)"
            )
        if self.time_unit is not None:
            object.__setattr__(self, "time_unit", time_unit_named(self.time_unit))
            require_choice("time_unit", self.time_unit, TIME_UNITS)
        if self.rate_unit is not None:
            object.__setattr__(self, "rate_unit", rate_unit_named(self.rate_unit))
            require_choice("rate_unit", self.rate_unit, RATE_UNITS)
        if self.delimiter is not None and len(self.delimiter) != 1:
            raise ValueError(f"delimiter must be one character, got {self.delimiter!r}")
        if self.delimiter in ('"', "\n", "\r"):
            raise ValueError(
                f"delimiter {self.delimiter!r} cannot separate fields (it quotes a field or ends a line): "
                "give ',', ';', a tab or another character"
            )
        rates = self.gyro_cols if self.gyro_cols is not None else (self.rate,)
        if self.time in rates:  # the times would be read as rates too
            raise ValueError(
                f"the time column {self.time!r} (time_col, --time-col) is also a rate column (rate_col, "
                "--rate-col; gyro_cols, --gyro-cols): give each its own column"
            )

    @property
    def counts_per_second(self) -> float:
        """Counts of the time unit in a second (a unit not resolved yet is s)."""
        return TIME_UNITS[self.time_unit or "s"]

    @property
    def time(self) -> str:
        """The time column of a named layout."""
        return self.time_col or "t"

    @property
    def rate(self) -> str:
        """The rate column of a named layout."""
        return self.rate_col or "gyro_z"

    @property
    def three_axis(self) -> bool:
        """Whether the yaw rate is the projection of three gyro axes on ``up``."""
        return self.gyro_cols is not None or self.accel_cols is not None or self.up is not None

    @property
    def measures_up(self) -> bool:
        """Whether ``up`` is measured from the accelerometer (not given)."""
        return self.three_axis and not isinstance(self.up, tuple)
