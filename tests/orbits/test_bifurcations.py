"""Bifurcations of periodic orbits: the PD and NS test functions against closed forms, and a period
doubling of (9) with its period-2 branch checked by an independent integrator and by simulation."""

import itertools

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.flows.smooth.integrator import integrate_grid
from slosh_bif.orbits import BranchingSettings
from slosh_bif.orbits.families import trace_orbits
from slosh_bif.orbits.settings import ParameterRange
from slosh_bif.orbits.shooting import ShootingProblem
from slosh_bif.orbits.starts import settle_and_shoot

X0 = np.zeros(4)  # the states a GivenMonodromy ignores


class GivenMonodromy(ShootingProblem):
    """A ShootingProblem whose monodromy is a given function of the parameter (no integration)."""

    def __init__(self, monodromy_of_p):
        super().__init__(get_preset("fig10").params)
        self._of_p = monodromy_of_p

    def monodromy(self, x, p):
        return self._of_p(p)

    def arc_matrices(self, x, p):
        return [self._of_p(p)]


def second_compound(M):
    """The matrix of 2x2 minors of M: its eigenvalues are mu_i mu_j (i < j)."""
    pairs = list(itertools.combinations(range(len(M)), 2))
    return np.array([[np.linalg.det(M[np.ix_(r, c)]) for c in pairs] for r in pairs])


def test_test_functions_equal_determinants_computed_another_way():
    rng = np.random.default_rng(5)
    for _ in range(20):
        M = rng.normal(size=(4, 4))
        pd, ns = GivenMonodromy(lambda p: M).test_functions(X0, 0.0)
        assert pd == pytest.approx(np.linalg.det(M + np.eye(4)), rel=1e-9, abs=1e-12)
        assert ns == pytest.approx(np.linalg.det(second_compound(M) - np.eye(6)), rel=1e-9, abs=1e-12)


def rotation_block(r, theta):
    return r * np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])


def test_pd_and_ns_test_functions_change_sign_exactly_where_multipliers_cross():
    # A real multiplier s through -1: only the PD function changes sign, at s = -1.
    pd_family = GivenMonodromy(lambda s: np.diag([s, 0.3, -0.2, 0.1]))
    values = [pd_family.test_functions(X0, s) for s in (-0.99, -1.01)]
    assert values[0][0] * values[1][0] < 0 and values[0][1] * values[1][1] > 0
    assert pd_family.test_functions(X0, -1.0)[0] == pytest.approx(0.0, abs=1e-15)
    # A complex pair r exp(+-0.7i) through the unit circle: only the NS function, at r = 1.
    ns_family = GivenMonodromy(
        lambda r: np.block(
            [[rotation_block(r, 0.7), np.zeros((2, 2))], [np.zeros((2, 2)), np.diag([0.5, 0.2])]]
        )
    )
    values = [ns_family.test_functions(X0, r) for r in (0.99, 1.01)]
    assert values[0][1] * values[1][1] < 0 and values[0][0] * values[1][0] > 0
    assert "Neimark-Sacker" in ns_family.confirm("NS", X0, 1.0) and "rotation 0.111408" in ns_family.confirm(
        "NS", X0, 1.0
    )
    # A real pair mu, 1/mu (a neutral saddle) zeroes the NS function too; confirm() drops it.
    saddle = GivenMonodromy(lambda p: np.diag([2.0, 0.5, 0.3, 0.1]))
    assert saddle.test_functions(X0, 0.0)[1] == pytest.approx(0.0, abs=1e-15)
    assert saddle.confirm("NS", X0, 0.0) is None


@pytest.fixture(scope="module")
def period_doubling():
    """The stable asymmetric orbit of the Fig. 10 set at sigma = -3 (reached by simulation),
    continued to sigma = -1.5: it period-doubles at sigma = -2.5358, and the period-2 branch."""
    preset = get_preset("fig10")
    P = preset.params.replace(sigma=-3.0)
    orbit, _ = settle_and_shoot(P, preset.state0)
    family = trace_orbits(
        P, orbit.y0, branching=BranchingSettings(max_branches=2), interval=ParameterRange(lo=-3.0, hi=-1.5)
    )
    return P, family


def test_period_doubling_is_located_where_an_independent_monodromy_has_a_multiplier_minus_one(
    period_doubling, scipy_multipliers
):
    P, family = period_doubling
    parent, doubled = family.branches
    (pd,) = parent.branch.special_of("PD")
    assert -3.0 < pd.p < -1.5
    assert (
        np.min(np.abs(scipy_multipliers(P.replace(sigma=float(pd.p)), pd.x[:4]) + 1)) < 1e-4
    )  # scipy DOP853
    assert doubled.name == "period-2" and doubled.problem.period_multiple == 2
    assert f"PD at sigma = {pd.p:.6g} on the asymmetric branch" in doubled.origin


def test_period_two_orbits_are_4pi_but_not_2pi_periodic_and_grow_like_a_square_root(
    period_doubling, scipy_flow
):
    P, family = period_doubling
    parent, doubled = family.branches
    sigma_pd = parent.branch.special_of("PD")[0].p
    b = doubled.branch
    gaps, distances = [], []
    for i in range(0, 12, 2):
        Pi, y = P.replace(sigma=float(b.p[i])), b.x[i, :4]
        assert (
            np.linalg.norm(scipy_flow(Pi, y, 4 * np.pi)[0] - y) < 1e-7
        )  # 4pi-periodic by scipy's integrator
        gaps.append(np.linalg.norm(scipy_flow(Pi, y)[0] - y))  # not 2pi-periodic
        distances.append(abs(b.p[i] - sigma_pd))
    # Normal form of a period doubling: the two halves part like sqrt(|sigma - sigma_PD|).
    slope = np.polyfit(np.log(distances), np.log(gaps), 1)[0]
    assert slope == pytest.approx(0.5, abs=0.1) and min(gaps) > 1e-3


def test_stable_period_two_orbit_attracts_a_simulation(period_doubling):
    P, family = period_doubling
    b = family.branches[1].branch
    i = 3  # sigma = -2.507: stable between the parent's PD and the period-2 branch's own PD at -2.4585
    assert b.stable[i]
    Pi, y = P.replace(sigma=float(b.p[i])), b.x[i, :4]
    strobes = integrate_grid(
        Pi, y + np.array([1e-3, -1e-3, 2e-3, 0.0]), 2 * np.pi * np.arange(401)
    )  # 800 pi of (9)
    np.testing.assert_allclose(strobes[-1], y, atol=1e-6)  # back on the orbit every 4 pi ...
    assert np.linalg.norm(strobes[-2] - y) > 1e-3  # ... and half-way round at odd multiples of 2 pi


_CONDITIONS = {  # kind: (test function of the multipliers, distance of the multipliers from the condition)
    "LP": (lambda mu: np.prod(mu - 1).real, lambda mu: np.min(np.abs(mu - 1))),
    "BP": (lambda mu: np.prod(mu - 1).real, lambda mu: np.min(np.abs(mu - 1))),
    "PD": (lambda mu: np.prod(mu + 1).real, lambda mu: np.min(np.abs(mu + 1))),
    "NS": (
        lambda mu: np.prod([mu[i] * mu[j] - 1 for i in range(4) for j in range(i + 1, 4)]).real,
        lambda mu: min([abs(abs(m) - 1) for m in mu if abs(m.imag) > 1e-6] or [np.inf]),
    ),
}


@pytest.mark.slow
def test_every_special_point_of_the_fig10_family_satisfies_its_condition_by_scipy(scipy_multipliers):
    """The whole Fig. 10 family over sigma in [-6, 8] (started from the slow flow, switched at
    branch points and period doublings): at every located point, scipy's monodromy of the orbit
    (over its own period) has the multiplier the point's kind says, or, where the multipliers move
    too fast for that (the period-2 branch's grazing folds sweep the largest multiplier from -60
    to +39 within 1e-5 in sigma), scipy's test function changes sign between the neighbouring
    points. Liouville's check holds along every branch."""
    from slosh_bif.orbits.starts import slow_flow_start

    P = get_preset("fig10").params
    start = slow_flow_start(P, -6.0, 8.0)
    family = trace_orbits(start.params, start.y0, interval=ParameterRange(lo=-6.0, hi=8.0))
    names = [ob.name for ob in family.branches]
    assert names[0] == "symmetric" and "asymmetric" in names and "period-2" in names
    checked = 0
    for ob in family.branches:
        b, T = ob.branch, ob.problem.orbit_period
        assert np.max(ob.measures["liouville_error"]) < 1e-8
        for sp in b.special:
            if sp.kind == "END":
                continue
            test, distance = _CONDITIONS[sp.kind]
            if distance(scipy_multipliers(P.replace(sigma=float(sp.p)), sp.x[:4], T)) >= 1e-3:
                i, j = max(sp.index - 1, 0), min(sp.index + 1, len(b) - 1)
                assert (
                    test(scipy_multipliers(P.replace(sigma=float(b.p[i])), b.x[i, :4], T))
                    * test(scipy_multipliers(P.replace(sigma=float(b.p[j])), b.x[j, :4], T))
                    < 0
                ), (ob.name, sp.kind, sp.p)
            checked += 1
    assert checked >= 100
