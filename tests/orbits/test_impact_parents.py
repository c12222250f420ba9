"""An asymmetric family of (8) that meets its symmetric parent at the parent's grazing ends there:
the orbits the contact's unfolding finds beyond are the parent's symmetric ones, which the family
does not go on along. Checked with scipy's reference flow (the expm event loop) for the symmetry
and with the half-period map for the parent's grazing."""

import numpy as np
import pytest

from slosh_bif import get_preset, simulate_impact
from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.flows.smooth.integrator import HAVE_NUMBA
from slosh_bif.orbits.impact.branches import trace_impact_orbits
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled flow needs numba")

# a random admissible set (seed 300 of the robustness draws): its symmetric branch has pitchforks
# at sigma = 0.282919, 0.309361 and 0.359386, whose asymmetric families end at grazings of the
# symmetric orbits (0.3155, 0.3416, 0.3810); an orbit of the third, 9 impacts a period
SET = dict(eps=0.0604, beta=0.19, gamma=0.163, Abar=3.376, lam=0.313, chi=1.421, n=3, pbar=3)
SIGMA0 = 0.37685597137011545
X0 = [-4.798965252422253, 3.318394681158824, 0.9848955769247695, 0.8999728626077446]


def _mirror_distance(params, x, phase):
    """|x + y(phase + pi)| / (1 + |x|) by the reference flow: zero for a symmetric orbit."""
    y = simulate_impact(params, x, (phase, phase + np.pi), backend="scipy").y[:, -1]
    return float(np.linalg.norm(x + y) / (1 + np.linalg.norm(x)))


def test_an_asymmetric_family_ends_where_it_meets_its_symmetric_parent_at_a_grazing():
    """Before, the branch crossed that grazing onto the symmetric orbits beyond it and traced the
    symmetric branch again on the whole-period map (at this set, three families in 8-17 pieces
    each, ending at a symmetric grazing with nothing found beyond: exit 3)."""
    params = get_preset("fig10").params.replace(**SET, sigma=SIGMA0)
    branch = trace_impact_orbits(params, X0, p_min=0.37, p_max=0.39)
    forward = next(e for e in branch.ends if e.direction == "forward")
    assert forward.reason == "parent" and "symmetric orbit" in forward.message, forward
    assert branch.complete
    for piece in branch.pieces:  # the family's own orbits are asymmetric
        i = len(piece.branch) // 2
        at = params.replace(sigma=float(piece.branch.p[i]))
        assert _mirror_distance(at, piece.branch.x[i], piece.phase) > 1e-5  # symmetric: 1e-12
    p, x, phase = max(branch.grazing, key=lambda g: g[0])  # where it meets the parent
    assert abs(p - 0.38104) < 1e-4
    at = params.replace(sigma=p)
    assert _mirror_distance(at, x, phase) < 1e-3
    # the parent: the symmetric orbit there (a fixed point of the half-period map) grazes the wall
    half = ImpactOrbitProblem(at, symmetric=True, phase=phase)
    run = newton_solve(half.replace(impacts=None), x, p, tol=1e-12)
    assert run.converged and abs(half.grazing(run.x, p).gap) < 1e-6
