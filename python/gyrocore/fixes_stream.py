"""What a stream of gyro blocks keeps of the heading fixes it was given between blocks: the last
fix (which may still wait for its samples, so a block that gives it again is refused), and what it
says of fixes that arrive late or far ahead. :class:`gyrocore.Pipeline` and
:class:`gyrocore.fixes.Fusion` share it."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from ._checks import warn

if TYPE_CHECKING:
    from . import _gyrocore
    from .fixes import Fixes, FixesLike


#: The core's words for a fix given after a sample past its time was processed.
_LATE = "comes before the last gyro sample processed"


def say_how_to_wait(error: ValueError) -> None:
    """Adds to the core's error about a late fix what a live stream does about one: a receiver
    delivers its fix after the gyro samples of its time came (its latency), and the core's words
    (pass it with the block that reaches its time) did not say that this means holding the gyro's
    samples back."""
    if _LATE in str(error):
        error.args = (f"{error}. A fix that arrives after the samples of its time (a receiver's latency) is used "
                      "only if the gyro is held back that long: process the samples up to the newest sample's "
                      "time less the latency, with every fix received, and keep the others for the next block "
                      "(docs/fixes_results.md, \"Fixes that arrive late\"); or leave such a fix out. Nothing of this "
                      "block was processed",)


#: How fixes on another clock are put on the gyro's, in the warnings of fixes outside a log or far
#: ahead of a stream: receivers and read_nmea give UTC (Unix) seconds, a gyro mostly counts from
#: its start or its boot.
ON_GYRO_CLOCK = ("give the fixes' times on the gyro's clock, in seconds: from fixes in UTC (Unix) seconds, as read_nmea "
                 "gives them, subtract the UTC time at which the gyro's clock read 0 (Fixes(f.t - t0, f.heading, "
                 "f.sigma))")


#: A stream's fixes that start this far [s] past its last gyro sample are warned about: live
#: fixes come after the samples of their time, and a log's fixes given ahead wait for less than a
#: day of samples; a day's wait is another clock.
FAR_AHEAD = 86_400.0


def warn_far_ahead(fixes: Fixes, last_sample: float | None) -> bool:
    """Warns when a stream's new ``fixes`` start more than :data:`FAR_AHEAD` after its last gyro
    sample ``last_sample`` [s], and says whether it did. Such fixes wait for samples that never
    come (UTC seconds against a gyro's seconds since boot), without a word: a stream does not warn
    of fixes outside its span, as a whole log does, since it may be given them ahead."""
    if last_sample is None or not len(fixes):
        return False
    first = float(fixes.t[0])
    if not first - last_sample > FAR_AHEAD:
        return False
    warn(f"the heading fixes given start at t = {first:.3f} s, {first - last_sample:.6g} s after the last gyro sample "
         f"(t = {last_sample:.3f} s): a stream keeps each fix until the samples reach it, and these wait for more than "
         "a day, so they look like another clock (UTC or GNSS seconds against a gyro's seconds since boot) and would "
         f"never be applied: {ON_GYRO_CLOCK}")
    return True


#: The last fix a stream was given: time [s], heading [rad], sigma [rad].
GivenFix = tuple[float, float, float]


def refuse_behind_waiting(fixes: Fixes, waiting: GivenFix | None) -> None:
    """Refuses a stream's new ``fixes`` whose first comes before ``waiting``, the last fix given
    with an earlier block and still waiting for its samples (None if none waits), or is that fix
    again. A stream keeps every fix it is given until the samples reach it, so a caller who gives
    the waiting fixes again has them twice: the filter found the step back only once the samples
    reached the end of the waiting ones, blocks later, and the waiting fix given again alone was
    applied twice. (Two different fixes at one time stay allowed, as in one call.)"""
    if waiting is None or not len(fixes):
        return
    first = (float(fixes.t[0]), float(fixes.heading[0]), float(fixes.sigma[0]))
    if first[0] < waiting[0]:
        how = f"comes before t = {waiting[0]!r}, a fix"
    elif first == waiting:
        how = "is the fix"
    else:
        return
    raise ValueError(f"fix 0: t = {first[0]!r} {how} given with an earlier block that still waits for its samples: a "
                     "stream keeps each fix it is given until the samples reach it, so give each fix once (only "
                     "those after the ones given before), in time order. Nothing of this block was processed")


def last_given(fixes: Fixes, before: GivenFix | None) -> GivenFix | None:
    """The last fix a stream was given, after a block that brought ``fixes``."""
    if not len(fixes):
        return before
    return float(fixes.t[-1]), float(fixes.heading[-1]), float(fixes.sigma[-1])


#: Why a fix that repeats the one before it exactly is dropped, in a whole log's words and a stream's.
TWICE = "one measurement given twice would count as two, tighter than its sigma says"


class StreamFixes:
    """What a stream keeps of the fixes it was given: the last one, which may still wait for its
    samples (a block whose fixes start behind it is refused), and whether fixes far ahead of the
    samples, most of them rejected, or any re-admitted were said (a pickle keeps both:
    :meth:`kept`)."""

    def __init__(self, last: GivenFix | None = None, said: Sequence[bool] = ()) -> None:
        self.last = last
        # a pickle made before the flags were kept has none: said again once, as before
        self.ahead_said, self.rejected_said, self.readmitted_said, self.repeat_said = (list(said) + [False] * 4)[:4]

    def kept(self) -> dict[str, Any]:
        """What a stream's pickle keeps (``last_fix``, ``fixes_said``), for :meth:`restored`: a
        stream restored after each block without the flags repeated its warnings on every block."""
        said = [self.ahead_said, self.rejected_said, self.readmitted_said, self.repeat_said]
        return {"last_fix": self.last, "fixes_said": said}

    @classmethod
    def restored(cls, state: Mapping[str, Any]) -> StreamFixes:
        """The fixes' part of a stream read back from :meth:`kept` (or an older pickle's)."""
        return cls(state.get("last_fix"), [bool(s) for s in state.get("fixes_said", ())])

    def said_by_whole_log(self) -> None:
        """Leaves to a whole log's own checks, made of every fix, what a stream says of its totals:
        fixes far ahead, most rejected, any re-admitted."""
        self.ahead_said = self.rejected_said = self.readmitted_said = True

    def check(self, block: Fixes, waits: bool) -> Fixes:
        """Refuses ``block`` if its first fix comes before the last one given, or is it again,
        while that one still ``waits`` for its samples (:func:`refuse_behind_waiting`). Returns
        it without a first fix that repeats the last one given, already processed, exactly: one
        call drops such a repeat (:func:`gyrocore.fixes.without_repeats`), and a stream given each
        fix twice, the copy with the next block, applied it again (each fix gated twice, a run of
        rejections twice as long in fixes, re-admitted sooner). Said once a stream."""
        refuse_behind_waiting(block, self.last if waits else None)
        if not len(block) or (float(block.t[0]), float(block.heading[0]), float(block.sigma[0])) != self.last:
            return block
        if not self.repeat_said:
            warn(f"heading fix 0 at t = {float(block.t[0])!r} s repeats exactly the last fix given with the block "
                 f"before, and is dropped (as any fix that repeats the one before it): {TWICE}")
            self.repeat_said = True
        from .fixes import Fixes

        return Fixes(block.t[1:], block.heading[1:], block.sigma[1:])

    def block_for(self, inner: _gyrocore.Pipeline, fixes: FixesLike | None) -> tuple[_gyrocore.Pipeline, Fixes | None]:
        """The core a pipeline runs a block on, and the block's fixes (:meth:`check`): fixes given
        to a pipeline without the fix stage start it (defaults) on a copy, if it has processed no
        sample yet, so that a bad fix leaves the pipeline without one."""
        if fixes is None:
            return inner, None
        from .fixes import as_fixes, stage_settings

        last = inner.last_time()
        # the last fix given waits unless a sample at or after its time was processed
        block = self.check(as_fixes(fixes), waits=self.last is not None and (last is None or self.last[0] > last))
        if inner.fused():
            return inner, block
        if last is not None:
            raise ValueError("fixes given to a pipeline that has processed samples without a fix stage: create "
                             "it with Pipeline(..., fusion={}) to give fixes in a later block")
        started = inner.__copy__()
        started.start_fusion(stage_settings(dict(inner.params()), {}))
        return started, block

    def restarted(self, dropped: int) -> None:
        """After a restart of the gyro's clock, which dropped ``dropped`` fixes that waited for
        samples: the fixes given before were on the old clock, and none waits now."""
        self.last = None
        if dropped:
            warn(f"restart_clock() dropped {dropped} heading fix(es) that waited for later samples: they are on the "
                 "clock that jumped back; give only fixes on the new clock")

    def taken(self, block: Fixes, last_sample: float | None) -> None:
        """After the core took ``block``: its last fix is kept, and fixes far ahead of the last
        sample are warned about once."""
        self.last = last_given(block, self.last)
        self.ahead_said = self.ahead_said or warn_far_ahead(block, last_sample)

    def judge(self, counts: Mapping[str, int]) -> None:
        """Warns once when the stream's gate has rejected most of the fixes it reached
        (:func:`gyrocore.fixes_warnings.warn_rejected`, a whole log's rule on the stream's totals): fixes
        stamped 0.3 s late on their arrival had the heading 16 deg off, and a stream said nothing;
        and once when it first re-admits fixes (:func:`gyrocore.fixes_warnings.warn_readmitted`)."""
        from .fixes_warnings import warn_readmitted, warn_rejected  # it builds on this module

        self.rejected_said = self.rejected_said or warn_rejected(counts)
        self.readmitted_said = self.readmitted_said or warn_readmitted(counts)
