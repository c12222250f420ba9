"""Grazing curves of (8) in two parameters against independent evaluations: each point's orbit
returns to itself and touches the wall with zero speed under scipy (DOP853 with event location
of the turning point, the expm event loop between), and the one-parameter grazing locator
(Newton on the map at a section and the turning-point gap, a formulation of its own) puts the
grazing at the curve's sigma for the curve's Abar."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from slosh_bif import ImpactModel, get_preset, simulate_impact
from slosh_bif.flows.smooth.integrator import HAVE_NUMBA
from slosh_bif.orbits.impact.branches import trace_impact_orbits
from slosh_bif.orbits.impact.curves import ImpactCurveSeed, trace_grazing_curve
from slosh_bif.orbits.impact.grazing import FREE, GrazingCurveProblem
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled flow needs numba")


@pytest.fixture(scope="module")
def curve():
    """The grazing curve through the GR point of the Fig. 10 set's asymmetric branch (sigma =
    2.16104 at Abar = 3), in (sigma, Abar)."""
    p = get_preset("fig10")
    params = p.params.replace(sigma=3.0)
    run = simulate_impact(params, p.state0, (0.0, 300 * np.pi))
    branch = trace_impact_orbits(params, run.y[:, -1], p_min=1.0, p_max=3.2)
    p_gr, x_gr, phase = branch.grazing[0]
    seed = ImpactCurveSeed("GR", x_gr, p_gr, "sigma", phase=phase, origin="test")
    box = {"sigma": (0.5, 4.0), "Abar": (2.2, 3.8)}
    return params, trace_grazing_curve(params, seed, box=box)


def test_the_curve_passes_through_its_seed_and_spans_the_box(curve):
    params, c = curve
    assert c.kind == "GR" and c.status == "ok" and len(c) > 5
    assert np.interp(params.Abar, *_sorted(c["Abar"], c["sigma"])) == pytest.approx(2.16104015, abs=1e-6)
    assert c["Abar"].min() < 2.3 and c["Abar"].max() > 3.7  # across Abar's range
    assert np.all(c["max_abs_w"] == 1.0)


def _sorted(a, b):
    order = np.argsort(a)
    return a[order], b[order]


def _reference_check(params, problem, u, p):
    """(return error, 1 - |w| at the turning point) of the grazing orbit u at p, by scipy."""
    at = problem.params_at(u, p)
    t_g, side = float(u[2]), problem.side
    y_g = np.array([u[0], u[1], side, 0.0])
    start = problem.leaving(u, p)  # expm of (8)'s linear part over FREE: no wall in reach
    period = problem.period
    run = simulate_impact(at, start, (t_g + FREE, t_g + period - 0.3), backend="scipy")
    model = ImpactModel(at)

    def turn(t, y):
        return y[3]

    # on past the return (the turning point is there): the flight without walls
    sol = solve_ivp(
        model.rhs,
        (run.t[-1], t_g + period + 0.3),
        run.y[:, -1],
        method="DOP853",
        rtol=1e-13,
        atol=1e-14,
        events=turn,
        t_eval=[t_g + period],
    )
    gap = 1.0 - np.abs(sol.y_events[0][:, 2]).max()
    return np.abs(sol.y[:, 0] - y_g).max(), gap


def test_each_point_is_a_periodic_orbit_touching_the_wall_under_scipy(curve):
    params, c = curve
    problem = GrazingCurveProblem(params, "sigma", "Abar", side=_side(c))
    for i in np.linspace(0, len(c) - 1, 4).astype(int):
        error, gap = _reference_check(params, problem, c.branch.x[i], c.branch.p[i])
        assert error < 1e-8 and abs(gap) < 1e-8, (i, error, gap)


def _side(c):
    """The wall touched: the sign of w at the grazing point, from the curve's first orbit."""
    u = c.branch.x[0]
    for side in (1.0, -1.0):
        problem = GrazingCurveProblem(get_preset("fig10").params, "sigma", "Abar", side=side)
        if np.abs(problem.residual(u, c.branch.p[0])).max() < 1e-8:
            return side
    raise AssertionError("the curve's first point is on neither wall")


def test_the_one_parameter_locator_finds_the_grazing_at_the_curves_sigma(curve):
    """At the Abar of a point of the curve far from the seed, the grazing located on the map at the
    section tau = 0 with the turning-point gap (ImpactOrbitProblem.edge_point), from the same orbit
    nudged off it, lands on the curve's sigma."""
    params, c = curve
    i = int(np.argmax(np.abs(c["Abar"] - params.Abar)))
    u, p = c.branch.x[i], c.branch.p[i]
    problem = GrazingCurveProblem(params, "sigma", "Abar", side=_side(c))
    at = problem.params_at(u, p)
    t0 = float(u[2]) + FREE
    # the orbit's state at the next tau = 0 (mod 2pi), by the compiled flow from the free stretch's end
    end = 2 * np.pi * np.ceil(t0 / (2 * np.pi))
    orbits = ImpactOrbitProblem(at, "sigma")
    x0 = orbits.flow_at(p).run(problem.leaving(u, p), t0, end, stick_speed=1e-9, max_impacts=100)[1][:, -1]
    # the other formulation holds at the curve's point: a fixed point of the map, gap zero; at an
    # orbit grazing exactly, a rounding-sized penetration delta (or none) registers as an impact of
    # speed sqrt(2 a delta) ~ 1e-7, which moves the map's image by as much
    assert np.abs(orbits.residual(x0, p)).max() < 1e-6 and orbits.grazing(x0, p).gap < 1e-10
    located = orbits.edge_point(x0 + 1e-7, p + 1e-6)  # Newton from beside it
    assert located is not None
    assert located[1] == pytest.approx(p, abs=1e-8)


def test_bad_input_is_named():
    params = get_preset("fig10").params
    with pytest.raises(ValueError, match="side must be"):
        GrazingCurveProblem(params, "sigma", "Abar", side=0.5)
    with pytest.raises(ValueError, match="'n' is an integer"):
        GrazingCurveProblem(params, "sigma", "n", side=1.0)
    with pytest.raises(ValueError, match="GR point"):
        trace_grazing_curve(
            params, ImpactCurveSeed("LP", np.zeros(4), 3.0), box={"sigma": (1, 4), "Abar": (1, 2)}
        )


def test_a_grazing_curve_whose_other_impacts_lie_below_the_laws_corner():
    """A random set (seed 310 of the corrected impact model's campaign): its period-4 branch grazes
    at sigma = -0.52782 where another of its 12 impacts a period is at 0.023, below the measured
    law's least speed 0.05. The grazing curve from there holds that impact's side of the corner,
    and at a point of it far from the seed the orbit, written at the section tau = 0 by the
    compiled flow, is a fixed point of the period-4 map of ImpactOrbitProblem with a zero gap."""
    params = get_preset("fig10").params.replace(
        eps=0.0961, beta=0.336, gamma=0.358, sigma=-0.969, Abar=1.211, lam=0.292, chi=1.401, n=3, pbar=3
    )
    x = [0.15387670542881526, -2.2145556176818846, -0.029590711939581398, 0.48159985246804493]
    p_gr, phase = -0.5278206935639772, 2.7982718627177743
    seed = ImpactCurveSeed("GR", np.array(x), p_gr, phase=phase, period_multiple=4, variant="corrected")
    c = trace_grazing_curve(params, seed, box={"sigma": (-0.56, -0.50), "Abar": (1.17, 1.25)})
    assert c.status == "ok" and len(c) > 5, c.branch.message
    i = int(np.argmax(np.abs(c["Abar"] - params.Abar)))
    u, p = c.branch.x[i], c.branch.p[i]
    assert abs(c["Abar"][i] - params.Abar) > 0.01
    (problem,) = [
        q
        for q in (
            GrazingCurveProblem(params, "sigma", "Abar", side=s, period_multiple=4, variant="corrected")
            for s in (1.0, -1.0)
        )
        if np.abs(q.residual(u, p)).max() < 1e-8
    ]
    at = problem.params_at(u, p)
    t0 = float(u[2]) + FREE
    end = 2 * np.pi * np.ceil(t0 / (2 * np.pi))
    orbits = ImpactOrbitProblem(at, "sigma", period_multiple=4, variant="corrected")
    x0 = orbits.flow_at(p).run(problem.leaving(u, p), t0, end, stick_speed=1e-9, max_impacts=100)[1][:, -1]
    assert np.abs(orbits.residual(x0, p)).max() < 1e-6 and orbits.grazing(x0, p).gap < 1e-8
    speeds = np.abs(orbits.evaluate(x0, p).impacts[:, 2])
    assert 1e-2 < speeds[speeds > 1e-6].min() < 0.05  # an impact (not the grazing contact) below the corner


def test_a_grazing_curve_starts_beside_a_second_contact_near_grazing():
    """A random set (seed 305 of the robustness draws) whose primary branch of (8) crosses a
    grazing where a second contact is near grazing too, and grazes again at sigma = -0.678047: the
    start's full Newton step flips the other contact and leaves the problem's domain, a halved one
    reaches the grazing orbit. Its points are periodic orbits touching the wall under scipy (to 1e-6:
    the reference's own slow impact at the other contact amplifies its error)."""
    params = get_preset("fig10").params.replace(
        eps=0.0723, beta=0.223, gamma=0.297, Abar=2.583, lam=0.563, chi=1.082, n=6, pbar=2
    )
    x = [2.3643046114611153, -1.3393470736498625, -0.8460495823721782, 0.836763856419806]
    seed = ImpactCurveSeed("GR", np.array(x), -0.6780467264913849, phase=1.2836254154747238, origin="test")
    box = {"sigma": (-4.389, -0.389), "Abar": (0.861, 3.875)}
    c = trace_grazing_curve(params.replace(sigma=seed.p), seed, box=box)
    assert c.status == "ok" and len(c) > 10
    for side in (1.0, -1.0):
        problem = GrazingCurveProblem(params, "sigma", "Abar", side=side)
        if np.abs(problem.residual(c.branch.x[0], c.branch.p[0])).max() < 1e-8:
            break
    for i in (len(c) // 4, len(c) // 2, 3 * len(c) // 4):  # the ends are where the other contact grazes
        error, gap = _reference_check(params, problem, c.branch.x[i], c.branch.p[i])
        assert error < 1e-6 and abs(gap) < 1e-6, (i, error, gap)
    # the end towards the box's sigma_max is that contact's grazing, just short of the box: an edge
    (last,) = [s for s in c.branch.special if s.kind == "END" and s.p == c.branch.p.max()]
    assert last.reason == "domain edge" and last.p < -0.389
