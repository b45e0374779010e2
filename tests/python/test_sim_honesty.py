"""What the simulator states is what it simulates: a stopped car does not turn, and the simulated
GNSS fixes have the noise, the rate and the outage they are given."""

from __future__ import annotations

import numpy as np
import pytest

from gyrocore import motion, sim


@pytest.mark.parametrize("mix", ["city", "downtown"])
def test_a_stopped_car_does_not_turn(mix: str) -> None:
    # the swerve of the drive-off after a stop began where the braking did: the car yawed at up to
    # 0.2 deg/s and turned 0.64 deg while standing, where a gyro reads bias and noise only
    route = motion.car(1800.0, mix=mix, seed=2)
    stops = route.segments_of("stop")
    assert len(stops) >= 3
    for stop in stops:
        t = np.linspace(stop.start, stop.end, 200)
        truth = route.sample(t)
        assert np.all(truth.speed == 0.0)
        assert np.abs(truth.rate).max() == 0.0, stop
        assert np.ptp(truth.heading) == 0.0, stop
