"""Every Python example in the README and in the docs pages runs as written (each in a fresh
interpreter, in a scratch folder beside a link to ../shared, as from a checkout)."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from .conftest import DATA

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
#: (page, its index-th Python block, the block's text), in page order.
EXAMPLES = [
    (page.relative_to(ROOT).as_posix(), index, code)
    for page in PAGES
    for index, code in enumerate(re.findall(r"```python\n(.*?)```", page.read_text(encoding="utf-8"), re.S))
]


def test_the_readme_and_the_docs_have_python_examples() -> None:
    readme = [e for e in EXAMPLES if e[0] == "README.md"]
    assert readme, "the README's front page has no Python example"
    # the README had 15 examples before its sections moved into docs/: none was lost on the way
    assert len(EXAMPLES) >= 16


@pytest.mark.parametrize(("page", "index", "code"), EXAMPLES, ids=[f"{p}-{i}" for p, i, _ in EXAMPLES])
def test_example_runs(page: str, index: int, code: str, tmp_path: Path) -> None:
    if not DATA.is_dir():
        pytest.skip(f"shared data not found at {DATA}")
    (tmp_path / "shared").symlink_to(DATA.parent, target_is_directory=True)
    work = tmp_path / "work"
    work.mkdir()
    script = work / f"example_{index}.py"
    script.write_text(code, encoding="utf-8")
    done = subprocess.run([sys.executable, script.name], cwd=work, capture_output=True, text=True, timeout=300)
    first_line = code.splitlines()[0]
    assert done.returncode == 0, f"{page} example {index} ({first_line}) failed:\n{done.stderr[-3000:]}"
    # an example is what a reader copies: it must not show a misuse (processing.md's batch gave the
    # first second of every real log as its rest, and 15 of them warned that the gyro turned in it)
    assert "does not look like a rest" not in done.stderr, f"{page} example {index} gives a rest that is none"


def _shown(page: str, expression: str) -> list[str]:
    """The pieces, between its "...", of the comment that ``page`` shows after ``print(expression)``."""
    text = (ROOT / page).read_text(encoding="utf-8")
    found = re.search(rf"^print\({re.escape(expression)}\)\s+#\s*(.*)$", text, re.M)
    assert found, f"{page} has no print({expression}) with its output"
    return [p.strip(" ,;") for p in found[1].split("...") if p.strip(" ,;")]


def _in_order(pieces: list[str], printed: str) -> None:
    at = 0
    for piece in pieces:
        at = printed.find(piece, at)
        assert at >= 0, f"shown {piece!r}, but it prints:\n{printed}"
        at += len(piece)


def test_the_calibration_page_shows_what_its_example_prints() -> None:
    # it showed a standard error of 1.89e-05 and a one-line noise summary the package never printed
    import gyrocore
    from gyrocore import allan, calibration

    from .conftest import real_log_path

    log = gyrocore.read_log(real_log_path("broad_10"))
    cal = calibration.static_bias(log.t, log.rate)
    _in_order(_shown("docs/calibration.md", "cal"), repr(cal))
    rest = (log.t >= cal.window[0]) & (log.t <= cal.window[1])
    noise = allan.noise_parameters(allan.deviation(log.rate[rest], 0.0035, taus="octave"))
    _in_order(_shown("docs/calibration.md", "noise"), str(noise))


def test_the_python_page_shows_what_its_examples_print() -> None:
    # its rest-tracking example showed end=29.5 where the rest ends at 29.49
    import numpy as np

    import gyrocore
    from gyrocore import datasets

    r = datasets.sample_drive().process()
    _in_order(_shown("docs/python.md", "r.bias_source"), str(r.bias_source))
    t = np.arange(0.0, 120.0, 0.01)
    rate = 0.01 + np.where((t > 50) & (t < 62), 0.0, 0.3 * np.sin(t / 3))
    whole = gyrocore.process(t, rate, "static_bias")
    _in_order(_shown("docs/python.md", "whole.bias_source"), str(whole.bias_source))
    t = np.arange(0, 60, 0.01)
    speed = np.where((t > 20) & (t < 30), 0.0, 5.0)
    rate = 0.003 + np.where(speed > 0, 0.1 * np.sin(t), 0.0)
    r = gyrocore.process(t, rate, "static_bias", mode="causal", bias=0.0, track_rests=True, speed=speed)
    _in_order(_shown("docs/python.md", "r.tracked_rests"), repr(r.tracked_rests))


def test_the_python_page_says_what_the_result_holds_and_plots_it() -> None:
    # it never said the heading's unit, that it is continuous, nor how to plot it beside a reference
    text = " ".join((ROOT / "docs" / "python.md").read_text(encoding="utf-8").split())
    assert "`heading` [rad] (float64, counter-clockwise positive, continuous" in text
    assert "`heading_deg` the same in degrees" in text
    assert any("plt.savefig(" in code and "r.heading_deg" in code for page, _, code in EXAMPLES
               if page == "docs/python.md")


@pytest.mark.parametrize("page", ["python", "processing", "reading-logs", "evaluation", "calibration"])
def test_a_guide_page_that_reads_the_real_logs_says_what_to_use_without_them(page: str) -> None:
    # the first example of each read ../shared/data/real/..., which a user of the package does not have
    text = " ".join((ROOT / "docs" / f"{page}.md").read_text(encoding="utf-8").split())
    before = text[: text.index("```")]
    assert "../shared/data/real" in text
    assert "the project's test data, not part of the package" in before
    assert "python -m gyrocore.datasets sample_drive" in before


def test_the_python_page_shows_what_its_table_example_scores() -> None:
    # it showed raw 214.115 and recommended 4.373 deg where the example printed 214.116 and 4.337,
    # and said 213.688 for the log without a rest window, which scores 213.689
    import warnings

    import gyrocore
    from gyrocore import datasets

    sample = datasets.sample_drive()
    rows = gyrocore.evaluate.compare([gyrocore.Log("drive 3", sample.t, sample.rate, t_ref=sample.t_ref,
                                                   heading_ref=sample.heading_ref, stationary=(0.0, 60.0))],
                                     ["raw", "recommended"])
    _in_order(_shown("docs/python.md", "rows"), repr(rows))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gyrocore.InputWarning)
        raw, recommended = gyrocore.evaluate.compare(
            [gyrocore.Log("drive 3", sample.t, sample.rate, t_ref=sample.t_ref, heading_ref=sample.heading_ref)],
            ["raw", "recommended"])
    text = " ".join((ROOT / "docs" / "python.md").read_text(encoding="utf-8").split())
    assert (f"`recommended` scores {recommended.errors.e_psi_deg:.3f} deg, about raw integration's "
            f"{raw.errors.e_psi_deg:.3f}") in text


def test_the_python_page_shows_what_its_first_and_whole_mode_examples_print() -> None:
    # what a result and a score print, and the two headings at 50 s, were shown but never checked
    import numpy as np

    import gyrocore

    from .conftest import real_log_path

    log = gyrocore.read_log(real_log_path("f110_ds3"))
    result = log.process("recommended")
    _in_order(_shown("docs/python.md", "result"), repr(result))
    text = " ".join((ROOT / "docs" / "python.md").read_text(encoding="utf-8").split())
    shown = re.search(r"\(`(HeadingResult\(.*?), \.\.\.\)`\)", text)
    assert shown and repr(result).startswith(shown[1]), (shown, repr(result))
    score = re.search(r"\(`(Score\('f110_ds3'.*?), \.\.\.\)`\)", text)
    assert score and repr(gyrocore.evaluate.compare([log], ["recommended"])[0]).startswith(score[1])
    t = np.arange(0.0, 120.0, 0.01)
    rate = 0.01 + np.where((t > 50) & (t < 62), 0.0, 0.3 * np.sin(t / 3))
    whole = gyrocore.process(t, rate, "static_bias")
    causal = gyrocore.process(t, rate, "static_bias", bias_window=(50.0, 62.0), mode="causal")
    pieces = _shown("docs/python.md", "whole.heading[5000], causal.heading[5000]")
    assert re.findall(r"\d+\.\d+", pieces[0])[:2] == [f"{whole.heading[5000]:.3f}", f"{causal.heading[5000]:.3f}"]
    true = float(np.sum(np.diff(t[:5001]) * (0.3 * np.sin(t[:5000] / 3) + 0.3 * np.sin(t[1:5001] / 3)) / 2))
    assert abs(whole.heading[5000] - true) < 1e-9 and abs(causal.heading[5000] - whole.heading[5000] - 0.5) < 0.01


def test_the_site_s_front_page_makes_the_readme_s_promises() -> None:
    # docs/index.md kept "pays for one output array" after the result began to hold its own copy
    # of the times, which the README had been corrected to say
    def bullets(page: str) -> list[str]:
        text = (ROOT / page).read_text(encoding="utf-8")
        found = re.findall(r"^- \*\*\w+\*\*:.*?(?=\n(?:- |\n))", text, re.M | re.S)
        return [" ".join(b.split()).replace("](docs/", "](") for b in found[:3]]

    readme, index = bullets("README.md"), bullets("docs/index.md")
    assert len(readme) == 3 and [b[:12] for b in readme] == ["- **Python**", "- **Rust**: ", "- **Speed**:"]
    assert [re.sub(r"\[[^]]*\]\(", "(", b) for b in readme] == [re.sub(r"\[[^]]*\]\(", "(", b) for b in index]
