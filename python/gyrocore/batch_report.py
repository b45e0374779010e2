"""What a batch reports: one :class:`FileReport` per input (what was read and written, the bias
used, what the input policy repaired, why a file failed) and the batch's :class:`BatchReport`."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass
from typing import Any

from . import rests, wholelog
from ._gap_turn import gap_turn_text
from .io._paths import one_line


@dataclass(frozen=True)
class FileReport:
    """What happened to one input.

    Attributes:
        input: the input path.
        output: the heading table written, or None if the file failed.
        rows_in: samples read (for a file that fails at a bad sample, the samples before it,
            whatever ``chunk_rows``; for other failures, up to the last chunk read).
        rows_out: rows written (equal to ``rows_in`` for a file that succeeded; 0 if it failed).
        seconds: wall time.
        error: why the file failed, or None.
        warnings: what looked wrong but was processed (units, a missing rest window, repairs).
        bias_source: where the static bias came from (None if the file failed).
        rests: the rests whose bias was used in whole mode.
        held, skipped: readings not finite or beyond +-2^20 that the input policy held or skipped
            (``nonfinite``); 0 if the file failed.
        gaps, longest_gap: intervals longer than ``gap_limit``, bridged or reset (``gap_action``),
            and the longest [s]; 0 if the file failed. These four are named as the keys of
            :attr:`gyrocore.Pipeline.report`, and said in the warnings too.
        gap_turn: the change of the heading written across the longest gap [rad], which the
            pipeline made up from the readings at its ends (None without a gap).
        output_existed: the file was skipped, not processed: its output existed already
            (``skip_existing``).
        fixes: for a log fused with heading fixes (a log folder's ``fixes.csv``, or those given),
            the fix stage's counts (:attr:`gyrocore.fixes.FusionResult.counts`); None without.
        fixes_file: where those fixes came from (a file, or ``given`` for fixes in memory).
    """

    input: str
    output: str | None
    rows_in: int
    rows_out: int
    seconds: float
    error: str | None = None
    warnings: tuple[str, ...] = ()
    bias_source: str | None = None
    rests: tuple[wholelog.Rest, ...] = ()
    held: int = 0
    skipped: int = 0
    gaps: int = 0
    longest_gap: float = 0.0
    gap_turn: float | None = None
    output_existed: bool = False
    fixes: Mapping[str, int] | None = None
    fixes_file: str | None = None

    @property
    def ok(self) -> bool:
        """Whether the file was processed completely (by this run: not a file skipped)."""
        return self.error is None and not self.output_existed

    def as_dict(self) -> dict[str, Any]:
        """Plain data for JSON."""
        return {
            **asdict(self),
            "warnings": list(self.warnings),
            "rests": [r.as_dict() for r in self.rests],
            "fixes": None if self.fixes is None else dict(self.fixes),
            "ok": self.ok,
        }

    def __str__(self) -> str:
        # one line per file, as a FAILED line is: a line break in a name (a\nb.csv) split it, and
        # the name's second half read as a line of its own
        if self.output_existed:
            return one_line(f"skipped {self.input}: {self.output} exists already")
        if not self.ok:
            return failed_line(self.input, self.error or "")
        lines = [one_line(
            f"ok     {self.input}: {self.rows_in} rows in, {self.rows_out} out -> {self.output} ({self.seconds:.2f} s)"
        )]
        policy = input_repairs(vars(self))
        if policy:  # also among the warnings, on stderr: the report is the file's record, kept with its output
            lines.append(f"       input policy: {'; '.join(policy)}")
        lines.append(f"       bias: {self.bias_source}")
        lines += rests.rest_lines(self.bias_source or "", self.rests, " " * 9)
        if self.fixes is not None:
            lines.append(f"       fixes from {self.fixes_file}: {', '.join(f'{k} {v}' for k, v in self.fixes.items())}")
        return "\n".join(lines)


def failed_line(input: str, error: str) -> str:
    """How a run over many inputs reports one that failed: ``FAILED <input>: <reason>``, the input
    named once (most reasons name it already)."""
    return one_line(f"FAILED {error}" if input in error else f"FAILED {input}: {error}")


@dataclass(frozen=True, repr=False)
class BatchReport:
    """The reports of a batch, in the order of the inputs."""

    files: tuple[FileReport, ...]
    seconds: float

    @property
    def succeeded(self) -> tuple[FileReport, ...]:
        """The files processed completely."""
        return tuple(r for r in self.files if r.ok)

    @property
    def failed(self) -> tuple[FileReport, ...]:
        """The files that failed, with their reason."""
        return tuple(r for r in self.files if r.error is not None)

    @property
    def skipped(self) -> tuple[FileReport, ...]:
        """The files not processed, since their outputs existed already."""
        return tuple(r for r in self.files if r.output_existed)

    @property
    def rows_in(self) -> int:
        """Samples read, over the files processed: a failed file's rows before its error (each
        file's own report has them) made "rows in" more than "out" for no row lost."""
        return sum(r.rows_in for r in self.succeeded)

    @property
    def rows_out(self) -> int:
        """Rows written, over the files processed."""
        return sum(r.rows_out for r in self.succeeded)

    def as_dict(self) -> dict[str, Any]:
        """Plain data for JSON."""
        return {
            "ok": len(self.succeeded),
            "failed": len(self.failed),
            "skipped": len(self.skipped),
            "rows_in": self.rows_in,
            "rows_out": self.rows_out,
            "seconds": self.seconds,
            "files": [r.as_dict() for r in self.files],
        }

    def __str__(self) -> str:
        return "\n".join([*(str(r) for r in self.files), self._summary()])

    def __repr__(self) -> str:
        """One line however many files (a notebook shows it): ``print`` the report for each file's."""
        return f"BatchReport({self._summary()}; print() it for each file, .files for their reports)"

    def _summary(self) -> str:
        skipped = f", {len(self.skipped)} skipped (their outputs exist already)" if self.skipped else ""
        return (f"{len(self.succeeded)} of {len(self.files)} files processed{skipped}, {len(self.failed)} failed; "
                f"{self.rows_in} rows in, {self.rows_out} out, {self.seconds:.2f} s")


def input_repairs(report: Mapping[str, Any]) -> list[str]:
    """What the pipeline's input policy repaired (NaN readings held or skipped, gaps), from its
    :attr:`~gyrocore.Pipeline.report` or a file's report: the warnings and the ok line say the same."""
    notes = []
    if report["held"]:
        notes.append(f"{int(report['held'])} reading(s) not finite or beyond +-2^20 replaced by the last usable one")
    if report["skipped"]:
        # under nonfinite='hold' (some were held) the core skips those before the first usable
        # reading: there is none to hold yet
        before = ", before the first usable one: none to hold yet" if report["held"] else ""
        notes.append(
            f"{int(report['skipped'])} sample(s) skipped "
            f"(readings not finite or beyond +-2^20{before}; their rows have a NaN rate)"
        )
    if report["gaps"]:
        notes.append(f"{int(report['gaps'])} gap(s), the longest {report['longest_gap']:.6g} s"
                     + gap_turn_text(report.get("gap_turn")))
    return notes
