"""The normal-form coefficient along curves of orbit bifurcations of (9) against independent
evaluations: at curve points, the coefficient of the same bifurcation found by one-parameter
continuation at the point's second parameter (its own location, tangent and integrated Jacobian,
not the curve's arcs); a degenerate point (GPD) of a curve against one-parameter branches
on either side of it, whose period doublings are soft on one side and hard on the other; and the
degenerate pitchforks of a curve against the coefficient integrated a hundred times more tightly;
curves and branch points whose coefficient does not settle under refinement, or cannot be
computed, undetermined."""

import copy
import dataclasses
import math

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.orbits import NO_SWITCHING, settle_and_shoot, trace_orbits
from slosh_bif.orbits.codim2 import CurveSeed, curve_boundary, curve_problem, trace_curve
from slosh_bif.orbits.codim2.coefficients import STRIDE, boundary, curve_coefficients
from slosh_bif.orbits.criticality import special_criticality
from slosh_bif.orbits.map_derivatives import FlowDerivatives, criticality
from slosh_bif.orbits.settings import ParameterRange
from slosh_bif.orbits.starts import start_orbit

PRESET = get_preset("fig10")


def test_the_boundary_reads_the_coefficients_sign_by_kind():
    b = np.array([0.5, -0.5, np.nan, 0.1])
    judged = np.array([1, 1, 1, 0])
    assert list(boundary("PD", b, judged)) == ["soft", "hard", "undetermined", "undetermined"]
    assert list(boundary("BP", b, judged))[:2] == ["soft", "hard"]
    assert list(boundary("NS", b, judged))[:2] == ["hard", "soft"]  # d < 0 is soft
    assert set(boundary("LP", b, judged)) == {"jump"}


@pytest.fixture(scope="module")
def flip_branch():
    """The Fig. 10 set's asymmetric orbits over sigma in [-3, -2.3], with a PD at sigma = -2.5358."""
    P = PRESET.params.replace(sigma=-3.0)
    orbit, _ = settle_and_shoot(P, PRESET.state0)
    family = trace_orbits(P, orbit.y0, branching=NO_SWITCHING, interval=ParameterRange(lo=-3.0, hi=-2.3))
    return P, family.branches[0]


@pytest.fixture(scope="module")
def flip_curve(flip_branch):
    """The period-doubling curve of (9) through that PD."""
    P, ob = flip_branch
    (pd,) = ob.branch.special_of("PD")
    return P, trace_curve(P, CurveSeed("PD", pd.x, pd.p), box={"sigma": (-2.9, -2.2), "Abar": (2.7, 3.3)})


def _one_parameter_verdict(P, x, sigma, abar, kind="PD"):
    """The verdict of the ``kind`` point nearest sigma on the one-parameter branch in sigma at
    Abar = abar, through the orbit x (states at tau = 0 first) from sigma - 0.02."""
    at = P.replace(sigma=float(sigma) - 0.02, Abar=float(abar))
    orbit, _ = settle_and_shoot(at, x[:4])
    family = trace_orbits(
        at,
        orbit.y0,
        branching=NO_SWITCHING,
        interval=ParameterRange(lo=float(sigma) - 0.02, hi=float(sigma) + 0.02),
    )
    ob = family.branches[0]
    found = special_criticality(ob)
    k = min(found, key=lambda k: abs(ob.branch.special[k].p - sigma))
    return ob.branch.special[k].p, found[k]


def test_the_curves_coefficient_is_that_of_one_parameter_branches_at_its_points(flip_curve):
    P, curve = flip_curve
    coefficient, kinds = curve_boundary(curve)
    assert len(curve) > 10 and np.all(np.isfinite(coefficient))
    for i in (0, STRIDE * (len(curve) // (2 * STRIDE)), STRIDE * ((len(curve) - 1) // STRIDE)):
        sigma, abar = curve["sigma"][i], curve["Abar"][i]
        p, verdict = _one_parameter_verdict(P, curve.branch.x[i, :-1], sigma, abar)
        assert p == pytest.approx(sigma, abs=1e-6)
        assert verdict.coefficient == pytest.approx(coefficient[i], rel=1e-4)
        assert verdict.verdict == kinds[i]


@pytest.fixture(scope="module")
def pitchfork_curve():
    """The BP curve of the Fig. 10 set through its symmetric orbit's pitchfork at sigma = -5.629,
    over the Fig. 10 chart's box: its coefficient b is a small difference of large terms where it
    passes sigma = 1.6-2.5 (b ~ 1e-3-1e-2, n = 50)."""
    P = PRESET.params
    start = start_orbit(P, PRESET.state0, (-6.0, -5.0))
    family = trace_orbits(
        start.params, start.y0, branching=NO_SWITCHING, interval=ParameterRange(lo=-6.0, hi=-5.0)
    )
    ob = family.branches[0]
    (bp,) = ob.branch.special_of("BP")
    return P, trace_curve(P, CurveSeed.on(ob, bp, "BP"), box={"sigma": (-6.0, 8.0), "Abar": (0.2, 6.0)})


def _refined(P, curve, x, p):
    """The curve point's pitchfork coefficient integrated at rtol 1e-13 (the curve's at 1e-11)."""
    at = P.replace(sigma=float(p), Abar=float(x[-1]))
    return criticality(at, x[:4], "BP", symmetric=True, rtol=1e-13).coefficient


def test_a_curves_degenerate_pitchforks_hold_under_refinement(pitchfork_curve):
    """Every DBP is a zero of b: its bracketing curve points have b of opposite signs integrated
    100 times more tightly, and b at the located point is small against them; and where b is
    small (sigma 1.6-2.5) the curve's b has the sign of the refined one at every third point (at
    the earlier tolerance, 1e-9, it changed sign four times there: spurious DBPs, a hard stretch)."""
    P, curve = pitchfork_curve
    b = curve.branch
    coefficient, kinds = curve_boundary(curve)
    dbp = [sp for sp in b.special if sp.kind == "DBP"]
    assert dbp, [sp.kind for sp in b.special]
    for sp in dbp:
        ends = [_refined(P, curve, b.x[i], b.p[i]) for i in (sp.index, sp.index + 1)]
        assert ends[0] * ends[1] < 0, (sp.p, ends)
        assert abs(_refined(P, curve, sp.x, sp.p)) < 1e-3 * max(map(abs, ends)), sp.message
        assert "located on the curve" in sp.message
    small = np.flatnonzero((b.p >= 1.6) & (b.p <= 2.5))[::STRIDE]
    assert len(small) >= 3
    for i in small:
        refined = _refined(P, curve, b.x[i], b.p[i])
        assert np.sign(coefficient[i]) == np.sign(refined), (b.p[i], coefficient[i], refined)
        assert kinds[i] == "soft"


class _Unsettled(FlowDerivatives):
    """(9)'s map derivatives with third derivatives off by a factor 1 + 1e12 rtol: a coefficient
    that moves by more than itself from each tolerance to the next (x1001, x11, x2 at 1e-9, 1e-11
    and 1e-12), as an integration's error does where the coefficient is a small difference."""

    def third(self, u, v, w):
        return (1 + 1e12 * self.rtol) * super().third(u, v, w)


def test_a_coefficient_that_does_not_settle_under_refinement_is_undetermined(pitchfork_curve):
    """The same curve with map derivatives whose coefficient changes with the tolerance: every
    computed point is undetermined, and no DBP is placed (the true ones included: their sign is
    not known from such derivatives)."""
    P, curve = pitchfork_curve
    b = curve.branch
    problem = curve_problem(P, "BP", "sigma", "Abar", segments=len(b.x[0][:-1]) // 4)
    branch = dataclasses.replace(b, special=tuple(sp for sp in b.special if sp.kind != "DBP"))
    noisy, measures = curve_coefficients(problem, branch, _Unsettled)
    assert not [sp for sp in noisy.special if sp.kind == "DBP"]
    computed = np.arange(0, len(branch), STRIDE)
    assert np.all(measures["judged"][computed] == 0)
    assert set(boundary("BP", measures["coefficient"], measures["judged"])) == {"undetermined"}


def _blind(box):
    """(9)'s map derivatives, not computable inside ``box`` ((sigma_lo, sigma_hi), (Abar_lo,
    Abar_hi)), as (8)'s map at a grazing is not."""
    (s0, s1), (a0, a1) = box

    class Blind(FlowDerivatives):
        def __init__(self, params, *args, **kwargs):
            if s0 <= params.sigma <= s1 and a0 <= params.Abar <= a1:
                raise ValueError("not computable here")
            super().__init__(params, *args, **kwargs)

    return Blind


def test_rows_beside_a_point_whose_coefficient_cannot_be_computed_are_undetermined(pitchfork_curve):
    """Where the coefficient cannot be computed (curve points 20-40) the curve's rows are
    undetermined, not labelled from the computed points on either side; away from there they keep
    the labels computed without the gap."""
    P, curve = pitchfork_curve
    b = curve.branch
    problem = curve_problem(P, "BP", "sigma", "Abar", segments=len(b.x[0][:-1]) // 4)
    abar = b.x[:, -1]
    gap = slice(20, 41)  # soft, away from the curve's codimension-2 points (from point 81 on)
    box = ((b.p[gap].min(), b.p[gap].max()), (abar[gap].min(), abar[gap].max()))
    inside = (b.p >= box[0][0]) & (b.p <= box[0][1]) & (abar >= box[1][0]) & (abar <= box[1][1])
    plain = curve_coefficients(problem, b)[1]
    blind = curve_coefficients(problem, b, _blind(box))[1]
    assert set(boundary("BP", plain["coefficient"][inside], plain["judged"][inside])) <= {"soft", "hard"}
    assert set(boundary("BP", blind["coefficient"][inside], blind["judged"][inside])) == {"undetermined"}
    away = np.ones(len(b), dtype=bool)
    away[10:51] = False
    assert np.array_equal(blind["judged"][away], plain["judged"][away])


def test_a_branch_points_verdict_is_undetermined_where_its_coefficient_does_not_settle(flip_branch):
    """The PD's verdict with (9)'s derivatives is soft or hard, its coefficient that at rtol 1e-11
    within the agreement asked of a settled one; with derivatives whose coefficient moves with the
    tolerance it is undetermined, and says so."""
    _, ob = flip_branch
    (k,) = [k for k, sp in enumerate(ob.branch.special) if sp.kind == "PD"]
    sp = ob.branch.special[k]
    plain = special_criticality(ob, only=k)[k]
    direct = criticality(ob.problem.params_at(sp.p), sp.x[:4], "PD", rtol=1e-11)
    assert plain.verdict in ("soft", "hard") and plain.coefficient == pytest.approx(
        direct.coefficient, rel=0.25
    )
    problem = copy.copy(ob.problem)
    problem.map_derivatives = _Unsettled  # the attribute by which (8)'s problems name their derivatives
    noisy = dataclasses.replace(ob, problem=problem)
    verdict = special_criticality(noisy, only=k)[k]
    assert verdict.verdict == "undetermined"
    assert "not settled under refinement" in verdict.nf.status and math.isnan(verdict.growth)


@pytest.mark.slow  # the Fig. 13 family with its switched branches, a PD curve, four short branches
def test_a_degenerate_flip_separates_soft_from_hard_period_doublings():
    """The PD curve of the Fig. 13 set's asymmetric orbits through sigma = -1.252 has a GPD near
    (-0.4165, 0.4507): one-parameter branches in sigma at the Abar of curve points a few steps to
    either side find period doublings there, soft on one side and hard on the other, as the curve
    says."""
    from slosh_bif.orbits.starts import slow_flow_start

    P = get_preset("fig13").params
    start = slow_flow_start(P, -2.5, 1.0, segments=4)
    family = trace_orbits(start.params, start.y0, interval=ParameterRange(name="sigma", lo=-2.5, hi=1.0))
    pd = min(
        (
            sp
            for ob in family.branches
            if ob.name.startswith("asymmetric")
            for sp in ob.branch.special_of("PD")
        ),
        key=lambda sp: abs(sp.p + 1.252),
    )
    assert pd.p == pytest.approx(-1.252, abs=1e-3)
    curve = trace_curve(P, CurveSeed("PD", pd.x, pd.p), box={"sigma": (-1.4, 0.0), "Abar": (0.3, 1.1)})
    gpd = [sp for sp in curve.branch.special if sp.kind == "GPD"]
    assert gpd, [sp.kind for sp in curve.branch.special]
    point = min(gpd, key=lambda sp: abs(sp.p + 0.4165))
    assert point.p == pytest.approx(-0.4165, abs=2e-3)
    j = point.index
    kinds = curve_boundary(curve)[1]
    sides = (j - STRIDE, j + 1 + STRIDE)
    assert {kinds[i] for i in sides} == {"soft", "hard"}
    for i in sides:
        _, verdict = _one_parameter_verdict(P, curve.branch.x[i, :-1], curve["sigma"][i], curve["Abar"][i])
        assert verdict.verdict == kinds[i], (i, verdict.coefficient)
