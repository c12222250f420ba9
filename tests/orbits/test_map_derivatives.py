"""The generated second and third derivatives of (9)'s right-hand side and the map's second and
third derivatives from the higher-order variational equations, against central differences of
the first-order ones (the generated Jacobian; scipy's monodromy by its own variational
equations), at a wall with pbar != 0."""

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.continuation.normal_forms import NormalForm
from slosh_bif.model._generated import models as gen
from slosh_bif.orbits.map_derivatives import COARSE_RTOL, FINE_RTOL, RTOL, FlowDerivatives, settle

P = get_preset("fig10").params.replace(n=6, pbar=2, sigma=1.5, lam=0.1)  # lam w' w^(2p) with p = 4
PARS = (P.eps, P.beta, P.gamma, P.sigma, P.Abar, P.lam, P.chi, P.n, P.p)
RNG = np.random.default_rng(11)
Y = np.array([0.3, -0.2, 0.93, 0.7])  # inside the wall's steep part
A, B, C = (RNG.normal(size=4) for _ in range(3))


def test_the_generated_second_and_third_derivatives_are_those_of_the_jacobian():
    h = 1e-6
    fd = (gen.smooth_jac(0.3, Y + h * B, *PARS) - gen.smooth_jac(0.3, Y - h * B, *PARS)) @ A / (2 * h)
    exact = gen.smooth_second(0.3, Y, A, B, *PARS)
    assert np.allclose(exact, fd, rtol=1e-6, atol=1e-6 * np.abs(fd).max())
    assert np.allclose(exact, gen.smooth_second(0.3, Y, B, A, *PARS), rtol=1e-13)  # symmetric
    fd3 = (
        gen.smooth_second(0.3, Y + h * C, A, B, *PARS) - gen.smooth_second(0.3, Y - h * C, A, B, *PARS)
    ) / (2 * h)
    exact3 = gen.smooth_third(0.3, Y, A, B, C, *PARS)
    assert np.allclose(exact3, fd3, rtol=1e-6, atol=1e-6 * np.abs(fd3).max())
    # finite at w = 0, where w^(2p - k) would be 0^-k without the guard
    assert np.all(np.isfinite(gen.smooth_third(0.0, np.zeros(4), A, B, C, *PARS)))


def _coefficients(values):
    """An ``evaluate(rtol)`` whose normal form has the coefficient ``values[rtol]`` (None: not
    computable at that tolerance), and the tolerances it was asked for."""
    asked = []

    def evaluate(rtol):
        asked.append(rtol)
        value = values[rtol]
        return None if value is None else NormalForm("PD", value, "soft", "ok", np.ones(4), np.ones(4))

    return evaluate, asked


@pytest.mark.parametrize(
    "coarse, fine, kept, settled, asked",
    [
        (1.1, 5.0, 1.0, True, [COARSE_RTOL]),  # within a quarter: the first integration stands
        (-0.3, 1.05, 1.05, True, [COARSE_RTOL, FINE_RTOL]),  # refined, and the finer one kept
        (None, 1.05, 1.05, True, [COARSE_RTOL, FINE_RTOL]),  # not computable coarsely: refined
        (-0.3, -0.9, -0.9, False, [COARSE_RTOL, FINE_RTOL]),  # the sign moves with the tolerance
        (-0.3, None, 1.0, False, [COARSE_RTOL, FINE_RTOL]),
    ],
)
def test_a_coefficient_is_kept_where_a_second_tolerance_agrees_with_it(coarse, fine, kept, settled, asked):
    evaluate, seen = _coefficients({COARSE_RTOL: coarse, RTOL: 1.0, FINE_RTOL: fine})
    nf, ok = settle(evaluate, evaluate(RTOL))
    assert (nf.coefficient, ok) == (kept, settled)
    assert seen[1:] == asked
    assert settle(evaluate, None) == (None, True)


@pytest.fixture(scope="module")
def flow():
    return FlowDerivatives(P, Y, 1.2)


def test_the_maps_second_derivative_is_the_difference_of_scipys_monodromy(flow, scipy_flow):
    h = 1e-5
    plus = scipy_flow(P, Y + h * B, 1.2)[1]
    minus = scipy_flow(P, Y - h * B, 1.2)[1]
    fd = (plus - minus) @ A / (2 * h)
    exact = flow.second(A, B)
    assert np.allclose(exact, fd, rtol=1e-5, atol=1e-5 * np.abs(fd).max())
    assert np.allclose(flow.jacobian(), scipy_flow(P, Y, 1.2)[1], rtol=1e-8, atol=1e-9)


def test_the_maps_third_derivative_is_the_difference_of_its_second(flow):
    h = 1e-4
    plus = FlowDerivatives(P, Y + h * C, 1.2).second(A, B)
    minus = FlowDerivatives(P, Y - h * C, 1.2).second(A, B)
    fd = (plus - minus) / (2 * h)
    exact = flow.third(A, B, C)
    assert np.allclose(exact, fd, rtol=1e-5, atol=1e-5 * np.abs(fd).max())


def test_the_compiled_path_and_scipys_agree(flow):
    slow = FlowDerivatives(P, Y, 1.2, backend="scipy")
    assert np.allclose(
        flow.third(A, B, C), slow.third(A, B, C), rtol=1e-8, atol=1e-8 * np.abs(slow.third(A, B, C)).max()
    )
    assert np.allclose(flow.jacobian(), slow.jacobian(), rtol=1e-9, atol=1e-10)


def test_complex_directions_follow_by_multilinearity(flow):
    q = A + 1j * B
    assert np.allclose(flow.second(q, np.conj(q)), flow.second(A, A) + flow.second(B, B), rtol=1e-12)
    value = flow.third(q, q, np.conj(q))
    assert np.allclose(value.real, flow.third(A, A, A) + flow.third(B, B, A), rtol=1e-10)


@pytest.fixture(scope="module")
def fig13_pitchforks():
    """The Fig. 13 set's symmetric branch over sigma in [-2.5, 1] with the asymmetric pair switched
    onto at its pitchforks (-2.034 and 0.374)."""
    from slosh_bif.orbits.families import trace_orbits
    from slosh_bif.orbits.settings import ParameterRange
    from slosh_bif.orbits.starts import slow_flow_start

    start = slow_flow_start(get_preset("fig13").params, -2.5, 1.0, segments=4)
    return trace_orbits(start.params, start.y0, interval=ParameterRange(name="sigma", lo=-2.5, hi=1.0))


@pytest.mark.slow  # the Fig. 13 family with its switched branches (about 20 s)
def test_each_pitchforks_verdict_is_what_its_switched_branch_does(fig13_pitchforks):
    """Soft: the asymmetric pair is born on the side where the symmetric orbit is unstable, and
    stable; hard: on the side where it is stable, and unstable (the package's own switched branch,
    found without the coefficient)."""
    from slosh_bif.orbits.map_derivatives import criticality

    symmetric, *others = fig13_pitchforks.branches
    pair = next(ob for ob in others if ob.name == "asymmetric")
    for sp in (s for s in symmetric.branch.special if s.kind == "BP"):
        nf = criticality(symmetric.problem.params_at(sp.p), sp.x[:4], "BP", symmetric=True)
        near = np.flatnonzero(np.abs(pair.branch.p - sp.p) < 0.02)
        assert near.size, f"no asymmetric orbit near the BP at {sp.p}"
        side = np.sign(np.median(pair.branch.p[near] - sp.p))
        # the parent's first point on the pair's side (the half-period map's branch steps 0.2 in sigma)
        beyond = np.flatnonzero((symmetric.branch.p - sp.p) * side > 1e-6)
        k = int(beyond[np.argmin(np.abs(symmetric.branch.p[beyond] - sp.p))])
        parent_stable_there = bool(symmetric.branch.stable[k])
        pair_stable = bool(np.all(pair.branch.stable[near]))
        soft = not parent_stable_there and pair_stable
        hard = parent_stable_there and not pair_stable
        assert soft or hard
        assert nf.verdict == ("soft" if soft else "hard"), (sp.p, nf.coefficient)


@pytest.mark.slow  # shares the Fig. 13 family above
def test_each_pitchforks_predicted_amplitude_is_its_switched_branchs(fig13_pitchforks):
    """The asymmetric orbits the switching found (without the coefficient) lie where the normal form
    puts them: the critical component at tau = 0 of the pair's two members (an orbit and its mirror
    image) differs by 2 growth |sigma - S|^0.5, and each is that far from the symmetric orbit
    (Newton at the same sigma), within 5 %, on the predicted side, where the unfolding parameter
    beta (the half-period multiplier -(1 + beta)) is at most 0.1, a tenth of its natural scale
    (sigma within 0.037 of the soft point, 0.0048 of the hard one, where the multiplier moves
    eight times faster)."""
    from slosh_bif.continuation.corrector import newton
    from slosh_bif.orbits.criticality import special_criticality
    from slosh_bif.orbits.map_derivatives import crossing_rate
    from slosh_bif.orbits.orbit_branch import mirror

    symmetric, *others = fig13_pitchforks.branches
    pair = next(ob for ob in others if ob.name == "asymmetric")
    verdicts = special_criticality(symmetric)
    assert len(verdicts) == 2
    for k, v in verdicts.items():
        c = ("X", "X'", "w", "w'").index(v.component)
        d = v.side * (pair.branch.p - v.at)
        sp = symmetric.branch.special[k]
        rate = crossing_rate(
            symmetric.problem.params_at, sp.p, sp.x[:4], sp.tangent[:4] / sp.tangent[-1], "BP", v.nf
        )
        agree, apart = [], []
        for i in np.flatnonzero((d > 1e-6) & (d * abs(rate) <= 0.1)):
            predicted = v.growth * np.sqrt(d[i])
            half = abs(pair.branch.x[i, c] - mirror(pair.problem, pair.branch.x[i])[c]) / 2
            if half / predicted < 3:  # the piece of the family through this pitchfork
                j = int(np.argmin(np.abs(symmetric.branch.p - pair.branch.p[i])))
                xs = newton(symmetric.problem, symmetric.branch.x[j], pair.branch.p[i])
                agree.append(half / predicted)
                apart.append(abs(pair.branch.x[i, c] - xs[c]) / predicted)
        assert len(agree) >= 2, (v.at, agree)
        assert np.allclose(agree, 1.0, atol=0.05), (v.at, agree)
        assert np.allclose(apart, 1.0, atol=0.05), (v.at, apart)


@pytest.mark.slow  # shares the Fig. 13 family above; two simulations of a few hundred periods
def test_a_simulation_past_a_soft_pitchfork_settles_at_the_predicted_size_past_a_hard_one_leaves(
    fig13_pitchforks,
):
    """Started beside the symmetric orbit on its unstable side: past the soft pitchfork (sigma =
    S + 0.01) the motion settles where the normal form says (the critical component's shift
    within 5 % of growth |sigma - S|^0.5); past the hard one (S - 0.003, where no small motion
    exists) it leaves the neighbourhood (ten times that size)."""
    from slosh_bif.continuation.corrector import newton
    from slosh_bif.flows.smooth.integrator import integrate
    from slosh_bif.orbits.criticality import special_criticality

    symmetric = fig13_pitchforks.branches[0]
    for v in special_criticality(symmetric).values():
        delta = 0.01 if v.verdict == "soft" else 0.003
        sigma = v.at + (v.side if v.verdict == "soft" else -v.side) * delta  # where the orbit is unstable
        j = int(np.argmin(np.abs(symmetric.branch.p - sigma)))
        xs = newton(symmetric.problem, symmetric.branch.x[j], sigma)[:4]
        P = symmetric.problem.params_at(sigma)
        y = xs + 1e-3 * np.real(v.nf.q)
        c = ("X", "X'", "w", "w'").index(v.component)
        size = v.growth * np.sqrt(delta)
        shifts = []
        for _ in range(600 if v.verdict == "soft" else 150):
            y = integrate(P, y, (0.0, 2 * np.pi)).z
            shifts.append(abs(y[c] - xs[c]))
        if v.verdict == "soft":
            assert np.ptp(shifts[-20:]) < 1e-3 * size, "not settled"
            assert shifts[-1] == pytest.approx(size, rel=0.05), (v.at, shifts[-1], size)
        else:
            assert max(shifts) > 10 * size, (v.at, max(shifts), size)


@pytest.mark.slow  # shares the Fig. 13 family above (its period-2 branches)
def test_each_period_doublings_predicted_size_is_its_switched_period_2_branchs(fig13_pitchforks):
    """The period-2 branches switched onto at the asymmetric branch's period doublings (-1.056 and
    -1.252, both soft), found without the coefficient, are born on the predicted side, stable, and
    their two iterates differ in the critical component at tau = 0 by 2 growth |sigma - S|^0.5
    within 5 % at up to a tenth of the branch's natural scale from the point (the smaller of 1 /
    |d beta / d sigma| and the distance to the next special point on the period-2 branch: a torus
    point 0.016 from the second doubling bounds its neighbourhood)."""
    from slosh_bif.flows.smooth.integrator import integrate
    from slosh_bif.orbits.criticality import special_criticality
    from slosh_bif.orbits.map_derivatives import crossing_rate

    branches = {ob.name: ob for ob in fig13_pitchforks.branches}
    asymmetric = branches["asymmetric"]
    verdicts = special_criticality(asymmetric)
    checked = 0
    for ob in branches.values():
        if not ob.origin.startswith("PD at") or "asymmetric" not in ob.origin:
            continue
        at = float(ob.origin.split("= ")[1].split(" ")[0])
        k = min(
            (k for k in verdicts if asymmetric.branch.special[k].kind == "PD"),
            key=lambda k: abs(asymmetric.branch.special[k].p - at),
        )
        v, sp = verdicts[k], asymmetric.branch.special[k]
        if abs(sp.p - at) > 1e-4 or v.nf.status != "ok" or sp.p > -1.0:
            continue  # the two doublings below sigma = -1, away from the clusters near resonance
        rate = crossing_rate(
            asymmetric.problem.params_at, sp.p, sp.x[:4], sp.tangent[:4] / sp.tangent[-1], "PD", v.nf
        )
        others = [abs(o.p - sp.p) for o in ob.branch.special if abs(o.p - sp.p) > 1e-6 and o.kind != "END"]
        scale = min([1 / abs(rate), *others])
        c = ("X", "X'", "w", "w'").index(v.component)
        ratios = []
        for p, x, stable in zip(ob.branch.p, ob.branch.x, ob.branch.stable):
            d = v.side * (p - sp.p)
            if 1e-7 < d <= scale / 10:
                image = integrate(ob.problem.params_at(p), x[:4], (0.0, 2 * np.pi)).z
                ratios.append(abs(x[c] - image[c]) / 2 / (v.growth * np.sqrt(d)))
                assert stable == (v.verdict == "soft"), (sp.p, p)
        assert len(ratios) >= 2 and np.allclose(ratios, 1.0, atol=0.05), (sp.p, ratios)
        assert not any(1e-7 < -v.side * (p - sp.p) < scale / 10 for p in ob.branch.p)  # not the other side
        checked += 1
    assert checked == 2


@pytest.mark.slow  # shares the Fig. 13 family above; simulations of a few thousand periods (seconds)
def test_past_a_soft_torus_point_a_simulation_settles_on_the_predicted_circle_past_a_hard_one_leaves(
    fig13_pitchforks,
):
    """Neimark-Sacker points: past the soft one on the period-2 branch (sigma = -1.2357, d < 0) a
    simulation started beside the unstable orbit settles on an invariant circle whose largest
    excursion in the critical component is growth |sigma - S|^0.5 to leading order: measured at two
    distances (a fiftieth and a twenty-fifth of the 0.024 to the branch's next torus point) the
    ratio to the prediction is 1 + c |sigma - S|^0.5 (the next order, about 4 and 6 % there),
    nearer 1 at the nearer one, and its value extrapolated to the point is 1 within 2 %; past the
    hard one on the asymmetric branch (0.3464, d > 0) it leaves the neighbourhood (ten times that
    size)."""
    from slosh_bif.continuation.corrector import newton
    from slosh_bif.flows.smooth.integrator import integrate
    from slosh_bif.orbits.criticality import special_criticality

    branches = {ob.name: ob for ob in fig13_pitchforks.branches}
    judged = []
    for name, near in (("period-2-2", -1.2357), ("asymmetric", 0.3464)):
        ob = branches[name]
        k, v = next(
            (k, v)
            for k, v in special_criticality(ob).items()
            if ob.branch.special[k].kind == "NS" and abs(ob.branch.special[k].p - near) < 1e-3
        )
        judged.append(v.verdict)
        c = ("X", "X'", "w", "w'").index(v.component)
        period = 2 * np.pi * ob.problem.period_multiple
        ratios = []
        for delta in (0.0005, 0.001) if v.verdict == "soft" else (0.005,):
            sigma = v.at + (v.side if v.verdict == "soft" else -v.side) * delta  # the orbit unstable
            j = int(np.argmin(np.abs(ob.branch.p - sigma)))
            xs = newton(ob.problem, ob.branch.x[j], sigma)[:4]
            P = ob.problem.params_at(sigma)
            y, excursions = xs + 1e-3 * np.real(v.nf.q), []
            for _ in range(6000):  # the circle is reached at a rate of order delta
                y = integrate(P, y, (0.0, period)).z
                excursions.append(abs(y[c] - xs[c]))
                if excursions[-1] > 1.0:
                    break
            size = v.growth * np.sqrt(delta)
            if v.verdict == "soft":
                assert np.ptp([max(excursions[-600:-300]), max(excursions[-300:])]) < 1e-3 * size  # settled
                ratios.append(max(excursions[-300:]) / size)
            else:
                assert max(excursions) > 10 * size, (v.at, max(excursions), size)
        if ratios:
            (r1, r2), (s1, s2) = ratios, np.sqrt([0.0005, 0.001])
            assert abs(r1 - 1) < abs(r2 - 1) < 0.1, ratios
            assert r1 - (r2 - r1) / (s2 - s1) * s1 == pytest.approx(1.0, abs=0.02), ratios
    assert judged == ["soft", "hard"]


def test_shoot_writes_and_prints_each_points_verdict(tmp_path, capsys):
    """The Fig. 13 set's symmetric branch: branch.csv's criticality column and shoot's lines give
    the pitchfork at -2.034 soft and the one at 0.374 hard (what their switched branches do: the
    slow test above)."""
    import csv
    import re

    from slosh_bif.cli import main

    argv = ["shoot", "--preset", "fig13", "--no-switch", "--sigma-min", "-3", "--sigma-max", "1"]
    assert main([*argv, "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "BP at sigma = -2.03387 on symmetric: soft (b = " in out
    assert re.search(r"BP at sigma = 0\.3738\d* on symmetric: hard \(b = ", out)
    assert "(sigma > -2.034), w at tau = 0 shifted by +-" in out  # the pair on the unstable side
    saved = np.load(tmp_path / "branch0_symmetric.npz")
    assert sorted(v for v in saved["special_verdict"] if v) == ["hard", "soft"]
    with open(tmp_path / "branch.csv", newline="") as fh:
        rows = [r for r in csv.DictReader(fh) if "BP" in r["special"]]
    verdicts = {round(float(r["sigma"]), 2): r["criticality"] for r in rows}
    assert verdicts[-2.03].startswith("BP soft") and verdicts[0.37].startswith("BP hard")


class _OneAtATime(FlowDerivatives):
    """(9)'s map derivatives with every real pair and triple integrated on its own (its own
    directions only): the bookkeeping of one integration for many checked against none."""

    def _fill(self, pairs, triples):
        for pair in pairs:
            super()._fill([pair], [])
        for triple in triples:
            super()._fill([], [triple])


def test_one_integration_for_many_directions_is_each_integrated_alone():
    """A Neimark-Sacker coefficient's C(q, q, conj q) (four real triples and three pairs in one
    integration) and B along two more directions, against each real pair and triple integrated
    with its own directions only."""
    q, h = A + 1j * B, C - 0.5j * A
    together, alone = FlowDerivatives(P, Y, 1.2), _OneAtATime(P, Y, 1.2)
    for form in ("third", "second"):
        args = (q, q, np.conj(q)) if form == "third" else (q, h)
        x, y = getattr(together, form)(*args), getattr(alone, form)(*args)
        assert np.allclose(x, y, rtol=1e-8, atol=1e-8 * np.abs(y).max()), form


def test_a_neimark_sacker_coefficient_takes_three_integrations(monkeypatch):
    """C(q, q, conj q) with B(q, q) and B(q, conj q) in one integration, then B(q, h11) and
    B(conj q, h20): three (seven with three directions an integration)."""
    import slosh_bif.orbits.map_derivatives as md
    from slosh_bif.continuation.normal_forms import neimark_sacker_coefficient

    calls = []
    real = md.integrate_variations
    monkeypatch.setattr(md, "integrate_variations", lambda *a, **k: calls.append(1) or real(*a, **k))
    flow = FlowDerivatives(P, Y, 1.2)
    theta = 1.1  # a map with a complex pair on the unit circle (the formula needs only A, B, C)
    A_ns = np.diag([0.5, 0.5, 0.2, 0.3])
    A_ns[:2, :2] = [[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]]
    nf = neimark_sacker_coefficient(A_ns, flow.second, flow.third)
    assert np.isfinite(nf.coefficient)
    assert len(calls) == 3


def test_a_triple_without_its_pairs_is_refused():
    from slosh_bif.flows.smooth.integrator import integrate_variations

    with pytest.raises(ValueError, match="needs its three pairs"):
        integrate_variations(P, Y, 1.2, [A, B, C], [(0, 1)], [(0, 1, 2)])
