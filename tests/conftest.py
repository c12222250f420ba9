"""Independent references and shared arguments for the tests: scipy's DOP853 (``solve_ivp`` through
:func:`~slosh_bif.orbits.shooting.period_map`, not the compiled shooting path) integrates (9) and
its variational equations, so a number the shooting code produced is checked by a second code."""

import sys
from pathlib import Path

import numpy as np
import pytest

from slosh_bif import SmoothModel
from slosh_bif.orbits.shooting import period_map

# The benchmarks (benchmarks/, beside the package, run as `python -m benchmarks` from the checkout)
# are importable in the tests.
ROOT = str(Path(__file__).resolve().parents[1])
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)


def _scipy_period_map(P, y0, period=2 * np.pi):
    model = SmoothModel(P)
    return period_map(model.rhs, model.jac, np.asarray(y0, float), period, rtol=1e-12, atol=1e-13)[:2]


@pytest.fixture(scope="session")
def scipy_flow():
    """``scipy_flow(P, y0, period)`` -> (state after ``period``, monodromy), by scipy DOP853 at rtol 1e-12."""
    return _scipy_period_map


@pytest.fixture(scope="session")
def scipy_multipliers():
    """``scipy_multipliers(P, y0, period)`` -> the eigenvalues of scipy's monodromy."""
    return lambda P, y0, period=2 * np.pi: np.linalg.eigvals(_scipy_period_map(P, y0, period)[1])


def _scipy_orbit_amplitudes(params, sigmas):
    """A1 of the stable 2pi-orbits of (9) at ``sigmas``, each from the slow flow's state by Newton
    on scipy's integration (the fit's orbits use the compiled one)."""
    from slosh_bif.identify.response_model import response_curve
    from slosh_bif.orbits.orbit_tools import orbit_measures
    from slosh_bif.orbits.shooting import ShootingProblem
    from slosh_bif.orbits.starts import orbit_from_slow_flow

    curve, out = response_curve(params), []
    for s in sigmas:
        at = params.replace(sigma=float(s))
        orbit = orbit_from_slow_flow(at, max(a for a, ok in curve.states_at(s) if ok), backend="scipy")
        assert orbit.converged and orbit.stable
        problem = ShootingProblem(at, segments=4, backend="scipy")
        out.append(orbit_measures(problem, problem.initial_states(orbit.y0, s), s)["A1"])
    return np.array(out)


@pytest.fixture(scope="session")
def scipy_orbit_amplitudes():
    """``scipy_orbit_amplitudes(params, sigmas)`` -> A1 of the stable 2pi-orbits of (9) at ``sigmas``,
    found on scipy's integration (not the fits' compiled path)."""
    return _scipy_orbit_amplitudes


@pytest.fixture
def beta_chart() -> list:
    """A small chart in (sigma, beta) of the Fig. 10 set (12 curve starts, seconds): the arguments
    of ``slosh-bif chart`` but ``--out``."""
    return [
        "chart",
        "--preset",
        "fig10",
        "--set",
        "sigma=-1.2",
        "--set",
        "beta=0.1",
        "--sigma-min",
        "-2",
        "--sigma-max",
        "1.5",
        "--second",
        "beta",
        "--second-min",
        "0.05",
        "--second-max",
        "0.3",
        "--no-switch",
        "--seeds",
        "3",
    ]


@pytest.fixture
def fold_chart() -> list:
    """The smallest (sigma, Abar) chart: the fold of the Fig. 10 set's symmetric orbits near
    sigma = -1.4 (one LP curve, seconds): the arguments of ``slosh-bif chart`` but ``--out``."""
    return [
        "chart",
        "--preset",
        "fig10",
        "--set",
        "sigma=-1.2",
        "--sigma-min",
        "-1.6",
        "--sigma-max",
        "-1.2",
        "--abar-min",
        "2.6",
        "--abar-max",
        "3.4",
        "--no-switch",
        "--seeds",
        "0",
    ]
