"""The public Python API once more under odd but valid use: a pipeline reset for a new log, and
results compared with ``==``."""

from __future__ import annotations

import pickle
import warnings

import numpy as np
import pytest

import gyrocore

T = np.arange(0.0, 60.0, 0.01)
RATE = 0.002 + 0.1 * np.sin(T)


def _said(run: object) -> list[str]:
    """The warnings a call gives, each as text."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run()  # type: ignore[operator]
    return [str(w.message) for w in caught]


@pytest.mark.parametrize("pickled", [False, True])
def test_a_reset_pipeline_warns_of_a_new_log_as_a_new_pipeline_does(pickled: bool) -> None:
    """``reset()`` returns to the state before the first sample: the unit check and the unmeasured
    bias are said again for the next log (a new log in ms was processed without a word)."""
    p = gyrocore.Pipeline("static_bias")
    p.process(T, RATE)
    if pickled:
        p = pickle.loads(pickle.dumps(p))
    p.reset()
    fresh = _said(lambda: gyrocore.Pipeline("static_bias").process(T * 1000, RATE))
    assert any("timestamps look like ms" in w for w in fresh) and any("removes a static bias" in w for w in fresh)
    assert _said(lambda: p.process(T * 1000, RATE)) == fresh
