"""Start orbits of the vibro-impact model (8): from a simulation at the set's sigma, else from the
slow flow's steady states over the range, else a one-line error naming what to change."""

import re

import numpy as np
import pytest

from slosh_bif import get_preset, simulate_impact
from slosh_bif.continuation import ConvergenceError
from slosh_bif.flows.smooth.integrator import HAVE_NUMBA
from slosh_bif.model.params import Params
from slosh_bif.orbits.impact.starts import impact_start

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled flow needs numba")

# no orbit of (8) settles at sigma = 0 in 2250 periods (a modulated response)
UNSETTLED = dict(eps=0.08, beta=0.15, gamma=0.3, sigma=0.0, Abar=2.0, lam=0.25, chi=0.4, n=8, pbar=2)
# pbar = -2: the restitution law (21) loses energy without bound at slow impacts, and at Abar = 0.1
# (46) has no steady state either
NOT_REAL = dict(eps=0.12, beta=0.0, gamma=0.15, sigma=1.0, Abar=0.1, lam=0.1, chi=1.0, n=4, pbar=-2)
# the simulation at the set stops at an impact speed where (21) is not real
NOT_REAL_AT_SPEED = dict(
    eps=0.07, beta=0.015, gamma=0.13, sigma=1.0, Abar=2.42, lam=0.353, chi=1.1, n=3, pbar=3
)
# not settled at sigma = 1, and below (46)'s critical forcing over the whole range
BELOW = dict(eps=0.0715, beta=0.2, gamma=0.33, sigma=1.0, Abar=0.36, lam=0.36, chi=0.88, n=5, pbar=3)


def _state0(params):
    return get_preset("fig10").state_for(params)


def test_where_8_settles_on_no_orbit_at_the_sets_sigma_the_start_comes_from_the_slow_flow():
    params = Params(**UNSETTLED)
    with pytest.raises(ConvergenceError, match="has not settled"):  # without a range, as before
        impact_start(params, _state0(params), periods=150)
    start = impact_start(params, _state0(params), periods=150, p_range=(-2.0, 2.0))
    assert -2.0 <= start.params.sigma <= 2.0 and start.params.sigma != params.sigma
    assert start.params.replace(sigma=params.sigma) == params
    assert "slow flow" in start.found_from and "has not settled" in start.found_from
    # a fixed point of the 2pi map of (8), by the expm event loop (independent of the compiled flow)
    image = simulate_impact(start.params, start.x, (0.0, 2 * np.pi), backend="scipy").y[:, -1]
    np.testing.assert_allclose(image, start.x, rtol=0, atol=1e-8)


def test_a_family_in_abar_starts_from_the_slow_flows_states_in_abar_at_the_sets_sigma():
    """pbar = 3 (a random draw): at Abar = 2.42 the simulation stops (the restitution (21) is not
    real at an impact speed reached); continued in Abar, the start is an orbit at another Abar
    and the set's own sigma, a fixed point of (8)'s map by the reference flow."""
    params = Params(**NOT_REAL_AT_SPEED)
    start = impact_start(params, _state0(params), periods=150, p_range=(0.0, 4.84), param="Abar")
    assert start.params.sigma == params.sigma and 0.0 <= start.params.Abar <= 4.84
    assert start.params.Abar != params.Abar and "at Abar = 2.42" in start.found_from
    image = simulate_impact(start.params, start.x, (0.0, 2 * np.pi), backend="scipy").y[:, -1]
    np.testing.assert_allclose(image, start.x, rtol=0, atol=1e-8)


def test_a_start_settled_at_the_sets_sigma_is_kept_there():
    params = get_preset("fig13").params.replace(sigma=0.5)
    start = impact_start(params, _state0(params), periods=150, p_range=(-3.0, 5.0))
    assert start.params == params and "simulation settled at sigma = 0.5" in start.found_from


def test_a_range_without_the_sets_sigma_takes_the_slow_flows_start_inside_it():
    params = get_preset("fig13").params.replace(sigma=0.5)  # settles there (the test above)
    start = impact_start(params, _state0(params), periods=150, p_range=(2.0, 5.0))
    assert 2.0 <= start.params.sigma <= 5.0
    assert "the set's sigma = 0.5 lies outside [2, 5]" in start.found_from
    image = simulate_impact(start.params, start.x, (0.0, 2 * np.pi), backend="scipy").y[:, -1]
    np.testing.assert_allclose(image, start.x, rtol=0, atol=1e-8)


def test_shoot_model_impact_starts_from_the_slow_flow_where_the_simulation_does_not_settle(tmp_path, capsys):
    from slosh_bif.cli import main

    settings = [a for name, value in UNSETTLED.items() for a in ("--set", f"{name}={value}")]
    args = ["shoot", "--preset", "fig10", *settings, "--model", "impact", "--no-switch"]
    assert main([*args, "--sigma-min", "-2", "--sigma-max", "2", "--out", str(tmp_path)]) in (0, 3)
    err = capsys.readouterr().err
    assert re.search(r"start orbit at sigma = -?[\d.]+: a 150-period simulation from the slow flow", err)
    assert (tmp_path / "branch.csv").exists()


@pytest.mark.parametrize(
    "values, command, reason",
    [
        (NOT_REAL, "chart", r"kappa \(eq. 21\) is not real at an impact speed reached"),
        (BELOW, "shoot", "has not settled"),
    ],
)
def test_a_start_that_8_cannot_reach_is_named_with_what_to_change(tmp_path, capsys, values, command, reason):
    from slosh_bif.cli import main

    settings = [a for name, value in values.items() for a in ("--set", f"{name}={value}")]
    box = ["--sigma-min", "-2", "--sigma-max", "2", "--abar-min", "0.05", "--abar-max", "3"]
    args = [command, "--preset", "fig10", *settings, "--model", "impact", "--out", str(tmp_path)]
    assert main(args + (box if command == "chart" else [])) == 1
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "code " not in err
    assert re.search(reason, err)
    assert "(46) has no stable steady state in sigma in" in err
    assert ("--set sigma=S" if command == "chart" else "pass --guess") in err


def test_a_branch_whose_directions_meet_at_a_grazing_with_nothing_beyond_is_complete():
    """A random draw (n = 50, pbar = 2): period-2 and period-4 branches of (8) run from a grazing
    with no orbit beyond it, one way round, back to the same grazing (a loop through it): complete.
    A branch with such a dead end that no loop closes (its other direction ends elsewhere) is not."""
    from slosh_bif.studies.chart.impact import impact_family

    values = dict(eps=0.0757, beta=0.1757, gamma=0.3181, sigma=1.0, Abar=2.779, lam=0.5832, chi=1.144, n=50)
    params = Params(**values, pbar=2)
    start = impact_start(params, _state0(params), periods=150, p_range=(-4.0, 6.0))
    family = impact_family(start.params, start.x, param="sigma", p_range=(-4.0, 6.0))
    at = re.compile(r"grazing (?:at|of) sigma = (-?[\d.]+)")
    seen = set()
    for nb in family:
        reasons = sorted(e.reason for e in nb.branch.ends)
        found = [at.search(e.message) for e in nb.branch.ends]
        if not all(found):
            continue
        gap = abs(float(found[0].group(1)) - float(found[1].group(1)))
        if reasons == ["closed loop", "grazing"] and gap < 1e-6:
            assert nb.branch.complete, nb.name
            seen.add("a loop through its dead end")
        if "grazing" in reasons and gap > 1e-6:
            assert not nb.branch.complete, nb.name
            seen.add("a dead end no loop closes")
    assert seen == {"a loop through its dead end", "a dead end no loop closes"}
