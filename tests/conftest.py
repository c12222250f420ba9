"""Independent references for the orbit and basin tests: scipy's DOP853 (``solve_ivp`` through
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
