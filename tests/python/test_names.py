"""A name that is not one of its choices (a preset, a parameter, a mode, a sensor, ...) is refused
in one form, with the choice it is a likely typo of: `unknown preset 'recomended' (did you mean
'recommended'?); choose one of ...`."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import gyrocore
from gyrocore import io, sim, tune
from gyrocore.motion_roads import car

from .conftest import gyrocore_cli

T, RATE = np.arange(3) * 0.01, np.zeros(3)


@pytest.mark.parametrize("call, said", [
    (lambda: gyrocore.Pipeline("recomended"), "unknown preset 'recomended' (did you mean 'recommended'?); choose one of raw,"),
    (lambda: gyrocore.Pipeline("HDR"), "unknown preset 'HDR' (did you mean 'hdr'?); choose one of"),
    (lambda: gyrocore.Pipeline("fast"), "unknown preset 'fast'; choose one of"),
    (lambda: gyrocore.process(T, RATE, "hdr", bias=0.0, lowpas_tau=1.0),
     "unknown parameter 'lowpas_tau' (did you mean 'lowpass_tau'?); valid names: bias,"),
    (lambda: gyrocore.Pipeline("hdr", bias=0.0, hdr_c=1.0), "unknown parameter 'hdr_c'; valid names"),  # c1 or c2?
    (lambda: gyrocore.process(T, RATE, "raw", mode="casual"), "unknown mode 'casual' (did you mean 'causal'?); choose one of whole, causal"),
    (lambda: sim.sensor("crs3"), "unknown sensor 'crs3' (did you mean 'crs03'?); choose one of"),
    (lambda: io.ReadOptions(time_unit="sek"), "unknown time_unit 'sek'"),
    (lambda: io.ReadOptions(rate_unit="dge/s"), "unknown rate_unit 'dge/s' (did you mean 'deg/s'?)"),
    (lambda: gyrocore.process(T, RATE, "raw").output("headings"), "unknown output 'headings' (did you mean 'heading'?)"),
    (lambda: io.HeadingWriter("h.csv", heading="compas"), "unknown heading convention 'compas' (did you mean 'compass'?); choose one of enu, compass"),
    (lambda: car(60.0, mix="downtwn"), "unknown road mix 'downtwn' (did you mean 'downtown'?)"),
    (lambda: tune.search_box("hdr", ["hdr_incremnt"]), "unknown parameter(s) hdr_incremnt (did you mean 'hdr_increment'?); the pipeline's are"),
])
def test_an_unknown_name_is_refused_with_the_choice_it_is_a_typo_of(call: Callable[[], object], said: str) -> None:
    with pytest.raises(ValueError) as e:
        call()
    assert str(e.value).startswith(said), str(e.value)


def test_a_name_that_is_no_text_is_refused_as_such() -> None:
    # a one-element array of "whole" compared equal to "whole" and passed
    for value in (np.array(["whole"]), None, 3):
        with pytest.raises(TypeError, match=r"^mode must be a name, one of whole, causal; got "):
            gyrocore.process(T, RATE, "raw", mode=value)  # type: ignore[arg-type]


@pytest.mark.parametrize("argv, said", [
    (["prcess"], "argument command: invalid choice: 'prcess' (did you mean 'process'?) (choose from 'demo', 'process',"),
    (["simulate", "--sensor", "crs3"], "argument --sensor: invalid choice: 'crs3' (did you mean 'crs03'?) (choose from"),
    (["zz"], "argument command: invalid choice: 'zz' (choose from 'demo',"),
])
def test_a_command_line_choice_says_which_one_a_typo_is_likely_of(argv: list[str], said: str) -> None:
    proc = gyrocore_cli(*argv, code=2)
    assert said in proc.stderr, proc.stderr


def test_an_unknown_option_is_refused_by_its_command_with_the_option_it_is_a_typo_of(tmp_path: Path) -> None:
    proc = gyrocore_cli("process", tmp_path / "log.csv", "--out", tmp_path / "h.csv", "--bias-windw", "0", "1", code=2)
    assert proc.stderr.splitlines()[-1] == ("gyrocore process: error: unrecognized arguments: --bias-windw 0 1 "
                                            "(did you mean '--bias-window'?)")
    assert proc.stderr.startswith("usage: gyrocore process")
    assert gyrocore_cli("process", "x.csv", "-o", "h.csv", "--xyz", code=2).stderr.splitlines()[-1] == (
        "gyrocore process: error: unrecognized arguments: --xyz")


def test_no_command_names_the_commands_and_a_mistyped_option_before_one() -> None:
    # both said only "the following arguments are required: command"
    commands = "demo, process, presets, allan, calibrate, evaluate, tune, simulate, reproduce"
    assert gyrocore_cli(code=2).stderr.splitlines()[-1] == (
        f"gyrocore: error: give a command: {commands} (gyrocore --help says what each does, gyrocore COMMAND "
        "--help its options)")
    assert gyrocore_cli("--verison", code=2).stderr.splitlines()[-1].startswith(
        "gyrocore: error: unrecognized arguments: --verison (did you mean '--version'?); give a command: demo, ")
