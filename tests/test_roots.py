"""Brent's method (slosh_bif.roots) against scipy's brentq and closed-form roots."""

import math

import numpy as np
import pytest
from scipy import optimize

from slosh_bif.roots import brent

CASES = [  # (f, a, b, the root in closed form)
    (lambda x: x**3 - 2, 0.0, 3.0, 2 ** (1 / 3)),
    (lambda x: math.cos(x) - x, 0.0, 1.0, None),
    (lambda x: math.exp(x) - 10, -5.0, 5.0, math.log(10)),
    (lambda x: x**5 - x - 1, 0.0, 3.0, None),
    (lambda x: math.atan(1e6 * (x - 1e-3)), -1.0, 1.0, 1e-3),  # a step: interpolation overshoots
    (lambda x: x if x != 0 else 0.0, -1.0, 3.0, 0.0),
]


@pytest.mark.parametrize("f, a, b, root", CASES)
@pytest.mark.parametrize("xtol", [1e-13, 1e-8])
def test_brent_matches_brentq_and_the_closed_form(f, a, b, root, xtol):
    ours = brent(f, a, b, xtol=xtol)
    theirs = optimize.brentq(f, a, b, xtol=xtol)
    width = xtol + 4 * np.finfo(float).eps * abs(theirs)
    assert abs(ours - theirs) <= 2 * width
    if root is not None:
        assert abs(ours - root) <= width


def test_brent_takes_no_more_evaluations_than_bisection():
    calls = []

    def f(x):
        calls.append(x)
        return math.tanh(50 * (x - 0.123456789))

    x = brent(f, 0.0, 1.0, xtol=1e-13)
    assert abs(x - 0.123456789) < 1e-13
    assert len(calls) <= 2 + math.ceil(math.log2(1.0 / 1e-13)) + 1


def test_brent_refuses_a_bracket_without_a_sign_change_and_bad_tolerances():
    with pytest.raises(ValueError, match="same sign"):
        brent(lambda x: x * x + 1, -1.0, 1.0)
    with pytest.raises(ValueError, match="xtol"):
        brent(lambda x: x, -1.0, 1.0, xtol=0.0)
    with pytest.raises(ValueError, match="rtol"):
        brent(lambda x: x, -1.0, 1.0, rtol=1e-20)
    with pytest.raises(RuntimeError, match="did not converge in 3"):
        brent(lambda x: math.tanh(50 * (x - 0.1)), -1.0, 1.0, maxiter=3)


def test_brent_takes_the_ends_values_it_is_given():
    calls = []

    def f(x):
        calls.append(x)
        return x**3 - 2

    x = brent(f, 0.0, 3.0, xtol=1e-13, fa=-2.0, fb=25.0)
    assert abs(x - 2 ** (1 / 3)) < 1e-12
    assert 0.0 not in calls and 3.0 not in calls
