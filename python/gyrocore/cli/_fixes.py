"""Heading fixes on the command line: ``--fixes FILE``, ``--no-fixes`` (``gyrocore process`` and
``evaluate``) and ``--sim-fixes SPEC`` (``evaluate``); docs/fixes.md."""

from __future__ import annotations

import argparse
import os
import re
import warnings
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TypeVar

from .._checks import InputWarning
from .._fixes_eval import FixScore, SimFixes, format_fix_scores, score_with_fixes
from ..evaluate import Failed, Method, named_error
from ..evaluate_compare import naming_log
from ..fixes import Fixes, read_fixes_file
from ..io import Log
from ..io._logfolder import FIXES_CSV, GNSS_CSV
from ..io._paths import has_file
from ._common import NAME, each_log, exit_code, note, print_failures, print_json, warn

FIXES_HELP = (
    "absolute headings fused with the gyro (docs/fixes.md): a CSV with columns t [s], heading [rad, CCW from "
    f"east], sigma [rad], or a gnss.csv (t, speed [m/s], bearing [deg, CW from north]); default: a log folder's {FIXES_CSV}"
)


def add_fix_options(parser: argparse.ArgumentParser, *, evaluate: bool) -> None:
    """``--fixes``, ``--no-fixes`` and, for ``evaluate``, ``--sim-fixes``."""
    group = parser.add_argument_group("heading fixes").add_mutually_exclusive_group()
    group.add_argument("--fixes", type=NAME, metavar="FILE", help=FIXES_HELP)
    if evaluate:
        group.add_argument(
            "--sim-fixes",
            metavar="SPEC",
            help="SIMULATED fixes from each log's reference: rate=HZ,sigma_deg=DEG[,outage=START:LENGTH][,seed=N] "
            "(START seconds after the first sample; defaults rate=1, sigma_deg=1, seed=0; each log's noise has "
            "its own seed, from N and the log's name, which the report gives); E_psi inside the outage is "
            "reported apart",
        )
    group.add_argument("--no-fixes", action="store_true", help=f"ignore a log folder's {FIXES_CSV}")


def fixes_wanted(args: argparse.Namespace, folders: Sequence[str | Path]) -> bool:
    """Whether ``evaluate`` scores with fixes: given, simulated, or the ``fixes.csv`` of one of the
    log ``folders``."""
    if args.no_fixes:
        return False
    return args.fixes is not None or args.sim_fixes is not None or any(has_file(Path(f) / FIXES_CSV) for f in folders)


def evaluate_with_fixes(args: argparse.Namespace, logs: Sequence[str | Failed], methods: Sequence[Method],
                        read: Callable[[str], Log]) -> int:
    """``gyrocore evaluate`` with fixes: the table of :func:`gyrocore._fixes_eval.format_fix_scores`;
    ``logs`` the paths of the logs, each ``read`` as its turn comes, or failed already."""
    if args.fixes is not None and len(logs) != 1:
        raise ValueError(f"--fixes {args.fixes} is for one log, got {len(logs)}; give each log folder its {FIXES_CSV}")
    if args.plot_dir:
        raise ValueError("--plot-dir draws no plots with fixes; leave it out, or pass --no-fixes")
    sim = None if args.sim_fixes is None else SimFixes.parse(args.sim_fixes)
    given = None if args.fixes is None else read_fixes_file(args.fixes)
    run = {"bias_duration": args.bias_duration, "mode": "causal" if args.causal else "whole",
           "use_speed": not args.no_speed}

    def score(path: str) -> list[FixScore]:
        log = read(path)  # one log in memory at a time
        try:
            fixes, label, window = _fixes_of(log, sim, given, args.fixes)
            with input_warnings() as messages:
                rows = score_with_fixes(log, methods, fixes, label, window, **run)
        except ValueError as e:
            raise named_error(log, e) from None
        for message in messages:
            warn(naming_log(log, message))
        return rows

    rows = each_log(logs, score, alone=len(logs) == 1)
    if args.json:
        print_json([r.as_dict() for r in rows])
    else:
        format_fix_scores(rows)
        print_failures(rows, len(logs))
    return exit_code(rows)


@contextmanager
def input_warnings() -> Iterator[list[str]]:
    """The messages of the warnings raised inside (every :class:`~gyrocore.InputWarning`, though
    each method run on a log repeats it), each once, for the caller to print with the log's name;
    the same message of several presets once, naming them all (:func:`merged_by_preset`), and
    one whose figures differ among the methods once, with their ranges (:func:`merged_by_count`)."""
    messages: list[str] = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", InputWarning)
        yield messages
    messages += merged_by_preset(merged_by_count(list(dict.fromkeys(str(w.message) for w in caught))))


#: A figure in a warning's text (a count, a ratio, ``1e-05``), with its sign: two negative ones,
#: their minus left in the text, gave a range of -0.0018 to 0.005 for -0.0018 and -0.005.
_FIGURE = re.compile(r"-?\d+(?:\.\d+)?(?:e[+-]?\d+)?")


def merged_by_count(messages: list[str]) -> list[str]:
    """``messages`` with those that differ only in their figures said once, each figure that
    differs as the range of them: each method's corrected rate runs a fix stage of its own, and
    `gyrocore evaluate` said "N time(s) ... took them in again" once for each different N of its
    methods (4 times on a log), and the gate's and the fit's warnings as often, each with the
    same list of causes."""
    def ranged(column: tuple[str, ...]) -> str:
        low, high = min(column, key=float), max(column, key=float)
        return low if float(low) == float(high) else f"{low} to {high}"

    def join(m: str, _kind: str, found: list[list[str]]) -> str:
        ranges = [ranged(column) for column in zip(*found)]
        return "".join(text + figure for text, figure in zip(_FIGURE.split(m), ranges + [""]))

    return _merged(messages, lambda m: (_FIGURE.sub("#", m), _FIGURE.findall(m)), join)


#: A message one preset gives of itself (``preset 'hdr' removes a static bias, but ...``).
_OF_PRESET = re.compile(r"preset '([^']+)' removes (.*)", re.DOTALL)


def merged_by_preset(messages: list[str]) -> list[str]:
    """``messages`` with those that differ only in the preset they name said once, naming every
    preset: `gyrocore evaluate` runs six presets that remove a static bias, and a log without a
    rest printed the same two lines of warning six times."""
    def split(m: str) -> tuple[str, str] | None:
        match = _OF_PRESET.fullmatch(m)
        return None if match is None else (match.group(2), match.group(1))

    def join(m: str, removes: str, names: list[str]) -> str:
        listed = ", ".join(f"'{n}'" for n in names[:-1]) + f" and '{names[-1]}'"
        return f"presets {listed} remove {removes}"

    return _merged(messages, split, join)


_Part = TypeVar("_Part")


def _merged(messages: list[str], split: Callable[[str], tuple[str, _Part] | None],
            join: Callable[[str, str, list[_Part]], str]) -> list[str]:
    """``messages`` with those of one kind said once, where the first of them was: ``split(m)``
    gives a message's kind and its own part (None: a message of no kind, kept as it is), and
    ``join(first, kind, parts)`` says every message of a kind in one, given each one's part."""
    parts = [split(m) for m in messages]
    kinds: dict[str, list[_Part]] = {}
    for part in parts:
        if part is not None:
            kinds.setdefault(part[0], []).append(part[1])
    said = []
    for m, part in zip(messages, parts):
        if part is None:
            said.append(m)
        elif (group := kinds.pop(part[0], None)) is not None:  # the later ones: said with the first
            said.append(m if len(group) == 1 else join(m, part[0], group))
    return said


def _fixes_of(log: Log, sim: SimFixes | None, given: Fixes | None,
              path: str | None) -> tuple[Fixes, str, tuple[float, float] | None]:
    """The fixes ``log`` is scored with, how to name them, and the simulated outage."""
    if sim is not None:
        return sim.fixes(log), sim.describe(log), sim.window(log)
    if given is not None:
        return given, f"{path} (as given)", None
    assert log.fixes is not None  # fixes_wanted
    return log.fixes, f"{Path(log.path or log.name) / FIXES_CSV} (as given)", None


def any_fixes_csv(args: argparse.Namespace, inputs: Sequence[Path]) -> bool:
    """Whether a log folder among ``inputs`` has a ``fixes.csv`` that is used (no ``--no-fixes``)."""
    # os.path.isfile is False in a folder this user may not enter, which reading it then names
    return not args.no_fixes and any(os.path.isfile(p / FIXES_CSV) for p in inputs)


def note_unused_gnss(args: argparse.Namespace, folders: Sequence[str | Path], apart: str = "") -> None:
    """A note on stderr, once per log folder among ``folders`` that has a ``gnss.csv`` and no
    ``fixes.csv``, naming the option that fuses it, unless fixes are given or refused
    (``--fixes``, ``--sim-fixes``, ``--no-fixes``): such a folder was run without its GNSS and
    without a word (comma_seg40 scores 116 deg E_psi without the fixes of its receiver, 0.9 with).
    ``apart``: how a run takes ``--fixes`` where this one cannot (``FOLDER`` stands for the log),
    empty where it can as it is."""
    if args.fixes is not None or args.no_fixes or getattr(args, "sim_fixes", None) is not None:
        return
    for folder in dict.fromkeys(map(Path, folders)):
        # os.path.isfile is False in a folder this user may not enter, whose reading names it
        if not os.path.isfile(folder / GNSS_CSV) or os.path.lexists(folder / FIXES_CSV):
            continue
        how = f" ({apart.replace('FOLDER', str(folder))})" if apart else ""
        note(f"{folder}: the log folder has a {GNSS_CSV}, which is not used: --fixes {folder / GNSS_CSV} fuses its "
             f"course over ground with the gyro as heading fixes{how}; --no-fixes runs without them and says nothing of it")
