"""Curves of bifurcations of the vibro-impact model (8) in (sigma, Abar), checked against
one-parameter branches of (8) (a different problem class and test function) and the multipliers
of the map at the points found."""

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.continuation import ContinuationOptions, continuation
from slosh_bif.orbits.impact.curves import ImpactCurveSeed, trace_impact_curve
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem

P = get_preset("fig13").params
SECTION = 1.522176547202477  # the symmetric branch's section tau = phase (one impact per half period)
# Orbits of (8) on the symmetric branch in sigma at Abar = 1 (``shoot --model impact``): its
# symmetry-breaking pitchfork and its torus point.
PITCHFORK = (0.43717150731520593, [0.22306208, 0.72903253, 0.04415473, -0.42826024])
TORUS = (3.511038050198928, [0.05099662, 0.08101857, 0.19784039, -0.61937469])


@pytest.fixture(scope="module")
def curves():
    out = {}
    for kind, (p, x), box in (
        ("BP", PITCHFORK, {"sigma": (-1.0, 2.0), "Abar": (0.6, 1.6)}),
        ("NS", TORUS, {"sigma": (2.5, 4.5), "Abar": (0.6, 1.6)}),
    ):
        out[kind] = trace_impact_curve(
            P, ImpactCurveSeed(kind, np.array(x), p, symmetric=True, phase=SECTION, impacts=1), box=box
        )
    return out


def _one_parameter_special(kind, x, sigma, abar):
    """The special point of ``kind`` that the one-parameter branch of (8) in sigma at Abar locates
    near sigma (started 0.02 below it)."""
    problem = ImpactOrbitProblem(
        P.replace(sigma=sigma - 0.02, Abar=abar), "sigma", symmetric=True, phase=SECTION
    )
    options = ContinuationOptions(step=0.01, step_max=0.02, tol=1e-10, p_min=sigma - 0.05, p_max=sigma + 0.05)
    branch = continuation(problem, x, sigma - 0.02, param="sigma", options=options)
    (found,) = [s.p for s in branch.special if s.kind == kind]
    return found


@pytest.mark.parametrize("kind", ["BP", "NS"])
def test_impact_curve_points_are_special_points_of_one_parameter_branches(curves, kind):
    curve = curves[kind]
    assert curve.status == "ok" and len(curve) > 10, curve.branch.message
    for i in (len(curve) // 3, (2 * len(curve)) // 3):
        sigma, abar = float(curve["sigma"][i]), float(curve["Abar"][i])
        assert _one_parameter_special(kind, curve.branch.x[i, :4], sigma, abar) == pytest.approx(
            sigma, abs=1e-8
        )


def test_impact_curve_multipliers_by_the_map(curves):
    # The pitchfork: the half-period map G = -phi_pi has the multiplier -1; the torus: a pair on
    # the unit circle at cos(theta) = kappa. At the pitchfork curve's BPLP point G has +1 as well.
    bp, ns = curves["BP"], curves["NS"]
    for curve, check in ((bp, "BP"), (ns, "NS")):
        for i in np.linspace(0, len(curve) - 1, 4).astype(int):
            u, sigma = curve.branch.x[i], float(curve.branch.p[i])
            mu = ImpactOrbitProblem(
                P.replace(sigma=sigma, Abar=float(curve["Abar"][i])), "sigma", symmetric=True, phase=SECTION
            ).map_multipliers(u[:4], sigma)
            if check == "BP":
                assert np.min(np.abs(mu + 1)) < 1e-8
            else:  # NS on the whole-period map: G's squares
                pair = (mu * mu)[np.argmin(np.abs(np.abs(mu * mu) - 1) + (np.abs(mu.imag) < 1e-9))]
                assert abs(abs(pair) - 1) < 1e-8 and pair.real == pytest.approx(u[-1], abs=1e-8)
    (bplp,) = bp.branch.special_of("BPLP")
    mu = ImpactOrbitProblem(
        P.replace(sigma=bplp.p, Abar=float(bplp.x[-1])), "sigma", symmetric=True, phase=SECTION
    ).map_multipliers(bplp.x[:4], bplp.p)
    assert np.min(np.abs(mu + 1)) < 1e-8 and np.min(np.abs(mu - 1)) < 1e-6


def test_bad_impact_seeds_are_refused_before_any_work():
    p, x = PITCHFORK
    with pytest.raises(ValueError, match="a BP curve starts from a branch of symmetric orbits"):
        trace_impact_curve(
            P,
            ImpactCurveSeed("BP", np.array(x), p, phase=SECTION),
            box={"sigma": (-1, 2), "Abar": (0.6, 1.6)},
        )
    with pytest.raises(ValueError, match="the orbit's state on the section, 4 finite numbers"):
        trace_impact_curve(
            P, ImpactCurveSeed("LP", np.zeros(8), p), box={"sigma": (-1, 2), "Abar": (0.6, 1.6)}
        )
    with pytest.raises(ValueError, match="the start is not a PD point"):
        trace_impact_curve(
            P,
            ImpactCurveSeed("PD", np.array(x), p, symmetric=True, phase=SECTION),
            box={"sigma": (-1, 2), "Abar": (0.6, 1.6)},
        )


def test_a_pitchfork_curve_of_the_corrected_impact_model_meets_its_one_parameter_branches():
    """The corrected impact model ((9)'s flights, the wall's measured law at its clearance D(v)):
    its symmetric branch on the Fig. 13 set from sigma = 0.5 down locates its pitchfork; the BP curve
    from there, at two interior points, is where one-parameter branches of that model in sigma at
    the point's Abar locate their own pitchfork."""
    from slosh_bif.orbits.impact.branches import settled_orbit, trace_impact_orbits

    at = P.replace(sigma=0.5)
    x0 = settled_orbit(at, get_preset("fig13").state0, periods=300, variant="corrected")
    branch = trace_impact_orbits(at, x0, p_min=0.2, p_max=0.8, symmetric=True, variant="corrected")
    piece, sp = next((pc, s) for pc in branch.pieces for s in pc.branch.special if s.kind == "BP")
    assert sp.p == pytest.approx(0.372879, abs=1e-5)
    seed = ImpactCurveSeed(
        "BP", sp.x, sp.p, symmetric=True, phase=piece.phase, impacts=piece.impacts, variant="corrected"
    )
    curve = trace_impact_curve(P, seed, box={"sigma": (0.0, 1.0), "Abar": (0.85, 1.2)})
    assert curve.status == "ok" and len(curve) > 5, curve.branch.message
    for i in (len(curve) // 3, (2 * len(curve)) // 3):
        sigma, abar = float(curve["sigma"][i]), float(curve["Abar"][i])
        problem = ImpactOrbitProblem(
            P.replace(sigma=sigma - 0.02, Abar=abar),
            "sigma",
            symmetric=True,
            phase=piece.phase,
            variant="corrected",
        )
        options = ContinuationOptions(
            step=0.01, step_max=0.02, tol=1e-10, p_min=sigma - 0.05, p_max=sigma + 0.05
        )
        one = continuation(problem, curve.branch.x[i, :4], sigma - 0.02, param="sigma", options=options)
        (found,) = [s.p for s in one.special if s.kind == "BP"]
        assert found == pytest.approx(sigma, abs=1e-8)


def test_a_period_doubling_curve_of_period_4_orbits_meets_its_one_parameter_branches():
    """The Fig. 10 set from sigma = 3: the asymmetric orbit's period doubling gives period-2 orbits,
    theirs period-4 ones, whose own period doubling (the onset of period 8) is traced as a curve in
    (sigma, Abar); at an interior point a one-parameter branch of period-4 orbits in sigma at that
    Abar locates its period doubling at the curve's sigma."""
    from slosh_bif import simulate_impact
    from slosh_bif.orbits.impact.branches import trace_impact_orbits
    from slosh_bif.orbits.impact.switching import doubled_branches

    pre = get_preset("fig10")
    at = pre.params.replace(sigma=3.0)
    x0 = simulate_impact(at, pre.state0, (0.0, 300 * np.pi)).y[:, -1]
    branch = trace_impact_orbits(at, x0, p_min=2.3, p_max=3.2)
    for _ in range(2):  # period 2, then period 4
        (_, branch), *_ = doubled_branches(at, branch, p_min=2.3, p_max=3.2, max_branches=1)
    piece, sp = next((pc, s) for pc in branch.pieces for s in pc.branch.special if s.kind == "PD")
    assert piece.period_multiple == 4
    seed = ImpactCurveSeed("PD", sp.x, sp.p, phase=piece.phase, impacts=piece.impacts, period_multiple=4)
    curve = trace_impact_curve(at, seed, box={"sigma": (2.0, 3.5), "Abar": (2.5, 3.5)})
    assert curve.status == "ok" and len(curve) > 10, curve.branch.message
    i = int(np.argmin(np.abs(curve["Abar"] - 2.75)))
    sigma, abar = float(curve["sigma"][i]), float(curve["Abar"][i])
    problem = ImpactOrbitProblem(
        at.replace(sigma=sigma - 0.005, Abar=abar), "sigma", period_multiple=4, phase=piece.phase
    )
    options = ContinuationOptions(
        step=0.002, step_max=0.004, tol=1e-10, p_min=sigma - 0.01, p_max=sigma + 0.01
    )
    one = continuation(problem, curve.branch.x[i, :4], sigma - 0.005, param="sigma", options=options)
    found = [s.p for s in one.special if s.kind == "PD"]
    assert found and min(abs(q - sigma) for q in found) < 1e-8


def test_a_fold_curve_goes_on_across_an_impact_on_its_section():
    """A fold of symmetric orbits of (8) at eps 0.099, beta 0.58, gamma 0.09, lam 0.39, chi 0.81,
    n 10, pbar 2, located on a branch in Abar at sigma = -0.5049, started on a section just after
    an impact: as sigma moves the impact reaches the section, where the curve ended (the chart of
    this set read Abar_c off a pitchfork curve at 0.319 where stable orbits exist down to 0.216,
    its fold curve cut so). It goes on on a moved section: its points there are where
    one-parameter branches in sigma on that section locate their own fold."""
    from slosh_bif.model.params import Params
    from slosh_bif.orbits.impact.branches import settled_orbit, trace_impact_orbits

    params = Params(
        eps=0.09876011384422585,
        beta=0.5823508928063189,
        gamma=0.09009404281499403,
        sigma=-0.5049,
        Abar=0.309,
        lam=0.3927080668452921,
        chi=0.8080862068317072,
        n=10,
        pbar=2,
    )
    x0 = settled_orbit(params, [0.72259, 1.02594, -0.11101, -0.57222], periods=100)
    branch = trace_impact_orbits(params, x0, param="Abar", p_min=0.15, p_max=0.35, symmetric=True)
    piece, sp = next((pc, s) for pc in branch.pieces for s in pc.branch.special if s.kind == "LP")
    assert sp.p == pytest.approx(0.21583, abs=1e-5)
    # the orbit's state on a section 0.02 after its first impact: the impact moves across it as
    # sigma falls
    at = params.replace(Abar=sp.p)
    problem = ImpactOrbitProblem(at, "Abar", symmetric=True, phase=piece.phase)
    first = problem.orbit(sp.x, sp.p)[2][0, 0]
    phase = first + 0.02
    state = problem.flow_at(sp.p).run(sp.x, piece.phase, phase, stick_speed=1e-9, max_impacts=100)[1][:, -1]
    seed = ImpactCurveSeed("LP", state, sp.p, "Abar", symmetric=True, phase=phase, impacts=piece.impacts)
    curve = trace_impact_curve(params, seed, box={"sigma": (-4.0, -0.3), "Abar": (0.1, 0.6)})
    moved = np.flatnonzero(curve["phase"] != phase)
    assert curve.status == "ok" and len(moved) >= 4, curve.branch.message
    # one curve in curve order: its two ends only, at its first and last points
    assert [sp.index for sp in curve.branch.special if sp.kind == "END"] == [0, len(curve) - 1]
    assert np.all(np.diff(curve.branch.arclength) >= 0)
    for i in moved[[1, -2]]:
        sigma, abar = float(curve["sigma"][i]), float(curve["Abar"][i])
        problem = ImpactOrbitProblem(
            params.replace(sigma=sigma - 0.02, Abar=abar), "sigma", phase=float(curve["phase"][i])
        )
        options = ContinuationOptions(
            step=0.01, step_max=0.02, tol=1e-10, p_min=sigma - 0.05, p_max=sigma + 0.05
        )
        one = continuation(problem, curve.branch.x[i, :4], sigma - 0.02, param="sigma", options=options)
        (found,) = [s.p for s in one.special if s.kind == "LP"]
        assert found == pytest.approx(sigma, abs=1e-8)


# A random admissible set (seed 310 of the corrected impact model's campaign) whose period-4 branch
# runs on past the law's corner: there the slowest of its 13 impacts a period is 0.0126, below the
# measured law's least speed 0.05, where the law is held constant. Its fold on that stretch
# (``shoot --model impact-corrected``, the period-4 branch's fourth piece).
BEYOND = get_preset("fig10").params.replace(
    eps=0.0961, beta=0.336, gamma=0.358, sigma=-0.969, Abar=1.211, lam=0.292, chi=1.401, n=3, pbar=3
)
BEYOND_FOLD = (
    -0.525917302040727,
    [0.16217461794022467, -2.218596826157004, -0.0273775439151007, 0.4922723668420632],
)
BEYOND_PHASE = 2.7982718627177743


@pytest.mark.slow  # 7 s; the grazing curve past the corner (test_impact_grazing.py) is the fast check
def test_a_fold_curve_beyond_the_measured_laws_corner_meets_its_one_parameter_branches():
    """The curves hold each impact's side of the law's corner (not only impacts faster than it):
    the fold curve from a fold whose orbit has an impact below 0.05 is traced, its orbits keep
    that slow impact, and at two interior points one-parameter branches in sigma at the point's
    Abar locate their own fold there."""
    p, x = BEYOND_FOLD
    seed = ImpactCurveSeed(
        "LP", np.array(x), p, phase=BEYOND_PHASE, impacts=13, period_multiple=4, variant="corrected"
    )
    curve = trace_impact_curve(
        BEYOND.replace(sigma=p), seed, box={"sigma": (-0.56, -0.50), "Abar": (1.17, 1.25)}
    )
    assert curve.status == "ok" and len(curve) > 10, curve.branch.message
    for i in (len(curve) // 3, (2 * len(curve)) // 3):
        sigma, abar = float(curve["sigma"][i]), float(curve["Abar"][i])
        at = BEYOND.replace(sigma=sigma, Abar=abar)
        problem = ImpactOrbitProblem(at, "sigma", period_multiple=4, phase=BEYOND_PHASE, variant="corrected")
        speeds = np.abs(problem.evaluate(curve.branch.x[i, :4], sigma).impacts[:, 2])
        assert len(speeds) == 13 and 0.01 < speeds.min() < 0.05
        options = ContinuationOptions(
            step=1e-4, step_max=5e-4, tol=1e-10, p_min=sigma - 2e-3, p_max=sigma + 2e-3, direction="forward"
        )
        branch = continuation(problem, curve.branch.x[i, :4], sigma, param="sigma", options=options)
        found = [s.p for s in branch.special if s.kind == "LP"]
        assert found and min(abs(q - sigma) for q in found) < 1e-7, (found, sigma)
