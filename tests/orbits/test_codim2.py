"""Two-parameter curves of orbit bifurcations of (9), checked by independent evaluations: one-
parameter continuation at the curve's second parameter locates its fold or period doubling at
the curve's first parameter, and scipy's monodromy (not the shooting code) has the critical
multiplier there (issue 16)."""

import dataclasses

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.continuation import continuation
from slosh_bif.orbits import (
    NO_SWITCHING,
    ShootingProblem,
    ShootingSettings,
    orbit_at,
    orbit_from_simulation,
    settle_and_shoot,
    trace_orbits,
)
from slosh_bif.orbits.codim2 import (
    CURVE_OPTIONS,
    BifurcationCurve,
    CurveSeed,
    FoldCurveProblem,
    curve_problem,
    trace_curve,
)
from slosh_bif.orbits.families import SHOOTING_OPTIONS
from slosh_bif.orbits.pitchforks import refine_pitchforks
from slosh_bif.orbits.settings import ParameterRange

PRESET = get_preset("fig10")


@pytest.fixture(scope="module")
def fold_curve():
    """The fold curve through the fold of the symmetric branch at sigma = -1.40027 (Abar = 3),
    in a small box."""
    P = PRESET.params
    start = orbit_from_simulation(P.replace(sigma=-1.2), PRESET.state0, settle=150)
    family = trace_orbits(
        start.params, start.y0, branching=NO_SWITCHING, interval=ParameterRange(lo=-1.6, hi=-1.2)
    )
    (lp,) = family.branches[0].branch.special_of("LP")
    return P, trace_curve(P, CurveSeed("LP", lp.x, lp.p), box={"sigma": (-1.8, -1.0), "Abar": (2.4, 3.6)})


@pytest.fixture(scope="module")
def flip_curve():
    """The period-doubling curve through the PD of the asymmetric orbit at sigma = -2.5358."""
    P = PRESET.params.replace(sigma=-3.0)
    orbit, _ = settle_and_shoot(P, PRESET.state0)
    family = trace_orbits(P, orbit.y0, branching=NO_SWITCHING, interval=ParameterRange(lo=-3.0, hi=-2.3))
    (pd,) = family.branches[0].branch.special_of("PD")
    return P, trace_curve(P, CurveSeed("PD", pd.x, pd.p), box={"sigma": (-2.9, -2.2), "Abar": (2.7, 3.3)})


@pytest.fixture(scope="module")
def torus_curve():
    """The Neimark-Sacker curve through the NS point of the symmetric branch at sigma = 0.8806."""
    P = PRESET.params
    start = orbit_from_simulation(P.replace(sigma=6.0), PRESET.state0, settle=100)  # the symmetric orbit
    family = trace_orbits(
        start.params,
        start.y0,
        shooting=ShootingSettings(points_per_2pi=32),
        branching=NO_SWITCHING,
        interval=ParameterRange(lo=-1.6, hi=6.0),
    )  # past the fold at -1.40
    ns = [s for s in family.branches[0].branch.special_of("NS") if abs(s.p - 0.8806) < 1e-3][0]
    return P, trace_curve(P, CurveSeed("NS", ns.x, ns.p), box={"sigma": (0.6, 1.2), "Abar": (2.6, 3.4)})


def test_torus_curve_points_have_a_pair_on_the_unit_circle_by_scipy(torus_curve, scipy_multipliers):
    P, curve = torus_curve
    assert curve.kind == "NS" and len(curve) > 10 and curve.status == "ok", curve.branch.message
    for i in np.linspace(1, len(curve) - 2, 3).astype(int):
        sigma, abar, theta = curve["sigma"][i], curve["Abar"][i], curve["theta"][i]
        x = curve.branch.x[i, :-2]
        mu = scipy_multipliers(P.replace(sigma=float(sigma), Abar=float(abar)), x[:4])
        pair = mu[np.argmin(np.abs(mu - np.exp(1j * theta)))]
        assert abs(abs(pair) - 1) < 1e-6 and abs(np.angle(pair) - theta) < 1e-6
        assert _one_parameter_special(P, "NS", x, sigma, abar) == pytest.approx(sigma, abs=1e-6)


@pytest.fixture(scope="module")
def resonant_torus_curve():
    """The NS curve of the Fig. 13 set through the symmetric orbit's torus point at sigma = 3.98266
    (Abar = 1): down past a fold-NS point at sigma = 0.125, turning at -0.57 and back to a 1:1
    resonance at sigma = 0.132."""
    P = get_preset("fig13").params
    start = orbit_from_simulation(P.replace(sigma=4.2), get_preset("fig13").state0, settle=150)
    family = trace_orbits(
        start.params,
        start.y0,
        shooting=ShootingSettings(points_per_2pi=32),
        branching=NO_SWITCHING,
        interval=ParameterRange(lo=3.8, hi=4.2),
    )
    ns = [s for s in family.branches[0].branch.special_of("NS") if abs(s.p - 3.98266) < 1e-3][0]
    return P, trace_curve(P, CurveSeed("NS", ns.x, ns.p), box={"sigma": (-1.0, 4.2), "Abar": (0.6, 1.2)})


def test_torus_curve_is_continued_to_a_strong_resonance_and_ends_there(
    resonant_torus_curve, scipy_multipliers
):
    # kappa = cos(theta) is regular through the 1:1 resonance: the test kappa - 1 changes sign,
    # the point is located and the curve ends on it; scipy's monodromy there has a double +1.
    P, curve = resonant_torus_curve
    assert curve.status == "ok", curve.branch.message
    (r1,) = [s for s in curve.branch.special if s.kind == "R1"]
    assert r1.located and r1.reason == "terminal point" and r1.index in (0, len(curve) - 1)
    assert r1.x[-1] == pytest.approx(1.0, abs=1e-8) and np.all(np.abs(curve["kappa"]) <= 1 + 1e-8)
    assert r1.p == pytest.approx(0.1324, abs=2e-3) and r1.x[-2] == pytest.approx(0.797, abs=2e-3)
    mu = scipy_multipliers(P.replace(sigma=float(r1.p), Abar=float(r1.x[-2])), r1.x[:4])
    near_one = np.sort(np.abs(mu - 1))
    assert (
        near_one[1] < 1e-3 and near_one[2] > 0.01
    )  # a double multiplier +1 (a Jordan block splits it by sqrt(rounding))


@pytest.fixture(scope="module")
def pitchfork_curve():
    """The symmetry-breaking curve through the pitchfork of the symmetric branch at sigma = 3.347."""
    P = PRESET.params
    start = orbit_from_simulation(P.replace(sigma=6.0), PRESET.state0, settle=100)
    family = trace_orbits(
        start.params,
        start.y0,
        shooting=ShootingSettings(points_per_2pi=32),
        branching=NO_SWITCHING,
        interval=ParameterRange(lo=3.0, hi=6.0),
    )
    (bp,) = family.branches[0].branch.special_of("BP")
    return P, trace_curve(P, CurveSeed("BP", bp.x, bp.p), box={"sigma": (2.5, 4.5), "Abar": (2.5, 3.5)})


def test_pitchfork_curve_points_are_branch_points_of_the_full_problem(pitchfork_curve, scipy_multipliers):
    # The curve solves the half-period map's condition; the full 2pi problem and scipy's
    # full-period monodromy see a branch point (multiplier +1 without a fold) there.
    P, curve = pitchfork_curve
    assert curve.kind == "BP" and len(curve) > 10 and curve.status == "ok", curve.branch.message
    for i in np.linspace(1, len(curve) - 2, 3).astype(int):
        sigma, abar = curve["sigma"][i], curve["Abar"][i]
        at = P.replace(sigma=float(sigma), Abar=float(abar))
        full = ShootingProblem(at, "sigma", segments=4).initial_states(curve.branch.x[i, :4])
        # The engine's bordered-determinant test brackets the pitchfork (its corrector fails
        # near it); the half-period refinement of the one-parameter branch lands on the curve.
        bracket = []
        assert _one_parameter_special(P, "BP", full, sigma, abar, bracket) == pytest.approx(sigma, abs=1e-6)
        assert min(bracket) <= sigma <= max(bracket)
        assert np.min(np.abs(scipy_multipliers(at, full[:4]) - 1)) < 1e-6


def _one_parameter_special(P, kind, x, sigma, abar, bracket=None):
    """The special point of ``kind`` found by one-parameter continuation in sigma at Abar = abar."""
    return _special_in(P.replace(sigma=float(sigma), Abar=float(abar)), kind, x, "sigma", bracket)


def _special_in(at, kind, x, param, bracket=None):
    """The special point of ``kind`` found by one-parameter continuation in ``param`` from the curve
    point ``at`` (every other parameter held), crossed in the interior of the run, where it is
    detected and located afresh. A PD, NS or BP is a regular point of its branch: the run starts
    from the orbit 0.02 below it. A fold is not (no orbit on one side): a first run from the fold
    finds the branch, and a second starts ten points away from it."""
    value = float(getattr(at, param))
    problem = ShootingProblem(at, param, segments=4)
    opts = dataclasses.replace(
        SHOOTING_OPTIONS, p_min=value - 0.05, p_max=value + 0.05, step=0.002, step_max=0.004
    )
    if kind == "LP":
        first = continuation(problem, x, value, param=param, options=opts)
        near = int(np.argmin(np.abs(first.p - value) + np.linalg.norm(first.x - x, axis=1)))
        j = near - 10 if near >= 10 else near + 10
        start, p0 = first.x[j], first.p[j]
    else:
        orbit = orbit_at(problem, x, value - 0.02)
        assert orbit.converged, orbit.message
        start, p0 = problem.initial_states(orbit.y0, value - 0.02), value - 0.02
    second = continuation(problem, start, p0, param=param, options=opts)
    found = [
        s
        for s in (refine_pitchforks(problem, second) if kind == "BP" else second).special
        if s.kind == kind and s.located
    ]
    assert found, f"no {kind} within 0.05 of {param} = {value} at {at}"
    nearest = min(found, key=lambda s: abs(s.p - value))
    if bracket is not None:
        bracket.extend(nearest.bracket)
    return nearest.p


@pytest.mark.parametrize(
    "curve_fixture, kind, mu",
    [pytest.param("fold_curve", "LP", 1.0, marks=pytest.mark.slow), ("flip_curve", "PD", -1.0)],
)
def test_curve_points_are_special_points_of_one_parameter_branches_and_of_scipys_monodromy(
    curve_fixture, kind, mu, request, scipy_multipliers
):
    P, curve = request.getfixturevalue(curve_fixture)
    assert curve.kind == kind and len(curve) > 10 and curve.status == "ok", curve.branch.message
    for i in np.linspace(1, len(curve) - 2, 3).astype(int):
        sigma, abar = curve["sigma"][i], curve["Abar"][i]
        x = curve.branch.x[i, :-1]
        assert _one_parameter_special(P, kind, x, sigma, abar) == pytest.approx(sigma, abs=1e-6)
        multipliers = scipy_multipliers(P.replace(sigma=float(sigma), Abar=float(abar)), x[:4])
        assert np.min(np.abs(multipliers - mu)) < 1e-6


@pytest.mark.parametrize("curve_fixture, kind", [("fold_curve", "LP"), ("flip_curve", "PD")])
def test_a_curve_read_between_its_points_is_corrected_onto_a_one_parameter_runs_point(
    curve_fixture, kind, request
):
    # Between two computed points, at a sigma of neither, the crossing corrected on the curve's
    # system is the special point a one-parameter run in Abar at that sigma locates; the linear
    # interpolation between the points is further off (the corrected value is no interpolation).
    from slosh_bif.orbits.codim2 import corrected_at

    P, curve = request.getfixturevalue(curve_fixture)
    i = len(curve) // 3
    sigma = 0.5 * (curve["sigma"][i] + curve["sigma"][i + 1])
    corrected = corrected_at(curve, P, sigma, i)
    assert corrected is not None
    x = curve.branch.x[i, :-1]
    exact = _special_in(P.replace(sigma=float(sigma), Abar=float(corrected)), kind, x, "Abar")
    assert corrected == pytest.approx(exact, abs=1e-7)
    interpolated = 0.5 * (curve["Abar"][i] + curve["Abar"][i + 1])
    assert abs(interpolated - exact) > abs(corrected - exact)


@pytest.fixture(scope="module")
def beta_fold_curve():
    """A fold curve in (sigma, beta): the fold of the symmetric branch at beta = 0.1 (Abar = 3)."""
    P = PRESET.params.replace(beta=0.1)
    start = orbit_from_simulation(P.replace(sigma=-1.2), PRESET.state0, settle=150)
    family = trace_orbits(
        start.params, start.y0, branching=NO_SWITCHING, interval=ParameterRange(lo=-1.7, hi=-1.2)
    )
    (lp,) = family.branches[0].branch.special_of("LP")
    return P, trace_curve(P, CurveSeed("LP", lp.x, lp.p), box={"sigma": (-1.8, -1.0), "beta": (0.02, 0.25)})


@pytest.fixture(scope="module")
def eps_flip_curve():
    """A period-doubling curve in (Abar, eps) through the PD of the asymmetric orbit found on a
    sigma branch (sigma = -2.5358 held): the start branch's parameter is neither of the two."""
    P = PRESET.params.replace(sigma=-3.0)
    orbit, _ = settle_and_shoot(P, PRESET.state0)
    family = trace_orbits(P, orbit.y0, branching=NO_SWITCHING, interval=ParameterRange(lo=-3.0, hi=-2.3))
    (pd,) = family.branches[0].branch.special_of("PD")
    return P.replace(sigma=pd.p), trace_curve(
        P, CurveSeed("PD", pd.x, pd.p, branch_param="sigma"), box={"Abar": (2.6, 3.4), "eps": (0.04, 0.06)}
    )


@pytest.mark.parametrize(
    "curve_fixture, mu",
    [pytest.param("beta_fold_curve", 1.0, marks=pytest.mark.slow), ("eps_flip_curve", -1.0)],
)
def test_curves_in_other_parameter_pairs_match_one_parameter_runs_and_scipy(
    curve_fixture, mu, request, scipy_multipliers
):
    # Any two real fields of Params: the curve's sensitivities come from the generated pair kernel;
    # a one-parameter run in p1 with p2 held (the dedicated or pair kernel of another problem)
    # and scipy's monodromy (no shooting code) check it.
    P, curve = request.getfixturevalue(curve_fixture)
    assert len(curve) > 10 and curve.status == "ok", curve.branch.message
    assert np.ptp(curve[curve.p2]) > 0.005, "the curve must move in its second parameter"
    for i in np.linspace(1, len(curve) - 2, 3).astype(int):
        at = P.replace(**{curve.p1: float(curve[curve.p1][i]), curve.p2: float(curve[curve.p2][i])})
        x = curve.branch.x[i, :-1]
        assert _special_in(at, curve.kind, x, curve.p1) == pytest.approx(curve[curve.p1][i], abs=1e-6)
        assert np.min(np.abs(scipy_multipliers(at, x[:4]) - mu)) < 1e-6


def test_the_curve_is_the_same_under_tighter_tolerances(fold_curve):
    # Convergence under refinement: the integration and corrector tolerances 100 times tighter
    # move the curve by less than 1e-7 in Abar at the same sigma.
    P, curve = fold_curve
    i = len(curve) // 2
    x = curve.branch.x[i]
    problem = FoldCurveProblem(P, rtol=1e-12, atol=1e-14)
    problem.init_borders(x, curve["sigma"][i])
    from slosh_bif.continuation import newton

    tight = newton(problem, x, curve["sigma"][i], tol=1e-12)
    assert abs(tight[-1] - x[-1]) < 1e-7
    # The curve does not depend on the bordering vectors: borders from another point of it, never
    # refreshed, give the same point.
    fixed = FoldCurveProblem(P, refresh_borders=False)
    fixed.init_borders(curve.branch.x[i - 5], curve["sigma"][i - 5])
    fixed.accept(x, curve["sigma"][i])  # a no-op without refreshing
    again = newton(fixed, x + 1e-6, curve["sigma"][i], tol=1e-10)
    assert np.max(np.abs(again - x)) < 1e-7


def test_curve_round_trips_through_npz(fold_curve, tmp_path):
    _, curve = fold_curve
    loaded = BifurcationCurve.load(curve.save(tmp_path / "lp.npz"))
    assert (loaded.kind, loaded.p1, loaded.p2, loaded.origin) == (
        curve.kind,
        curve.p1,
        curve.p2,
        curve.origin,
    )
    np.testing.assert_array_equal(loaded["Abar"], curve["Abar"])
    np.testing.assert_array_equal(loaded["A1"], curve["A1"])


def test_bad_requests_fail_before_any_work():
    P = PRESET.params
    x = np.zeros(16)
    with pytest.raises(ValueError, match="kind must be one of LP, PD, BP, NS"):
        trace_curve(P, CurveSeed("XX", x, 0.0), box={"sigma": (-1, 1), "Abar": (1, 2)})
    with pytest.raises(ValueError, match="'omega' is not a field of Params"):
        curve_problem(P, "LP", "sigma", "omega")
    with pytest.raises(ValueError, match="the two parameters must differ"):
        curve_problem(P, "LP", "sigma", "sigma")
    with pytest.raises(ValueError, match="'n' is an integer"):
        trace_curve(P, CurveSeed("LP", x, 0.0), box={"sigma": (-1, 1), "n": (1, 60)})
    with pytest.raises(ValueError, match="start branch's parameter must be one of"):
        trace_curve(P, CurveSeed("LP", x, 0.0, branch_param="pbar"), box={"sigma": (-1, 1), "Abar": (1, 4)})
    with pytest.raises(ValueError, match="empty box"):
        trace_curve(P, CurveSeed("LP", x, 0.0), box={"sigma": (1, -1), "Abar": (1, 2)})
    with pytest.raises(ValueError, match="outside the box"):
        trace_curve(P, CurveSeed("LP", x, 5.0), box={"sigma": (-1, 1), "Abar": (1, 4)})


def test_a_start_that_is_not_a_special_point_of_the_kind_is_refused(flip_curve):
    P, curve = flip_curve
    x, sigma = curve.branch.x[5, :-1], curve["sigma"][5]
    at = P.replace(Abar=float(curve["Abar"][5]))
    with pytest.raises(ValueError, match="the start is not a LP point"):
        trace_curve(at, CurveSeed("LP", x, sigma), box={"sigma": (-2.9, -2.2), "Abar": (2.7, 3.3)})


def test_renewed_borders_keep_their_orientation():
    # A border renewed as -v/|v| instead of v/|v| flips the sign of the fold's quadratic
    # coefficient w^T F_xx[v, v], and the cusp test then changes sign at every flip.
    from slosh_bif.orbits.codim2.minaug import orthonormal

    rng = np.random.default_rng(7)
    for a in (np.array([[3.0], [4.0]]), np.array([[-3.0], [4.0]]), rng.normal(size=(9, 1))):
        np.testing.assert_allclose(orthonormal(a), a / np.linalg.norm(a), atol=1e-15)
    A = rng.normal(size=(9, 2)) + 1j * rng.normal(size=(9, 2))
    Q = orthonormal(A)
    np.testing.assert_allclose(Q.conj().T @ Q, np.eye(2), atol=1e-14)
    assert np.real(np.vdot(Q[:, 0], A[:, 0])) > 0


# A fold of the Fig. 13 set's asymmetric orbits (four arcs' start states, then Abar) at
# sigma = 0.238629, just past a fold-flip point, on the chart's fold curve from the asymmetric
# branch's fold at sigma = -0.395572, Abar = 1.
ASYMMETRIC_FOLD = (
    0.2386292151495742,
    [
        -0.7148530978941231,
        1.5185409394108365,
        0.09556320805221538,
        0.6849721281700706,
        1.507156846438365,
        0.6925015690759277,
        0.9656768661778115,
        -0.16523146758683027,
        0.6744090981333701,
        -1.5049301688991485,
        -1.0668776001923508,
        1.0449367740631663,
        -1.5147752552889249,
        -0.709203058911448,
        0.46435318899334305,
        -1.3351344263412561,
        0.6452025739910295,
    ],
)


def test_a_fold_curve_passes_a_nearly_singular_stretch_with_exact_second_derivatives(scipy_multipliers):
    # Past the cusp at sigma = 0.2401 the curve runs by a nearly singular stretch (the augmented
    # Jacobian's least singular value 6e-7 near sigma = 0.2394). With g's derivatives by central
    # differences of arcs integrated to rtol 1e-10 the steps crept to nothing there and the
    # direction had to be resumed with arcs at 1e-12; by the second-order variational equations
    # it passes at the arcs' own tolerance, through a second fold-flip point to the box's edge.
    p, u = ASYMMETRIC_FOLD
    P = get_preset("fig13").params.replace(Abar=u[-1])
    options = dataclasses.replace(CURVE_OPTIONS, direction="forward", max_steps=200, tol=1e-10)
    curve = trace_curve(
        P, CurveSeed("LP", u[:-1], p), box={"sigma": (-0.25, 1.0), "Abar": (0.3, 1.0)}, options=options
    )
    branch = curve.branch
    assert branch.status == "ok" and "resumed" not in branch.message, branch.message
    assert set(branch.diagnostics["rtol"]) == {1e-10}
    assert branch.p[-1] == -0.25  # ended on the box, not at the stall
    (cusp,) = branch.special_of("CP")
    assert cusp.p == pytest.approx(0.2401, abs=2e-4)
    flips = [s for s in branch.special_of("LPPD") if s.p < 0]
    assert len(flips) == 1
    mu = scipy_multipliers(P.replace(sigma=float(flips[0].p), Abar=float(flips[0].x[-1])), flips[0].x[:4])
    assert np.min(np.abs(mu - 1)) < 1e-6 and np.min(np.abs(mu + 1)) < 1e-6
    for i in np.linspace(0, len(branch) - 1, 5).astype(
        int
    ):  # fold points by scipy on both sides of the stall
        mu = scipy_multipliers(
            P.replace(sigma=float(branch.p[i]), Abar=float(branch.x[i, -1])), branch.x[i, :4]
        )
        assert np.min(np.abs(mu - 1)) < 1e-6


def test_a_fold_curve_of_doubled_orbits_ends_where_the_orbit_becomes_its_parents():
    # At a degenerate period doubling of the parent the fold curve of the doubled orbits meets
    # the parent's flip curve; the doubled orbit repeats after half its period there and the
    # fold system is singular (the Fig. 10 chart's period-2 fold curve crept to a stop within
    # 3e-5 of it). The problem's domain ends 1e-3 short, its edge named.
    from slosh_bif.orbits.codim2 import MEETS_PARENT

    P = PRESET.params
    problem = FoldCurveProblem(P, segments=8, period_multiple=2)
    parent = np.array([0.3, -0.1, 0.9, 0.2, -0.2, 0.4, -0.7, 0.1, 0.25, 0.3, -0.4, -0.6, -0.3, 0.1, 0.2, 0.5])
    doubled = np.append(np.tile(parent, 2), P.Abar)
    assert not problem.in_domain(doubled, P.sigma)
    assert problem.edge_name_at(doubled, P.sigma) == MEETS_PARENT
    apart = np.concatenate([parent, parent + 0.05])
    assert problem.in_domain(np.append(apart, P.Abar), P.sigma)
    assert FoldCurveProblem(P, segments=4).in_domain(
        np.append(np.tile(parent[:8], 2), P.Abar), P.sigma
    )  # period 1: no parent
