"""What a located sign change of a multiplier test is: a crossing of the unit circle, or a jump of
an impact map's Jacobian (a non-smooth point), which is none."""

import numpy as np
import pytest

from slosh_bif.orbits.multipliers import describe_crossing


def test_a_period_doubling_has_a_multiplier_at_minus_one_and_a_jump_is_none():
    pair = [0.652 + 0.4736j, 0.652 - 0.4736j]
    crossing = np.array([-1.0 + 1e-9, *pair, 0.1])
    assert describe_crossing("PD", crossing, symmetric=False).startswith("period doubling")
    assert describe_crossing("BP", crossing, symmetric=True).startswith("symmetry-breaking pitchfork")
    # the corrected impact model's map across its law's clamp: its largest multiplier jumps from
    # +77 to -77, and PD's test (the product of 1 + mu) changes sign with no multiplier near -1
    jumped = np.array([-77.5494, *pair, -8e-4])
    assert describe_crossing("PD", jumped, symmetric=False) is None
    assert describe_crossing("BP", jumped, symmetric=True) is None
    # a double -1 (a free particle's drift) is no simple crossing either
    assert describe_crossing("PD", np.array([-1.0, -1.0 + 1e-7, 0.5, 0.2]), symmetric=False) is None


def test_a_pair_nearing_the_circle_as_the_particle_reaches_the_walls_is_no_neimark_sacker():
    """The tank's fitted set (n = 50, beta = 0.40), symmetric orbits at sigma = 0.141157: off the
    walls the particle is undamped and its pair sits on the unit circle to rounding; as the forcing
    rises the walls pull the pair inside (|mu| - 1 = -2e-11 at Abar = 0.5575), and it never leaves
    the circle. A step from there to rounding of either sign is no NS: a sign change with rounding
    at one end is none (the engine's rule, failing without it in tests/continuation/test_problem.py;
    here the rounding's sign depends on the run)."""
    from slosh_bif import Params
    from slosh_bif.continuation import ContinuationOptions, continuation
    from slosh_bif.continuation.corrector import newton_solve
    from slosh_bif.orbits.shooting import ShootingProblem

    params = Params(
        eps=0.03995, beta=0.3973, gamma=0.5075, sigma=0.141157, Abar=0.5575, lam=0.4899, chi=0.2, n=50, pbar=0
    )
    problem = ShootingProblem(params, "Abar", segments=2, symmetric=True)
    shape = np.array([0.40024, 0.30571, 0.40024, 0.30571, 0.30571, -0.40024, 0.30571, -0.40024]) / 0.4379
    ns = {}
    for a in (0.4379, 0.5575):
        run = newton_solve(problem, shape * a, a, tol=1e-10, max_iter=20, criterion="residual")
        assert run.converged
        ns[a] = (problem.test_functions(run.x, a)[1], np.abs(problem.map_multipliers(run.x, a)))
    assert abs(ns[0.4379][0]) < 1e-13 and np.allclose(ns[0.4379][1][:2], 1, atol=1e-13)
    assert ns[0.5575][0] > 1e-11 and np.all(ns[0.5575][1] < 1 - 1e-11)
    # continued down in long steps from the walls to the undamped orbits: no special point
    branch = continuation(
        problem,
        run.x,
        0.5575,
        options=ContinuationOptions(step=0.12, step_max=0.13, p_min=0.3, p_max=0.56, direction="backward"),
    )
    assert branch.status == "ok" and branch.p.min() == pytest.approx(0.3)
    assert not [s.kind for s in branch.special if s.kind != "END"]
