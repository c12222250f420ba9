"""A branch of (8) that is a closed curve stops after one lap: a start on a moved section that lies
on an earlier piece is recognised, the orbit carried between sections by scipy's reference flow
(the expm event loop), and the closed period-2 branch of a random set is checked against its
multipliers and the period-1 orbit it is born from."""

import numpy as np
import pytest

from slosh_bif import get_preset, simulate_impact
from slosh_bif.continuation.branch import Status
from slosh_bif.flows.smooth.integrator import HAVE_NUMBA
from slosh_bif.orbits.impact.branches import trace_impact_orbits
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem
from slosh_bif.orbits.impact.retrace import retraced_piece

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled flow needs numba")

# a random admissible set (seed 304 of the robustness draws) with a closed branch of period-2
# orbits (ten to twelve impacts a period) born at a period doubling near sigma = -0.8248
SET = dict(eps=0.0909, beta=0.192, gamma=0.332, lam=0.136, chi=0.113, n=35, pbar=3)
SIGMA0 = -0.6355249917624982
X0 = [3.9416186793186903, 2.898546455010853, -0.997969176639579, -3.114848106848531]


def _params():
    return get_preset("fig10").params.replace(**SET, sigma=SIGMA0, Abar=3.226)


def _moved(params, x, phase, to):
    """The orbit's state at tau = ``to`` (> phase) by the reference flow."""
    return simulate_impact(params, x, (phase, to), backend="scipy").y[:, -1]


def test_an_orbit_of_a_piece_on_another_section_or_mirrored_is_recognised_and_a_nearby_state_is_not():
    params = _params()
    branch = trace_impact_orbits(params, X0, p_min=SIGMA0 - 0.05, p_max=SIGMA0 + 0.05, period_multiple=2)
    piece = max(branch.pieces, key=lambda pc: len(pc.branch))
    i = len(piece.branch) // 2
    p, x = float(piece.branch.p[i]), piece.branch.x[i]
    at = params.replace(sigma=p)
    for shift in (0.7, 2.9):  # sections between the impacts
        phase = piece.phase + shift
        y = _moved(at, x, piece.phase, phase)
        problem = ImpactOrbitProblem(at, period_multiple=2, phase=phase % (2 * np.pi))
        problem = problem.replace(impacts=len(problem.evaluate(y, p).impacts))
        assert problem.impacts == piece.impacts
        assert retraced_piece(problem, y, p, branch.pieces) is not None
        # the mirror image y(tau + pi) -> -y is the same family traced again
        mirror = -_moved(at, x, piece.phase, phase + np.pi)
        assert retraced_piece(problem, mirror, p, branch.pieces) is not None
        # a state 1e-4 off the orbit is no orbit of the piece: Newton from the chord lands elsewhere
        assert retraced_piece(problem, y + 1e-4, p, branch.pieces) is None


@pytest.mark.slow
def test_a_closed_period_two_branch_ends_as_a_loop_after_one_lap():
    """Without the test the branch laps its loop, each lap meeting the section at another point,
    until its 40 pieces are spent."""
    params = _params()
    branch = trace_impact_orbits(params, X0, p_min=-6.0, p_max=8.0, period_multiple=2)
    assert branch.complete and len(branch.pieces) < 20
    assert all(end.reason == Status.LOOP.value for end in branch.ends)
    points = [(float(p), x, pc) for pc in branch.pieces for p, x in zip(pc.branch.p, pc.branch.x)]
    # the lowest orbit is the period-1 orbit the branch is born from: it returns after 2 pi
    p, x, pc = min(points, key=lambda t: t[0])
    assert p == pytest.approx(-0.8248, abs=1e-3)
    half = _moved(params.replace(sigma=p), x, pc.phase, pc.phase + 2 * np.pi)
    assert np.linalg.norm(half - x) < 1e-3 * (1 + np.linalg.norm(x))
    # the highest is a fold: a multiplier of the 4 pi map at +1
    p, x, pc = max(points, key=lambda t: t[0])
    folds = [s for s in pc.branch.special if s.kind == "LP" and abs(s.p - p) < 1e-6]
    assert folds
    problem = ImpactOrbitProblem(params, period_multiple=2, phase=pc.phase, impacts=pc.impacts)
    assert np.min(np.abs(problem.eigenvalues(folds[0].x, folds[0].p) - 1)) < 1e-5
