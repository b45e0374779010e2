"""The ``gyrocore`` command line: one entry point, one module per subcommand.

A subcommand module has ``register(sub)``, which adds its parser with ``_common.add_command``;
add the module to ``COMMANDS`` below.
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings
from typing import Any, NoReturn, Sequence

from .. import _signals
from .._checks import did_you_mean
from .._gyrocore import __version__
from . import allan, calibrate, demo, evaluate, presets, process, reproduce, simulate, tune
from ..batch_run import BatchInterrupted
from ..tune import TuningInterrupted
from ..io._paths import error_text, one_line
from ..io.atomic import discard_all, outputs_checked
from ._common import SAMPLE_LOG_NOTE, USER_ERRORS, show_warning

COMMANDS = (demo, process, presets, allan, calibrate, evaluate, tune, simulate, reproduce)


class _StoreOnce(argparse._StoreAction):
    """argparse's store of an option's value, which refuses the option given twice: argparse kept
    the last without a word (``process --params a.json --params b.json`` ran b.json alone, ``tune
    --preset hdr --preset combined`` fitted combined); options meant to be repeated append."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: Any,
                 option_string: str | None = None) -> None:
        stored = parser._stored if isinstance(parser, _Parser) else set()
        if self.dest in stored:
            earlier = getattr(namespace, self.dest)
            raise argparse.ArgumentError(self, f"given twice ({_shown(earlier)}, then {_shown(values)}); give it once")
        stored.add(self.dest)
        setattr(namespace, self.dest, values)


def _shown(value: Any) -> str:
    return " ".join(map(str, value)) if isinstance(value, list) else str(value)


class _Parser(argparse.ArgumentParser):
    """argparse's parser, whose "invalid choice" (a command, ``--heading``, ``--format``, ...) and
    "unrecognized arguments" say which choice or option a typo is likely of, as the package's own
    errors do; an unknown option is refused by its command's parser, with that command's usage
    (the top parser's named neither); an option that takes one value refuses a second
    (:class:`_StoreOnce`)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        for name in (None, "store"):  # an option without an action stores its value
            self.register("action", name, _StoreOnce)
        self._stored: set[str] = set()  # the options stored in this parse (_StoreOnce)
        self._args: list[str] = []

    def parse_known_args(self, args: Sequence[str] | None = None, namespace: Any = None) -> Any:  # type: ignore[override]
        self._stored = set()
        self._args = list(sys.argv[1:] if args is None else args)  # for error(): what was typed
        return super().parse_known_args(args, namespace)

    def error(self, message: str) -> NoReturn:
        commands = self._commands()
        if commands and message == "the following arguments are required: command":
            # argparse asks for a command before it looks at the options: `gyrocore --verison`
            # said only that a command was required, and `gyrocore` alone not which there are
            options = [o for action in self._actions for o in action.option_strings]
            typed = [a for a in self._args if a.startswith("-")]
            hints = "".join(did_you_mean(a.split("=")[0], options) for a in typed)
            told = f"unrecognized arguments: {' '.join(typed)}{hints}; " if typed else ""
            message = (f"{told}give a command: {', '.join(commands)} (gyrocore --help says what each does, "
                       "gyrocore COMMAND --help its options)")
        super().error(message)

    def _commands(self) -> list[str]:
        """The names of this parser's commands (none for a command's own parser)."""
        return [name for action in self._actions if isinstance(action, argparse._SubParsersAction)
                for name in action.choices]

    def parse_args(self, args: Sequence[str] | None = None, namespace: Any = None) -> Any:  # type: ignore[override]
        namespace, extras = self.parse_known_args(args, namespace)
        if extras:
            parser = self._command_parser(namespace)
            options = [o for action in parser._actions for o in action.option_strings]
            hints = "".join(did_you_mean(e.split("=")[0], options) for e in extras if e.startswith("-"))
            parser.error(f"unrecognized arguments: {' '.join(extras)}{hints}")
        return namespace

    def _command_parser(self, namespace: Any) -> argparse.ArgumentParser:
        """The parser of the command ``namespace`` holds (this one without a command)."""
        for action in self._actions:
            command = getattr(namespace, action.dest, None)
            if isinstance(action, argparse._SubParsersAction) and command in action.choices:
                parser: argparse.ArgumentParser = action.choices[command]
                return parser
        return self

    def _check_value(self, action: argparse.Action, value: Any) -> None:
        if action.choices is not None and value not in action.choices:
            choices = [str(c) for c in action.choices]
            raise argparse.ArgumentError(action, f"invalid choice: {value!r}{did_you_mean(value, choices)} "
                                                 f"(choose from {', '.join(map(repr, choices))})")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="gyrocore", description="Drift-free heading from a yaw-rate gyro.",
                     epilog=f"The examples read {SAMPLE_LOG_NOTE}.")
    # what a bug report asks for first; it was "the following arguments are required: command"
    parser.add_argument("--version", action="version", version=f"gyrocore {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    for command in COMMANDS:
        command.register(sub)
    return parser


#: Options whose value may begin with ``-`` (an axis such as ``-x``), which argparse would take
#: for an option of its own.
SIGNED_VALUES = ("--up",)


def attach_signed_values(argv: Sequence[str]) -> list[str]:
    """``--up -x`` as ``--up=-x``: the value that follows an option of :data:`SIGNED_VALUES` is
    its value, whatever it begins with."""
    out: list[str] = []
    args = iter(argv)
    for arg in args:
        value = next(args, None) if arg in SIGNED_VALUES else None
        out.append(arg if value is None else f"{arg}={value}")
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command; user errors print one line ``gyrocore: error: ...`` and return 2, warnings
    one line ``gyrocore: warning: ...``; a closed pipe on stdout returns 141 quietly; Ctrl-C or
    SIGTERM, whenever it comes, returns 130 with every output as it was before the run."""
    with _signals.handled():
        try:
            args = build_parser().parse_args(attach_signed_values(sys.argv[1:] if argv is None else argv))
            # every command refuses its outputs that exist before its work (refuse_existing):
            # one found when it is written was written meanwhile, and is refused as such
            with warnings.catch_warnings(), outputs_checked("--overwrite"):
                warnings.showwarning = show_warning
                return int(args.func(args))
        except BrokenPipeError:
            # The reader went away (`gyrocore ... | head`): what was asked is done, and the
            # report has no one to read it. Quiet, with the shell's code for SIGPIPE.
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            return 141
        except USER_ERRORS as e:
            print(f"gyrocore: error: {one_line(error_text(e))}", file=sys.stderr)
            return 2
        except KeyboardInterrupt as e:
            discard_all()
            finished = ""
            if isinstance(e, BatchInterrupted) and str(e):  # their outputs are complete: no need to redo them
                finished = (f"; {e}; to go on, run it again with --skip-existing: it processes only the inputs "
                            "without an output")
            elif isinstance(e, TuningInterrupted):  # minutes of fitting: its best, to hold with --set
                finished = f"; {e}"
            print(f"gyrocore: interrupted; no partial output was left{finished}", file=sys.stderr)
            return 130


def run() -> None:
    """The ``gyrocore`` program: :func:`main` with the process's arguments, then exit with its code.

    After an interrupt the process ends with ``os._exit(130)``: CPython otherwise kills itself
    with SIGINT at exit, whatever the exit code, once a KeyboardInterrupt has passed through an
    ``eval`` (``collections.namedtuple`` builds classes with one, so an import that a Ctrl-C
    interrupts can do it)."""
    code = main()
    if code == 130:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    sys.exit(code)
