"""Pitchforks of symmetric branches (issues 16, 19). A symmetric branch is traced on the
half-period map, where the pitchfork is a regular multiplier -1 located by the engine's test;
on the 2pi problem it is a branch point, which the engine brackets only to where its corrector
fails (1.5e-5 in sigma at the Fig. 10 pitchfork near -1.09) and :func:`refine_pitchforks` then
locates by Newton on the minimally augmented half-period condition. The two methods must agree,
and scipy's full-period monodromy must have the multiplier +1 at both."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.continuation import continuation
from slosh_bif.model.parameter_file import read_parameter_file
from slosh_bif.orbits import (
    NO_SWITCHING,
    BranchingSettings,
    ShootingSettings,
    orbit_from_simulation,
    trace_orbits,
)
from slosh_bif.orbits.families import SHOOTING_OPTIONS
from slosh_bif.orbits.pitchforks import refine_pitchforks
from slosh_bif.orbits.settings import ParameterRange
from slosh_bif.orbits.shooting import ShootingProblem
from slosh_bif.orbits.starts import start_orbit

PRESET = get_preset("fig10")


@pytest.fixture(scope="module")
def symmetric_branch():
    start = orbit_from_simulation(PRESET.params.replace(sigma=-1.2), PRESET.state0, settle=150)
    return trace_orbits(
        start.params,
        start.y0,
        shooting=ShootingSettings(points_per_2pi=32),
        branching=NO_SWITCHING,
        interval=ParameterRange(lo=-1.6, hi=1.2),
    ).branches[0]


def test_every_pitchfork_of_the_half_period_map_has_a_multiplier_at_one_by_scipy(
    symmetric_branch, scipy_multipliers
):
    assert symmetric_branch.kind == "symmetric" and symmetric_branch.problem.symmetric
    pitchforks = symmetric_branch.branch.special_of("BP")
    assert len(pitchforks) == 4
    for sp in pitchforks:
        assert (
            sp.located
            and "half-period map's multiplier" in sp.message
            and min(sp.bracket) <= sp.p <= max(sp.bracket)
        )
        mu = scipy_multipliers(PRESET.params.replace(sigma=float(sp.p)), sp.x[:4])
        assert np.min(np.abs(mu - 1)) < 1e-6, (sp.p, mu)


def test_pitchforks_refined_on_the_2pi_problem_agree_with_the_half_period_map(symmetric_branch):
    # The branch's sigma box, (-3.0, 2.6), does not contain Abar = 3: the refinement's problem
    # (Abar held, sigma an unknown) must not inherit it.
    half = symmetric_branch.problem
    full = ShootingProblem(half.params, "sigma", segments=2 * half.segments, box=(-3.0, 2.6))
    x0 = half.full_states(symmetric_branch.branch.x[0])
    options = dataclasses.replace(SHOOTING_OPTIONS, p_min=-1.6, p_max=1.2)
    on_full = refine_pitchforks(
        full, continuation(full, x0, float(symmetric_branch.branch.p[0]), param="sigma", options=options)
    )
    refined = on_full.special_of("BP")
    assert len(refined) == 4 and all("refined on the half-period map" in sp.message for sp in refined)
    expected = sorted(sp.p for sp in symmetric_branch.branch.special_of("BP"))
    assert sorted(sp.p for sp in refined) == pytest.approx(expected, abs=1e-8)


def test_no_pitchfork_off_the_walls_where_the_free_particle_makes_minus_one_double(scipy_multipliers):
    """Fig. 10 set (beta = 0) at sigma = 6 continued in Abar: below Abar ~ 4.5 the orbit stays off
    the walls (max |w| < 1), the particle drifts freely and the half-period map has -1 twice all
    along; its test flips sign on rounding. No BP may be reported there, neither located nor
    detected; the genuine pitchfork where the orbit touches the wall is kept."""
    start = orbit_from_simulation(PRESET.params.replace(sigma=6.0), PRESET.state0, settle=100)
    ob = trace_orbits(
        start.params,
        start.y0,
        shooting=ShootingSettings(points_per_2pi=64),
        branching=NO_SWITCHING,
        interval=ParameterRange(name="Abar", lo=0.2, hi=6.0),
    ).branches[0]
    assert ob.kind == "symmetric"
    off_wall = ob.measures["max_abs_w"] < 0.9
    assert np.sum(off_wall) >= 10  # the stretch the test is about is on the branch
    pitchforks = ob.branch.special_of("BP")
    assert pitchforks and all(ob.measures["max_abs_w"][sp.index] >= 1.0 for sp in pitchforks), [
        (sp.p, ob.measures["max_abs_w"][sp.index]) for sp in pitchforks
    ]
    for sp in pitchforks:
        mu = scipy_multipliers(PRESET.params.replace(sigma=6.0, Abar=float(sp.p)), sp.x[:4])
        assert np.min(np.abs(mu - 1)) < 1e-6


TANK = Path(__file__).parents[2] / "docs/identify/tank/tank.toml"  # an asymmetric attractor at sigma = 2


def _tank_family(max_branches, progress=None):
    """The tank example's family from its attractor at sigma = 2 over [1.5, 3.5], and its preset."""
    tank = read_parameter_file(TANK)
    start = orbit_from_simulation(tank.params.replace(sigma=2.0), tank.state0, settle=150)
    family = trace_orbits(
        start.params,
        start.y0,
        shooting=ShootingSettings(points_per_2pi=32),
        branching=BranchingSettings(max_branches=max_branches),
        interval=ParameterRange(lo=1.5, hi=3.5),
        progress=progress,
    )
    return family, tank


def test_a_family_started_on_an_asymmetric_orbit_traces_its_symmetric_parent_both_ways():
    # The tank example's attractor at sigma = 2 is asymmetric; its branch turns at 2.3456, where
    # the pair meets the symmetric parent. The family switches there first (before the pair's
    # period doublings) onto the parent, traced both ways on the half-period map: its pitchfork is
    # the pair's turn, located on another problem, and past it the parent is the attractor that a
    # simulation at sigma = 3.5 settles on.
    family, tank = _tank_family(max_branches=2)
    pair, parent = family.branches
    assert (pair.kind, parent.kind) == ("asymmetric", "symmetric") and parent.problem.symmetric
    assert parent.branch.p.min() == 1.5 and parent.branch.p.max() == 3.5  # both ways, to the bounds
    (turn,) = [sp.p for sp in pair.branch.special if sp.kind == "LP"]
    (pitchfork,) = [sp.p for sp in parent.branch.special if sp.kind == "BP"]
    assert abs(pitchfork - turn) < 1e-6
    settled = orbit_from_simulation(tank.params.replace(sigma=3.5), tank.state0, settle=150)
    end = parent.problem.full_states(parent.branch.x[np.argmax(parent.branch.p)])[:4]
    np.testing.assert_allclose(end, settled.y0, atol=1e-7)


def test_a_family_cut_by_its_branch_cap_says_where_it_did_not_switch():
    said = []
    family, _ = _tank_family(max_branches=1, progress=said.append)
    assert len(family.branches) == 1
    (cut,) = [m for m in said if m.startswith("not switched at")]
    assert "BP sigma = 2.34564 on asymmetric" in cut and "--max-branches" in cut


def test_a_switched_branch_ends_where_it_meets_its_parent_again():
    """The Fig. 10 asymmetric pair born at the pitchfork near sigma = -5.63 meets the symmetric
    branch again at the one near -0.384: its trace stops there (beyond, it would be its own
    mirror image back to the start), the end is that pitchfork, and the branch counts as closed."""
    start = start_orbit(PRESET.params.replace(sigma=-6.0), PRESET.state0, (-6.0, 0.0))
    family = trace_orbits(
        start.params,
        start.y0,
        shooting=ShootingSettings(points_per_2pi=32),
        branching=BranchingSettings(max_branches=2, doublings=False),
        interval=ParameterRange(lo=-6.0, hi=0.0),
    )
    symmetric, pair = family.branches
    assert (symmetric.kind, pair.kind) == ("symmetric", "asymmetric")
    pitchforks = sorted(sp.p for sp in symmetric.branch.special if sp.kind == "BP")
    end = pair.branch.special[-1]
    assert pair.branch.ends == (("forward", "terminal point"),) and pair.closed
    assert end.kind == "BP" and end.index == len(pair) - 1
    assert min(abs(end.p - p) for p in pitchforks) < 1e-6 and pair.branch.p[0] < -5 < -1 < end.p
