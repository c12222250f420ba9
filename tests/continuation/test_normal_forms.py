"""Normal-form coefficients of maps against closed forms (the Henon map's flip, maps written in
normal form) and against what the maps themselves do, found without the coefficient: the
period-2 orbit past a flip (closed form) and the invariant circle past a Neimark-Sacker point
(iterating the delayed logistic map), whose sizes the coefficient predicts."""

import math

import numpy as np
import pytest

from slosh_bif.continuation.normal_forms import (
    flip_coefficient,
    fold_coefficient,
    growth_law,
    neimark_sacker_coefficient,
)

ZERO3 = lambda u, v, w: np.zeros(len(u), dtype=complex)  # noqa: E731


def _henon(a, b):
    """The Henon map (x, y) -> (1 + y - a x^2, b x): its fixed point, Jacobian and B."""
    x = (-(1 - b) + math.sqrt((1 - b) ** 2 + 4 * a)) / (2 * a)
    A = np.array([[-2 * a * x, 1.0], [b, 0.0]])
    B = lambda u, v: np.array([-2 * a * u[0] * v[0], 0.0 * u[0]])  # noqa: E731
    return np.array([x, b * x]), A, B


@pytest.mark.parametrize("b", [0.3, -0.2, 0.6])
def test_the_henon_flip_coefficient_is_its_closed_form_and_predicts_the_period_2_orbit(b):
    a_c = 0.75 * (1 - b) ** 2  # the fixed point's multiplier is -1 here
    _, A, B = _henon(a_c, b)
    nf = flip_coefficient(A, B, ZERO3)
    # with q = (1, -b) the coefficient is a_c^2 / (1 - b^2); with |q| = 1 it has 1 + b^2 below too
    assert nf.coefficient == pytest.approx(a_c**2 / ((1 - b * b) * (1 + b * b)), rel=1e-8)
    assert nf.verdict == "soft" and nf.status == "ok"
    # past the flip: the period-2 orbit in closed form, x = (1 - b +- sqrt(4a - 3(1 - b)^2)) / (2a)
    a = a_c * (1 + 1e-5)
    fixed, A1, _ = _henon(a, b)
    mu = min(np.linalg.eigvals(A1).real)
    beta = -mu - 1.0  # the multiplier -(1 + beta)
    x2 = (1 - b + math.sqrt(4 * a - 3 * (1 - b) ** 2)) / (2 * a)
    xi = np.vdot(nf.p, np.array([x2, b * ((1 - b) / a - x2) / 1.0]) - fixed).real
    assert xi**2 == pytest.approx(beta / nf.coefficient, rel=1e-2)  # to leading order in xi ~ 5e-3


def test_the_growth_law_puts_the_henon_period_2_orbit_where_it_is():
    """growth_law with d beta / da of the closed-form multiplier: the period-2 point lies
    K (a - a_c)^0.5 from the fixed point (closed form) on the side a > a_c, within 1 %."""
    b = 0.3
    a_c = 0.75 * (1 - b) ** 2
    _, A, B = _henon(a_c, b)
    nf = flip_coefficient(A, B, ZERO3)

    def beta(a):
        return -min(np.linalg.eigvals(_henon(a, b)[1]).real) - 1.0

    h = 1e-6
    K, side = growth_law(nf, (beta(a_c + h) - beta(a_c - h)) / (2 * h))
    assert side == 1
    a = a_c * (1 + 1e-5)
    fixed = _henon(a, b)[0]
    x2 = (1 - b + math.sqrt(4 * a - 3 * (1 - b) ** 2)) / (2 * a)
    distance = np.linalg.norm(np.array([x2, b * ((1 - b) / a - x2)]) - fixed)
    assert distance == pytest.approx(K * math.sqrt(a - a_c), rel=1e-2)
    assert growth_law(fold_coefficient(np.array([[1.0]]), lambda u, v: u * v), 1.0) == (math.nan, 0) or (
        math.isnan(growth_law(fold_coefficient(np.array([[1.0]]), lambda u, v: u * v), 1.0)[0])
    )


def test_a_map_in_flip_normal_form_gives_its_coefficient_and_sign():
    for c, verdict in ((1.0, "soft"), (-2.5, "hard")):
        nf = flip_coefficient(np.array([[-1.0]]), lambda u, v: 0 * u, lambda u, v, w: 6 * c * u * v * w)
        assert nf.coefficient == pytest.approx(c, rel=1e-12) and nf.verdict == verdict


def test_a_map_in_neimark_sacker_normal_form_gives_its_lyapunov_coefficient():
    """x -> R(theta) (x + s |x|^2 x): in z = <p, x> with |q| = 1, z -> e^{i theta} z (1 + 2 s |z|^2)."""
    theta = 0.9
    R = np.array([[math.cos(theta), -math.sin(theta)], [math.sin(theta), math.cos(theta)]])
    for s, verdict in ((1.0, "hard"), (-0.5, "soft")):

        def C(u, v, w, s=s):
            return 2 * s * R @ (np.dot(u, v) * w + np.dot(u, w) * v + np.dot(v, w) * u)

        nf = neimark_sacker_coefficient(R, lambda u, v: 0 * u, C)
        assert nf.coefficient == pytest.approx(2 * s, rel=1e-10) and nf.verdict == verdict


def _delayed_logistic(r):
    x = 1 - 1 / r
    A = np.array([[1.0, -(r - 1)], [1.0, 0.0]])  # r (1 - y), -r x at the fixed point
    B = lambda u, v: np.array([-r * (u[0] * v[1] + u[1] * v[0]), 0 * u[0]])  # noqa: E731
    return np.array([x, x]), A, B


def test_the_delayed_logistic_maps_invariant_circle_has_the_predicted_size():
    """(x, y) -> (r x (1 - y), x): a Neimark-Sacker point at r = 2 (multipliers e^{+-i pi/3});
    iterated at r = 2.002, the orbit settles on a circle whose radius in z = <p, x - x*> is
    sqrt(-beta / d) to within 5 % (|mu| = 1 + beta)."""
    _, A, B = _delayed_logistic(2.0)
    nf = neimark_sacker_coefficient(A, B, ZERO3)
    assert nf.verdict == "soft" and nf.status == "ok"
    r = 2.002
    fixed, A1, _ = _delayed_logistic(r)
    beta = abs(np.linalg.eigvals(A1)[0]) - 1.0
    z = fixed + np.array([1e-3, 0.0])
    radii = []
    for k in range(400_000):
        z = np.array([r * z[0] * (1 - z[1]), z[0]])
        if k > 390_000:
            radii.append(abs(np.vdot(nf.p, z - fixed)))
    assert np.mean(radii) ** 2 == pytest.approx(-beta / nf.coefficient, rel=0.05)


def test_the_fold_coefficient_and_the_named_cases():
    """x -> x + a x^2 (a multiplier at +1): a; a resonance 1:4 and a map without a complex pair named."""
    nf = fold_coefficient(np.array([[1.0]]), lambda u, v: 2 * 0.7 * u * v)
    assert nf.coefficient == pytest.approx(0.7) and nf.verdict == "jump"
    quarter = np.array([[0.0, -1.0], [1.0, 0.0]])  # a rotation by pi / 2
    assert "1:4" in neimark_sacker_coefficient(quarter, lambda u, v: 0 * u, ZERO3).status
    assert neimark_sacker_coefficient(np.diag([0.5, -1.0]), lambda u, v: 0 * u, ZERO3).status.startswith(
        "no complex"
    )
    degenerate = flip_coefficient(np.array([[-1.0]]), lambda u, v: 0 * u, lambda u, v, w: 0 * u)
    assert degenerate.verdict == "undetermined" and "codimension-2" in degenerate.status


def test_a_second_critical_multiplier_makes_the_verdict_undetermined():
    """A flip with a second multiplier at 1 + 1e-4 (a fold-flip point near): no sign is given."""
    A = np.diag([-1.0, 1.0 + 1e-4])
    nf = flip_coefficient(A, lambda u, v: 0 * u, lambda u, v, w: 6 * u * v * w)
    assert nf.verdict == "undetermined" and "codimension-2" in nf.status
