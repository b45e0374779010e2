"""Helpers shared by the subcommands."""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import sys
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TypeVar

from .. import _gyrocore, _signals, io
from .._checks import MAX_READING, json_value
from .._extras import MissingExtra, tqdm_class
from .._gyrocore import SampleError
from .._time_steps import time_steps_named
from ..calibration import Calibration
from ..evaluate import Failed
from ..io.atomic import already_there, check_output_folder, check_replaceable
from ..io.units import rate_unit_named, time_unit_named
from ..io._paths import error_text, one_line
from ..pipeline import Pipeline, has_bias_source, recommended_preset
from ..window import Window


#: The errors a user can act on: one line ``gyrocore: error: ...`` and exit 2, or, for one log of
#: many, its ``FAILED`` line.
USER_ERRORS = (ValueError, TypeError, OSError, MissingExtra)

_Row = TypeVar("_Row")


def each_log(items: Sequence[str | io.Log | Failed], work: Callable[[Any], Sequence[_Row]], *,
             alone: bool) -> list[_Row | Failed]:
    """The rows of ``work(item)`` for each log (a path or a log read from one), in order; a log
    that failed already stays as it is. The only log of a run (``alone``) fails the command (one
    line, exit 2); of several, a log that fails becomes its :class:`~gyrocore.evaluate.Failed`
    row, named by its path, and the others go on."""
    rows: list[_Row | Failed] = []
    for item in items:
        if isinstance(item, Failed):
            rows.append(item)
            continue
        try:
            rows += work(item)
        except USER_ERRORS as e:
            if alone:
                raise
            rows.append(Failed(item.path or item.name if isinstance(item, io.Log) else item, error_text(e)))
    return rows


def print_failures(rows: Sequence[object], logs: int) -> None:
    """Under a table of several logs where some failed: how many were scored."""
    failed = sum(isinstance(r, Failed) for r in rows)
    if failed:
        print(f"{logs - failed} of {logs} logs scored, {failed} failed")


def exit_code(rows: Sequence[object]) -> int:
    """1 when a log failed (as ``gyrocore process`` over a folder), else 0."""
    return 1 if any(isinstance(r, Failed) for r in rows) else 0


#: The log folder the examples of the commands' help read, and where it comes from.
SAMPLE_LOG = "sample_drive"
SAMPLE_LOG_NOTE = f"{SAMPLE_LOG}: the sample log folder that python -m gyrocore.datasets {SAMPLE_LOG} writes"


def add_command(
    sub: argparse._SubParsersAction[argparse.ArgumentParser],
    name: str,
    help_text: str,
    example: str,
    func: Callable[[argparse.Namespace], int],
) -> argparse.ArgumentParser:
    """Add a subcommand whose ``--help`` ends with an example; ``func(args)`` returns the exit code."""
    # the example also shows in the list of subcommands of ``gyrocore --help``
    # an example that reads a log reads the sample log, which every install can write
    where = f"\n({SAMPLE_LOG_NOTE})" if SAMPLE_LOG in example else ""
    parser = sub.add_parser(
        name, help=f"{help_text} (example: {example})", description=help_text, epilog=f"example: {example}{where}"
    )
    parser.set_defaults(func=func)
    return parser


#: How every window option is written.
WINDOW_HELP = "T0 T1 [s] in the log's time base, or +T0 +T1 after its first sample"


#: What a reference file given with ``--reference`` holds.
REFERENCE_HELP = "a CSV file with columns t [s, the log's time base] and heading [rad, counter-clockwise]"


def with_reference(log: io.Log, path: Path) -> io.Log:
    """``log`` with the reference heading of the file ``path`` (see :data:`REFERENCE_HELP`)."""
    ref = io.read_reference_file(path)
    return dataclasses.replace(log, t_ref=ref["t"], heading_ref=ref["heading"], x_ref=ref.get("x"), y_ref=ref.get("y"))


def delimiter(text: str) -> str:
    """A ``--delimiter``: ``tab`` or ``\\t`` (as a shell passes them) mean a tab, which is hard to
    type on a command line; any other text is the delimiter itself (checked where it is used)."""
    return "\t" if text.lower() in ("tab", "\\t") else text


def add_reading_options(parser: argparse.ArgumentParser, rest_window: str) -> None:
    """The options that say how to read a file input, the same for every command that reads one;
    ``rest_window`` names the command's own rest window options, which ``--up-window`` defaults to
    (each command has other ones, and a help naming options it lacks sent users nowhere)."""
    read = parser.add_argument_group(
        "reading (where the samples are; a header like 't [ms]' or 'gyro_z_dps' states its unit)"
    )
    read.add_argument("--time-col", help="time column, with or without its unit (default t; "
                      "column number for a plain .npy array)")
    read.add_argument("--rate-col", help="rate column, with or without its unit (default gyro_z)")
    # a unit as a header may spell it (sec, dps) is taken too: the type runs before the choices' check
    read.add_argument("--time-unit", choices=tuple(io.TIME_UNITS), type=time_unit_named,
                      help="unit of the time column (default: the header's, else s)")
    read.add_argument("--rate-unit", choices=io.RATE_UNITS, type=rate_unit_named,
                      help="unit of the rate column (default: the header's, else rad/s; also dps)")
    read.add_argument("--topic", help="bag topic with sensor_msgs/Imu (default: the only one)")
    read.add_argument("--delimiter", type=delimiter, help="CSV delimiter (default , and a tab for .tsv; "
                      "'tab' or '\\t' for a tab)")
    axes = parser.add_argument_group(
        "three-axis input (the yaw rate is the gyro's component along up; a bag reads angular_velocity "
        "and linear_acceleration)"
    )
    axes.add_argument("--gyro-cols", metavar="GX,GY,GZ", help="the gyro's x, y and z columns (in --rate-unit)")
    axes.add_argument("--accel-cols", metavar="AX,AY,AZ",
                      help="the accelerometer's x, y and z columns [m/s^2]: up is their mean over the rest window")
    axes.add_argument("--up", metavar="UP", help=f"the sensor axis that points up: {io.UP_HELP}")
    axes.add_argument("--up-window", nargs=2, metavar=("T0", "T1"),
                      help=f"rest window over which up is measured: {WINDOW_HELP} (default: {rest_window}, "
                      "else a log folder's rest window)")


def reading_options(args: argparse.Namespace) -> dict[str, Any]:
    """The reading options given on the command line, as :class:`gyrocore.io.ReadOptions` fields.

    ``up`` is measured over ``--up-window``, else over the command's own rest window
    (``--bias-window``, ``--bias-duration``; ``--window`` of calibrate and allan), which the static
    bias (or the Allan deviation) is measured over too."""
    names = ("time_col", "rate_col", "time_unit", "rate_unit", "topic", "delimiter", "gyro_cols", "accel_cols", "up")
    out = {name: getattr(args, name) for name in names if getattr(args, name) is not None}
    window = _rest_window(args)
    # the bias's rest window serves three-axis input only; --up-window alone is refused by ReadOptions
    if window is not None and ({"gyro_cols", "accel_cols", "up"} & out.keys() or args.up_window is not None):
        out["up_window"] = window
    return out


def _rest_window(args: argparse.Namespace) -> Window | None:
    """The rest window the command line gives, in the order ``--up-window``, ``--bias-window``,
    ``--window`` (calibrate's and allan's rest), ``--bias-duration`` (the first S seconds), or None."""
    for option in ("up_window", "bias_window", "window"):
        bounds = getattr(args, option, None)
        if bounds is not None:
            return Window.parse(bounds, "--" + option.replace("_", "-"))
    duration = getattr(args, "bias_duration", None)
    if duration is not None:
        return Window(0.0, duration, (True, True), "--bias-duration")
    return None


def check_samples(path: Path, log: io.Log, args: argparse.Namespace, reading_fix: str = "") -> None:
    """Refuse a log with a NaN or infinite time or rate, or times that do not increase, naming the
    first such sample by its file and line, in the core's words, as ``gyrocore process`` does; the
    analyses (calibration) name only its index. ``reading_fix`` follows the error of a bad reading:
    the option of the command that takes one."""
    try:
        with time_steps_named(log.t):  # a counter's wrap, float32 times: not mended by sorting
            _gyrocore.check_samples(log.t, log.rate)
    except SampleError as e:
        source = io.open_source(path, **reading_options(args))
        raise ValueError(source.locate(e, None, reading_fix or None)) from None


def add_override_options(group: argparse._ArgumentGroup) -> None:
    """``--param`` and ``--calibration``: pipeline parameters beyond the command's own options."""
    group.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                       help="any pipeline parameter, in SI units (gyrocore presets lists them, with their units); "
                       "repeatable")
    group.add_argument("--calibration", type=named_path, metavar="FILE",
                       help="a calibration written by gyrocore calibrate --save: its scale, and its bias "
                       "unless another bias option is given")


def parse_value(text: str) -> Any:
    """A ``--param`` value: a bool, a number, numbers separated by commas (a tuple), or text."""
    if text.lower() in ("true", "false"):
        return text.lower() == "true"
    numbers = text.split(",")
    try:
        values = [float(v) for v in numbers]
    except ValueError:
        return text
    if len(values) > 1:
        return tuple(values)
    return int(text) if text.strip().lstrip("+-").isdigit() else values[0]


_READING_FIELDS = {f.name for f in dataclasses.fields(io.ReadOptions)}


def pipeline_overrides(args: argparse.Namespace, named: dict[str, Any]) -> dict[str, Any]:
    """The pipeline parameters of the command line: the options ``named`` (parameter -> value, None
    when not given; a ``bias_window`` as written, see :class:`gyrocore.window.Window`), the
    scale and bias of ``--calibration`` and each ``--param NAME=VALUE``; a parameter given twice is
    an error."""
    out = {k: v for k, v in named.items() if v is not None}
    if "bias_window" in out:
        out["bias_window"] = Window.parse(out["bias_window"], "--bias-window")
    sources = dict.fromkeys(out, "its own option")
    offset = None  # the calibration's time offset, which this run does not apply
    if args.calibration is not None:
        # a bias given on the command line (or a rest window) replaces the calibration's bias; evaluate
        # passes its --bias-duration on apart from ``named`` (the calibration's bias was kept beside it)
        given = has_bias_source(out) or getattr(args, "bias_duration", None) is not None
        calibration = Calibration.load(args.calibration)
        found, offset = calibration.overrides(include_bias=False if given else None), calibration.time_offset
        try:  # checked here, where the file is known: the pipeline's error would name the value alone
            checked: dict[str, Any] = {"bias": 0.0, **found}
            Pipeline(recommended_preset(), **checked)  # the core checks each value as it is built
        except (TypeError, ValueError) as e:
            raise ValueError(f"--calibration {args.calibration}: {e}") from None
        out.update(found)
        sources.update(dict.fromkeys(found, f"--calibration {args.calibration}"))
    for item in args.param:
        name, sep, value = item.partition("=")
        if not sep or not name:
            raise ValueError(f"--param {item!r}: expected NAME=VALUE")
        if name in _READING_FIELDS:
            raise ValueError(f"--param {name} is a reading option, not a pipeline parameter (see the reading options)")
        if name in sources:
            raise ValueError(f"--param {name} is also given by {sources[name]}")
        out[name] = parse_value(value)
        sources[name] = "--param"
    if offset is not None:  # a field of the file given that this run does not use (said once the options hold)
        note(f"--calibration {args.calibration}: its time offset ({offset:+.4g} s) is not applied: the heading stays at "
             f"the gyro's times; on the reference's clock they are t {'+' if offset >= 0 else '-'} {abs(offset):.4g} s "
             "(in Python: gyrocore.process(t + calibration.time_offset, rate, ...))")
    return out


def add_overwrite_option(parser: argparse.ArgumentParser | argparse._ArgumentGroup) -> None:
    """``--overwrite``: the command replaces output files that exist already (see :func:`refuse_existing`)."""
    parser.add_argument("--overwrite", action="store_true",
                        help="replace output files that exist already (default: refuse them, before any work)")


def require_suffix(path: str | Path, option: str, what: str, suffixes: tuple[str, ...]) -> None:
    """Refuse, before any work, an output file ``path`` (of ``option``) whose suffix is none of
    ``suffixes``: the command writes ``what`` whatever the name (``--plot drive.csv`` was a PNG
    image named like a log, and with ``--overwrite`` it replaced the log)."""
    if Path(path).suffix.lower() not in suffixes:
        raise ValueError(f"{option} {path}: gyrocore writes {what} there, so its name must end in "
                         f"{' or '.join(suffixes)}")


def refuse_existing(outputs: Iterable[Path], overwrite: bool, *, folders_exist: bool = True) -> None:
    """Refuse, before any work, outputs whose folder is missing (unless the command makes it: not
    ``folders_exist``), and outputs that exist already unless ``--overwrite`` was given:
    nothing a user has is replaced without being asked (a dangling link counts, its target too).
    A folder where an output file goes is refused even with ``--overwrite``: the output could not
    be renamed over it, and that failed only once the work was done; so is a named pipe, socket
    or device (:func:`~gyrocore.io.atomic.check_replaceable`)."""
    outputs = list(outputs)
    for p in outputs:
        check_output_folder(p, made=not folders_exist)
        check_replaceable(p)
    folder = next((p for p in outputs if p.is_dir()), None)
    if folder is not None:
        raise IsADirectoryError(f"{folder}: a folder, where an output file goes; move it or write elsewhere "
                                "(--overwrite replaces files, never a folder; nothing was written)")
    if overwrite:
        return
    taken = [p for p in outputs if os.path.lexists(p)]
    if taken:
        raise already_there(taken, "--overwrite")


def _bounded(low: float, *, above: bool, integer: bool = False, infinite: bool = False) -> Callable[[str], float]:
    """An argparse ``type``: a finite number (an integer where ``integer``; also +inf where
    ``infinite``) above ``low``, or at least ``low``; argparse's error names the option, this one
    the value and the bound."""
    wanted = f"{'an integer' if integer else 'a finite number'} {'>' if above else '>='} {low:g}"
    wanted += " (or inf)" if infinite else ""

    def parse(text: str) -> float:
        try:
            value: float = int(text) if integer else float(text)
        except ValueError:
            value = math.nan
        if not ((math.isfinite(value) or (infinite and value == math.inf))
                and (value > low if above else value >= low)):
            raise argparse.ArgumentTypeError(f"must be {wanted}, got {text!r}")
        return value

    return parse


def finite(text: str) -> float:
    """An argparse ``type``: a finite number of either sign (a bias)."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text!r}")
    return value


def named(hint: str = "") -> Callable[[str], str]:
    """An argparse ``type`` for every option or argument that names a file or folder: a name that
    is empty or only spaces (an unset shell variable) is refused, where it was taken as the
    current folder (``process ""`` processed every log in it, ``--plot-dir ""`` wrote there) or
    made a folder named " "; ``hint`` says what to give instead."""

    def parse(text: str) -> str:
        if not text.strip():
            raise argparse.ArgumentTypeError(f"{text!r}: no name (an empty shell variable?)"
                                             + (f"; give {hint}" if hint else ""))
        return text

    return parse


def named_path(text: str) -> Path:
    """:func:`named` for an option read as a :class:`~pathlib.Path`."""
    return Path(named()(text))


#: The argparse type of a file or folder name (see :func:`named`).
NAME = named()


def bias_dps(text: str) -> float:
    """An argparse ``type``: a bias [deg/s] (``--bias-dps``) the core takes, finite and within
    its limit of a reading, said in deg/s (the core's own error named the parameter ``bias`` and
    its value and limit in rad/s, none of which the user gave)."""
    value = finite(text)
    limit = math.degrees(MAX_READING)
    if abs(value) > limit:
        raise argparse.ArgumentTypeError(f"must be at most {limit:.7g} deg/s in magnitude (2^20 rad/s, the limit of "
                                         f"a reading), got {text!r}")
    return value


#: argparse types of numeric options: checked as the command line is read, before any work.
POSITIVE = _bounded(0.0, above=True)
NON_NEGATIVE = _bounded(0.0, above=False)
COUNT = _bounded(1, above=False, integer=True)
SEED = _bounded(0, above=False, integer=True)
#: A time span that may be infinite (``--gap-limit inf``: no gap detection).
POSITIVE_OR_INF = _bounded(0.0, above=True, infinite=True)
BIAS_DPS = bias_dps


def print_json(data: Any) -> None:
    """Machine output on stdout: JSON has no inf or nan, written as null (``presets --json`` wrote
    ``Infinity``, which JSON.parse and other strict readers refuse)."""
    print(json.dumps(json_value(data), indent=2, allow_nan=False))


def warn(message: str) -> None:
    """One line on stderr: ``gyrocore: warning: ...``."""
    print(f"gyrocore: warning: {one_line(message)}", file=sys.stderr)


def note(message: str) -> None:
    """One line on stderr: ``gyrocore: note: ...``, of something the run did not use that the user
    may want (not a problem with the input, as a warning is)."""
    print(f"gyrocore: note: {one_line(message)}", file=sys.stderr)


def once_each(paths: Sequence[str], what: str, why: str,
              same: Callable[[str], str] = os.path.realpath) -> list[str]:
    """``paths`` with each file or folder once (also when named two ways, through a link or ``..``),
    warning of the others with ``why`` that matters (a log given twice to ``tune`` weighed twice in
    its mean over the drives; ``evaluate`` scored it twice). ``same`` gives what two of them share
    when they are one (:func:`str` for names that are no paths: a method given twice)."""
    seen: dict[str, str] = {}
    for p in paths:
        seen.setdefault(same(p), p)
    twice = [p for p in paths if p not in seen.values() or paths.count(p) > 1]
    if twice:
        warn(f"{', '.join(dict.fromkeys(twice))}: given more than once as {what}; each is used once ({why})")
    return list(seen.values())


def warn_about(path: str | Path, messages: Iterable[str]) -> None:
    """A file's warnings, each naming the file once (most of a report's warnings do not name it;
    those its reader raises do)."""
    for message in messages:
        warn(message if message.startswith(f"{path}: ") else f"{path}: {message}")


def show_warning(
    message: Warning | str, category: type[Warning], filename: str, lineno: int, file: Any = None, line: Any = None
) -> None:
    """``warnings.showwarning`` for the command line: the message alone, as :func:`warn` prints it
    (not Python's ``file:line: Category`` form, which points into the package). None once a
    signal came: the run then only says that it was interrupted, and a warning after the signal
    is one of its consequences (pandas 1.5's import cut short by it warned "Cython module failed
    to patch module with custom type")."""
    if not _signals.received():
        warn(str(message))


@contextmanager
def progress_bar(description: str) -> Iterator[Callable[[int, int | None, str], None]]:
    """A callback ``(done, total, unit)`` that draws a tqdm bar on stderr, only on a terminal
    (pipes, CI and logs get nothing)."""
    tqdm = tqdm_class() if sys.stderr.isatty() else None
    if tqdm is None:
        yield lambda done, total, unit: None
        return

    bar: Any = None

    def update(done: int, total: int | None, unit: str) -> None:
        nonlocal bar
        if bar is None:
            bar = tqdm(total=total, unit=unit, unit_scale=True, desc=description, leave=False)
        bar.update(done - bar.n)

    try:
        yield update
    finally:
        if bar is not None:
            bar.close()
