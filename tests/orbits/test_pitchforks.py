"""Pitchforks of symmetric branches located on the half-period map (issue 16): the engine's
bordered test alone brackets them only to where its corrector fails (1.5e-5 in sigma at the
Fig. 10 pitchfork near -1.09); refined, scipy's full-period monodromy has the multiplier +1 there."""

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.orbits import orbit_from_simulation, trace_orbits

PRESET = get_preset("fig10")


@pytest.fixture(scope="module")
def symmetric_branch():
    # The branch's sigma box, (-3.0, 2.6), does not contain Abar = 3: the refinement's problem
    # (Abar held, sigma an unknown) must not inherit it.
    start = orbit_from_simulation(PRESET.params.replace(sigma=-1.2), PRESET.state0, settle=150)
    return trace_orbits(start.params, start.y0, p_min=-1.6, p_max=1.2, switch=False, points_per_2pi=32).branches[0]


def test_every_pitchfork_is_refined_and_has_a_multiplier_at_one_by_scipy(symmetric_branch, scipy_multipliers):
    assert symmetric_branch.kind == "symmetric"
    pitchforks = symmetric_branch.branch.special_of("BP")
    assert len(pitchforks) == 4
    for sp in pitchforks:
        assert "refined on the half-period map" in sp.message and min(sp.bracket) <= sp.p <= max(sp.bracket)
        mu = scipy_multipliers(PRESET.params.replace(sigma=float(sp.p)), sp.x[:4])
        assert np.min(np.abs(mu - 1)) < 1e-6, (sp.p, mu)
