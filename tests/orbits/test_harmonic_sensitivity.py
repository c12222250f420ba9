"""A1's parameter derivatives from the variational equations (orbits.harmonic_sensitivity) against
central differences of orbits Newton solves again at moved parameters, and compiled against scipy."""

import pytest

from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.model.presets import get_preset
from slosh_bif.orbits.harmonic_sensitivity import first_harmonic_gradient
from slosh_bif.orbits.orbit_tools import orbit_measures
from slosh_bif.orbits.shooting import ShootingProblem

NAMES = ("lam", "chi", "gamma", "eps", "Abar", "sigma")


def _orbit(params, x):
    problem = ShootingProblem(params, segments=4)
    run = newton_solve(problem, x, params.sigma, tol=1e-12, max_iter=20, criterion="residual")
    assert run.converged
    return run.x, orbit_measures(problem, run.x, params.sigma)["A1"]


@pytest.fixture(scope="module", params=[3.0, -2.0])
def orbit(request):
    """An orbit of the Fig. 10 set: above the resonance (sigma = 3) and on the resonant branch
    below it (sigma = -2), from the slow flow's motion on (46)'s largest state there."""
    from slosh_bif.identify.response_model import response_curve
    from slosh_bif.orbits.starts import orbit_from_slow_flow

    params = get_preset("fig10").params.replace(sigma=request.param)
    A = max(A for A, _ in response_curve(params).states_at(params.sigma))
    start = orbit_from_slow_flow(params, A, segments=4)
    assert start.converged
    x, _ = _orbit(params, ShootingProblem(params, segments=4).initial_states(start.y0, params.sigma))
    return params, x


def test_derivatives_match_central_differences_of_orbits(orbit):
    params, x = orbit
    A1, grad = first_harmonic_gradient(params, x[:4], [{n: 1.0} for n in NAMES])
    assert A1 == pytest.approx(_orbit(params, x)[1], rel=1e-10)
    for name, g in zip(NAMES, grad):
        value = getattr(params, name)
        h = 1e-4 * abs(value)
        up, down = (_orbit(params.replace(**{name: value + s * h}), x)[1] for s in (1, -1))
        assert g == pytest.approx((up - down) / (2 * h), rel=1e-6, abs=1e-9), name


def test_a_direction_is_the_weighted_sum_and_scipy_agrees(orbit):
    params, x = orbit
    _, unit = first_harmonic_gradient(params, x[:4], [{"gamma": 1.0}, {"Abar": 1.0}, {"lam": 1.0}])
    _, mixed = first_harmonic_gradient(params, x[:4], [{"gamma": 2.0, "Abar": -0.5, "lam": 3.0}])
    assert mixed[0] == pytest.approx(2 * unit[0] - 0.5 * unit[1] + 3 * unit[2], rel=1e-9)
    _, scipy = first_harmonic_gradient(params, x[:4], [{"gamma": 1.0}, {"Abar": 1.0}], backend="scipy")
    assert scipy == pytest.approx(unit[:2], rel=1e-7)


def test_a_direction_naming_no_parameter_is_refused(orbit):
    params, x = orbit
    with pytest.raises(ValueError, match="directions name n"):
        first_harmonic_gradient(params, x[:4], [{"n": 1.0}])
