"""The lower end of the stable orbits with impacts of (8) on a branch in Abar, and the side of a
curve of (8) they lie on; checked by simulations of (8) on the expm event loop (scipy), a flow
apart from the compiled one the branches use."""

import numpy as np
import pytest

from slosh_bif.model.params import Params
from slosh_bif.orbits.impact.branches import settled_orbit, state_at_zero, trace_impact_orbits
from slosh_bif.orbits.impact.curves import ImpactCurveSeed, trace_impact_curve
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem
from slosh_bif.orbits.impact.stable_impacts import impacts_along_bottom, lowest_stable_impacts
from slosh_bif.simulation.vibro_impact import simulate_impact
from slosh_bif.studies.chart.bottom import below_bottom
from slosh_bif.studies.chart.reading import critical_at, lowest_stable_boundary

# Random admissible draws of the impact chart's campaign (docs/findings/impact.md)
SET_40 = Params(
    eps=0.11014394438424445,
    beta=0.7564407629259371,
    gamma=0.07684342702014839,
    sigma=-1.0,
    Abar=2.5,
    lam=0.20075960745797036,
    chi=0.7060688291833481,
    n=18,
    pbar=4,
)
SET_45 = Params(
    eps=0.08870384887212637,
    beta=0.6227376798514446,
    gamma=0.4152617451543232,
    sigma=0.5050560694294228,
    Abar=2.5145472792751327,
    lam=0.322523055694817,
    chi=1.0137060052090412,
    n=28,
    pbar=2,
)
# its symmetric orbit at tau = 0 there (the chart's seed at that sigma)
SET_45_ORBIT = np.array([-2.76918817, 2.07519204, 0.25094916, -0.69473421])


def _strobe_after(params, y0, periods):
    """(the state after ``periods`` forcing periods, the state one period later, impacts in that
    period) of (8) from y0, by the expm event loop."""
    T = 2 * np.pi
    run = simulate_impact(params, y0, (0.0, periods * T), backend="scipy")
    last = simulate_impact(params, run.y[:, -1], (periods * T, (periods + 1) * T), backend="scipy")
    assert run.success and last.success
    return run.y[:, -1], last.y[:, -1], len(last.impact_t)


def _orbit_at(branch, abar, symmetric, params):
    """The state at tau = 0 of the branch's orbit with impacts nearest ``abar``, and that Abar."""
    piece, i = min(
        ((pc, int(np.argmin(np.abs(pc.branch.p - abar)))) for pc in branch.pieces if pc.impacts),
        key=lambda found: abs(found[0].branch.p[found[1]] - abar),
    )
    p = float(piece.branch.p[i])
    problem = ImpactOrbitProblem(params.replace(Abar=p), "Abar", symmetric=symmetric, phase=piece.phase)
    return state_at_zero(problem, piece.branch.x[i], p), p


@pytest.fixture(scope="module")
def set_40_branch():
    x0 = settled_orbit(SET_40, np.array([0.0, 0.0, 0.5, 0.0]), periods=300)
    return trace_impact_orbits(SET_40, x0, param="Abar", p_min=0.1, p_max=4.0, symmetric=True)


def test_below_a_pitchfork_curve_of_8_stable_orbits_with_impacts_reach_the_bottom(set_40_branch):
    # The symmetric orbits of (8) at sigma = -1 lose their stability to the asymmetric pair as Abar
    # rises through the pitchfork at 2.2702: they are stable below it, down to the range's bottom.
    end = lowest_stable_impacts(set_40_branch, 0.1, symmetric=True)
    assert end.below_range
    (piece, sp) = next((pc, s) for pc in set_40_branch.pieces for s in pc.branch.special if s.kind == "BP")
    assert sp.p == pytest.approx(2.27019, abs=1e-4)
    seed = ImpactCurveSeed("BP", sp.x, sp.p, "Abar", symmetric=True, phase=piece.phase, impacts=piece.impacts)
    curve = trace_impact_curve(SET_40, seed, box={"sigma": (-1.05, -0.95), "Abar": (0.1, 4.0)})
    # the curve alone bounds stable orbits at the pitchfork; the reading looks below it
    assert lowest_stable_boundary([curve], -1.0, SET_40)[:2] == (pytest.approx(sp.p, rel=1e-6), "BP")
    value, kind, loss, below = critical_at([curve], -1.0, SET_40, 0.1, variant="paper")
    assert np.isnan(value) and below
    # a simulation from the orbit at Abar = 1 (far below the pitchfork), nudged, returns towards it
    # (its multipliers are 0.97 in modulus: 40 periods shrink the nudge threefold), hitting the walls
    y0, p = _orbit_at(set_40_branch, 1.0, True, SET_40)
    nudge = np.array([1e-4, -1e-4, 1e-4, 1e-4])
    after, again, impacts = _strobe_after(SET_40.replace(Abar=p), y0 + nudge, 40)
    assert np.linalg.norm(after - y0) < 0.5 * np.linalg.norm(nudge)
    assert np.linalg.norm(again - y0) < np.linalg.norm(after - y0)
    assert impacts >= 1


def test_a_stable_flag_at_a_grazing_point_alone_does_not_end_the_stable_orbits_there():
    # On SET_45's symmetric branch in Abar the impacting orbits lose stability at a torus point
    # (0.53958), fold at 0.374 and graze at 0.42886, where the grazing orbit's own flag is stable
    # (an impact of speed zero): the stable orbits with impacts end at the torus point.
    branch = trace_impact_orbits(SET_45, SET_45_ORBIT, param="Abar", p_min=0.1, p_max=4.0, symmetric=True)
    end = lowest_stable_impacts(branch, 0.1, symmetric=True)
    assert (end.kind, end.Abar) == ("NS", pytest.approx(0.53958, abs=1e-4))
    # between the grazing and the torus point the branch's orbit, nudged by 1e-7, is left
    y0, p = _orbit_at(branch, 0.47, True, SET_45)
    after, _, _ = _strobe_after(SET_45.replace(Abar=p), y0 + 1e-7, 40)
    assert np.linalg.norm(after - y0) > 1e-4


def test_along_the_bottom_of_the_box_the_stable_orbits_with_impacts_reach_sigmas_no_seed_is_at(set_40_branch):
    # From the seed at sigma = -1, whose symmetric orbits are stable with impacts down to Abar =
    # 0.1, the orbit at 0.1 continued in sigma stays stable with impacts to sigma = -4: there no
    # curve bounds anything, and Abar_c lies below the box.
    bottom = impacts_along_bottom(set_40_branch, SET_40, 0.1, (-4.0, -0.5), symmetric=True)
    assert below_bottom(bottom, -3.0) and below_bottom(bottom, -3.9)
    # a simulation at (sigma, Abar) = (-3, 0.1) from the seed's orbit at Abar = 0.1 settles on a
    # period-1 orbit that hits the walls: 400 periods of the compiled flow, then one period by
    # the expm event loop
    y0, _ = _orbit_at(set_40_branch, 0.1, True, SET_40)
    at = SET_40.replace(sigma=-3.0, Abar=0.1)
    settled = simulate_impact(at, y0, (0.0, 400 * 2 * np.pi))
    after, again, impacts = _strobe_after(at, settled.y[:, -1], 1)
    assert np.linalg.norm(again - after) < 1e-6 and impacts >= 1
