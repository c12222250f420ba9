"""The continuation's predictor against a curve known in closed form: the cubic guess's error falls
as the fourth power of the step (third order), the second-order guess's as the third."""

import types

import numpy as np

from slosh_bif.continuation.options import ContinuationOptions
from slosh_bif.continuation.predictor import predictor


def _helix(s):
    """A helix parametrised by arclength (|u'| = 1) and its unit tangent."""
    c = 1 / np.sqrt(2.0)
    u = np.array([np.cos(c * s), np.sin(c * s), c * s])
    t = np.array([-c * np.sin(c * s), c * np.cos(c * s), c])
    return u, t


def _point(s):
    u, t = _helix(s)
    return types.SimpleNamespace(u=u, t=t)


def _errors(cubic):
    """Guess errors at h = 0.2, 0.1, 0.05: the cubic, or (``cubic=False``) the tangent plus the turn."""
    out = []
    for h in (0.2, 0.1, 0.05):
        points = [_point(-h), _point(0.0)]
        bend = (points[1].t - points[0].t) / np.linalg.norm(points[1].u - points[0].u)
        guess = predictor(points if cubic else points[1:], bend, h, ContinuationOptions())(h)
        out.append(np.linalg.norm(guess - _helix(h)[0]))
    return np.array(out)


def test_the_cubic_guess_is_third_order_and_beats_the_turn():
    cubic, turn = _errors(True), _errors(False)
    assert np.all(np.log2(cubic[:-1] / cubic[1:]) > 3.7)  # error ~ h^4
    assert np.all(np.log2(turn[:-1] / turn[1:]) < 3.3)  # the tangent plus its turn: h^3
    assert np.all(cubic < 0.06 * turn)


def test_a_previous_point_too_near_falls_back_to_the_turn():
    # a located special point just behind the last point would amplify its own error in the cubic
    h = 0.1
    points = [_point(-0.01 * h), _point(0.0)]
    bend = np.zeros(3)
    guess = predictor(points, bend, h, ContinuationOptions())(h)
    np.testing.assert_allclose(guess, points[1].u + h * points[1].t)
