"""Switching on a closed loop of asymmetric orbits (:mod:`slosh_bif.orbits.switching`): the loop
holds both members of the mirror pair, so it meets each of its period doublings twice, once on
each member, and its pitchfork is a branch point of the symmetric parent too; the second of such
points is an image of the first and is not switched at again."""

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.flows.smooth.integrator import integrate_grid
from slosh_bif.orbits import BranchingSettings, on_traced_branch
from slosh_bif.orbits.families import trace_orbits
from slosh_bif.orbits.settings import NO_SWITCHING, ParameterRange
from slosh_bif.orbits.starts import settle_and_shoot
from slosh_bif.orbits.switching import image_of_settled


@pytest.fixture(scope="module")
def loop():
    """The asymmetric branch of the Fig. 10 set through its orbit at sigma = -3, traced until it
    closes (through its pitchfork at sigma = -0.384 onto the mirror image and back)."""
    preset = get_preset("fig10")
    P = preset.params.replace(sigma=-3.0)
    orbit, _ = settle_and_shoot(P, preset.state0)
    family = trace_orbits(P, orbit.y0, branching=NO_SWITCHING, interval=ParameterRange(lo=-6.0, hi=-0.3))
    return P, orbit.y0, family.branches[0]


def test_each_period_doubling_of_the_loop_comes_twice_as_mirror_images(loop):
    P, _, ob = loop
    assert ob.closed
    doublings = [sp for sp in ob.branch.special if sp.kind == "PD"]
    assert len(doublings) >= 4
    for sp in doublings:
        twins = [q for q in doublings if q is not sp and abs(q.p - sp.p) <= 1e-6]
        assert len(twins) == 1, sp.p
        (twin,) = twins
        # independently of the arcs' bookkeeping: the mirror image starts at -y(pi) of the orbit
        at = P.replace(sigma=float(sp.p))
        y_pi = integrate_grid(at, twin.x[:4], np.array([0.0, np.pi]))[-1]
        assert np.allclose(-y_pi, sp.x[:4], atol=1e-6)
        assert image_of_settled(ob, sp, [(ob, twin)]) == (ob, twin)
        assert image_of_settled(ob, sp, [(ob, q) for q in doublings if abs(q.p - sp.p) > 1e-6]) is None


@pytest.mark.slow  # a family of five branches (about 20 s); the test above covers the test it rests on
def test_a_family_on_the_loop_switches_at_one_member_of_each_mirror_pair_of_doublings(loop):
    P, y0, _ = loop
    said = []
    family = trace_orbits(
        P,
        y0,
        branching=BranchingSettings(max_branches=5),
        interval=ParameterRange(lo=-6.0, hi=-0.3),
        progress=said.append,
    )
    assert any("its orbit is an image of the one at PD" in m for m in said)
    # no branch is another's image: Newton from the middle orbit of each (the scan's test, not the
    # family's) converges on no other branch nor on its images
    for ob in family.branches:
        i = len(ob) // 2
        others = [o for o in family.branches if o is not ob]
        at = P.replace(sigma=float(ob.branch.p[i]))
        multiple = ob.problem.period_multiple
        assert on_traced_branch(at, ob.branch.x[i, :4], others, period_multiple=multiple) is None, ob.name
