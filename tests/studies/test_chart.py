"""The chart's curve tracing on several processes gives the sequential result: the same curves,
point for point, each once however the starts repeat (issue 16's speed target, on 2 cores)."""

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.orbits import orbit_from_simulation, trace_orbits
from slosh_bif.studies.chart_curves import curve_starts as _starts, trace_curves as _trace_curves

PRESET = get_preset("fig10")


@pytest.fixture(scope="module")
def starts():
    """The fold at sigma = -1.40 and the pitchfork at -1.09 of the symmetric branch at Abar = 3,
    each listed twice (as when two branches share a special point)."""
    P = PRESET.params
    start = orbit_from_simulation(P.replace(sigma=-1.2), PRESET.state0, settle=150)
    family = trace_orbits(start.params, start.y0, p_min=-1.6, p_max=-0.9, switch=False, points_per_2pi=32)
    found = list(_starts(family.branches[0], "sigma", P, (-1.6, -0.9), (2.8, 3.2)))
    assert sorted(s.kind for s in found) == ["BP", "LP"]
    return found + found


def test_parallel_curves_are_the_sequential_curves_each_once(starts):
    sequential, status, failures = _trace_curves(starts, lambda message: None, workers=1)
    assert failures == ()
    assert status == "complete" and sorted(c.kind for c in sequential) == ["BP", "LP"]
    parallel, status, failures = _trace_curves(starts, lambda message: None, workers=2)
    assert failures == ()
    assert status == "complete" and [c.kind for c in parallel] == [c.kind for c in sequential]
    for a, b in zip(sequential, parallel):
        np.testing.assert_array_equal(a.branch.x, b.branch.x)
        np.testing.assert_array_equal(a.branch.p, b.branch.p)
