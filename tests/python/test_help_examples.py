"""The example at the end of each command's ``--help`` runs as written for a user who has only
the package: a log it reads is the sample log, which the help says how to write, not a file of
the project's own test data."""

from __future__ import annotations

import argparse
import shlex
from pathlib import Path

import pytest

from gyrocore import datasets
from gyrocore.cli import build_parser, main


def helps() -> dict[str, str]:
    """Each subcommand's ``--help``, its lines joined as one."""
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return {name: " ".join(command.format_help().split()) for name, command in sub.choices.items()}


def example(command: str) -> str:
    text = helps()[command]
    return text[text.index("example: ") + len("example: "):].split(" (", 1)[0]


def test_no_example_reads_a_file_the_package_does_not_make() -> None:
    for name, text in helps().items():
        assert "../" not in text and "shared/data" not in text, name


@pytest.mark.parametrize("command", ["process", "allan", "calibrate", "evaluate"])
def test_the_example_of_a_command_that_reads_a_log_runs_on_the_sample_log(
    command: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    assert "(sample_drive: the sample log folder that python -m gyrocore.datasets sample_drive writes)" in (
        helps()[command])
    monkeypatch.chdir(tmp_path)
    assert datasets.main(["sample_drive"]) == 0
    args = shlex.split(example(command))
    assert args[:2] == ["gyrocore", command], args
    assert main(args[1:]) == 0, capsys.readouterr().err
