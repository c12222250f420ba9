"""The least forcing with a stable response in wall contact on branches of (9) in Abar: its lower
end at a fold far below a pitchfork whose symmetric orbit stays stable beneath it, reached from
both ends of the branch; at a contact crossing, where max |w| = 1 on an orbit computed apart
(single shooting, then an integration by scipy)."""

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.model.params import Params
from slosh_bif.orbits import NO_SWITCHING, periodic_orbit, trace_orbits
from slosh_bif.orbits.settings import BranchingSettings, ParameterRange
from slosh_bif.orbits.stable_contact import (
    born_at,
    lowest_stable_contact,
    stable_orbit_below,
    stable_side_below,
)
from slosh_bif.simulation.direct import integrate_smooth

# A random admissible draw (seed 28 of the chart's campaign) at sigma = -2.049: the orbits with
# contact are stable from a fold at Abar = 0.0455 up to a pitchfork at 3.234.
SEED_28 = Params(
    eps=0.13503608402999223,
    beta=0.6242813949181742,
    gamma=0.06448937039741993,
    sigma=-2.049,
    Abar=0.02,
    lam=0.1451777130963097,
    chi=1.351204532948671,
    n=21,
    pbar=1,
)


@pytest.fixture(scope="module")
def from_rest():
    """The branch in Abar over [0.02, 4] from the small response near rest."""
    family = trace_orbits(
        SEED_28, np.zeros(4), interval=ParameterRange(0.02, 4.0, "Abar"), branching=NO_SWITCHING
    )
    return family.branches[0]


def test_the_stable_orbits_with_contact_end_at_a_fold_far_below_the_pitchfork(from_rest):
    end = lowest_stable_contact(from_rest, 0.02)
    assert (end.kind, end.below_range) == ("LP", False)
    assert 0.04 < end.Abar < 0.05
    pitchfork = [sp for sp in from_rest.branch.special if sp.kind == "BP"]
    assert len(pitchfork) == 1 and pitchfork[0].p > 3.2
    # From the pitchfork down, on the branch traced from there: the same fold.
    at = SEED_28.replace(Abar=pitchfork[0].p)
    below = stable_side_below(at, stable_orbit_below(at, pitchfork[0].x[:4], 0.02), 0.02)
    assert below.kind == "LP"
    assert below.Abar == pytest.approx(end.Abar, rel=1e-9)


def test_stable_orbits_with_contact_down_to_the_range_bottom_lie_below_it(from_rest):
    pitchfork = [sp for sp in from_rest.branch.special if sp.kind == "BP"][0]
    at = SEED_28.replace(Abar=pitchfork.p)
    below = stable_side_below(at, stable_orbit_below(at, pitchfork.x[:4], 0.1), 0.1)
    assert below.below_range and np.isnan(below.Abar)


def test_above_a_fold_whose_stable_orbits_lie_above_nothing_is_found_below(from_rest):
    fold = [sp for sp in from_rest.branch.special if sp.kind == "LP" and sp.p < 1][0]
    assert stable_orbit_below(SEED_28.replace(Abar=fold.p), fold.x[:4], 0.02, fold=True) is None


def test_a_pair_stable_from_where_it_was_switched_on_starts_at_its_parents_pitchfork():
    """The asymmetric pair born at the pitchfork at 3.234 is stable with contact from its first
    point, a step off the pitchfork: its lower end is the parent's located pitchfork."""
    family = trace_orbits(
        SEED_28,
        np.zeros(4),
        interval=ParameterRange(0.02, 4.0, "Abar"),
        branching=BranchingSettings(doublings=False),
    )
    parent, pair = family.branches
    end = lowest_stable_contact(pair, 0.02)
    assert end.kind == "unlocated"
    (pitchfork,) = [sp for sp in parent.branch.special if sp.kind == "BP"]
    assert 0 < abs(end.Abar - pitchfork.p) < 1e-3
    born = born_at(end, family.branches)
    assert (born.kind, born.Abar, born.branch) == ("BP", pitchfork.p, parent)
    assert born_at(lowest_stable_contact(parent, 0.02), family.branches).kind == "LP"  # not switched


def test_a_contact_crossing_is_where_the_stable_orbit_first_touches_the_walls():
    """A soft wall (n = 2) and beta = 0.7: the small response grows into contact and stays
    stable; its lower end is where max |w| = 1, found on an orbit computed apart."""
    params = get_preset("fig13").params.replace(
        n=2, beta=0.7, sigma=1.0, Abar=0.05, lam=0.05, chi=1.5, gamma=0.4, pbar=0
    )
    family = trace_orbits(
        params, np.zeros(4), interval=ParameterRange(0.04, 4.0, "Abar"), branching=NO_SWITCHING
    )
    end = lowest_stable_contact(family.branches[0], 0.04)
    assert end.kind == "contact" and 0.5 < end.Abar < 2
    i = int(np.argmin(np.abs(family.branches[0].branch.p - end.Abar)))
    y0 = family.branches[0].branch.x[i, :4]
    for factor, side in ((1.0, 0), (0.99, -1), (1.01, 1)):
        at = params.replace(Abar=end.Abar * factor)
        orbit = periodic_orbit(at, y0)
        assert orbit.converged and orbit.stable
        run = integrate_smooth(at, orbit.y0, (0.0, 2 * np.pi), t_eval=np.linspace(0, 2 * np.pi, 20001))
        peak = np.max(np.abs(run.y[2]))
        if side == 0:
            assert peak == pytest.approx(1.0, abs=1e-6)
        else:
            assert np.sign(peak - 1.0) == side
