"""The profile likelihood against its closed form: one parameter with residual (z - 1) / 0.1
crosses the 3.84 rise at 1 -+ 0.1 sqrt(3.84); a side where the objective loses its model (the
orbits it follows) ends there with no bound rather than at a rise the model never had."""

import math

import numpy as np
import pytest

from slosh_bif.identify.response_stats import lost_sentence, profile


class Line:
    """Residuals ((z - 1) / 0.1, 0, 0); beyond ``edge`` the model is lost (a large constant)."""

    names = ("a",)
    lower, upper = np.array([0.0]), np.array([np.inf])
    diff_step, jacobian = None, None

    def __init__(self, edge=np.inf):
        self.edge, self.lost = edge, False

    def __call__(self, z):
        self.lost = bool(z[0] > self.edge)
        return np.full(3, 1e3) if self.lost else np.array([(z[0] - 1.0) / 0.1, 0.0, 0.0])


HALF_WIDTH = 0.1 * math.sqrt(3.841458820694124)


def test_a_profile_crosses_where_the_closed_form_does():
    bounds, rows, lost = profile(
        Line(), np.array([1.0]), 0, 0.0, True, {"std": 0.1}, np.random.default_rng(0)
    )
    assert bounds == pytest.approx([1 - HALF_WIDTH, 1 + HALF_WIDTH], abs=1e-6) and not lost


def test_a_side_where_the_model_is_lost_has_no_bound_and_says_where():
    bounds, rows, lost = profile(
        Line(edge=1.15), np.array([1.0]), 0, 0.0, True, {"std": 0.1}, np.random.default_rng(0)
    )
    assert bounds[0] == pytest.approx(1 - HALF_WIDTH, abs=1e-6) and bounds[1] is None
    assert len(lost) == 1 and lost[0][0] > 0 and lost[0][1] > 1.15
    assert all(value <= 1.15 for value, _ in rows)  # the lost value is no row of the profile
    assert "a's profile stops at a = " in lost_sentence("a", lost)[0]
