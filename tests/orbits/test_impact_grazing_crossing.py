"""Crossing a grazing point of (8): the orbits beyond it against independent evaluations and the
local theory of grazing (Nordmark's discontinuity map).

Near a grazing point p_g, the family with the new impact of speed v has (i) p - p_g linear in v,
(ii) a multiplier of the map growing as 1/v (the saltation of a slow impact), so it is unstable
right beyond the grazing, and (iii) each of its orbits returns to itself under scipy's event loop
(the reference flow, expm between impacts) with an impact of speed v. The Fig. 10 set's symmetric
branch of (8), continued through its four grazings, covers sigma in [-6, 8] as (9)'s does."""

import numpy as np
import pytest

from slosh_bif import get_preset, simulate_impact
from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.flows.smooth.integrator import HAVE_NUMBA
from slosh_bif.orbits.impact.branches import settled_orbit, trace_impact_orbits
from slosh_bif.orbits.impact.grazing_crossing import Contact, contact_at, on_section, unfold
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled flow needs numba")


@pytest.fixture(scope="module")
def symmetric_branch():
    """The Fig. 10 set's symmetric orbit of (8) at sigma = 5, continued over [-6, 8]."""
    p = get_preset("fig10")
    params = p.params.replace(sigma=5.0)
    x0 = settled_orbit(params, p.state0, periods=300)
    return params, trace_impact_orbits(params, x0, p_min=-6.0, p_max=8.0, symmetric=True)


def test_beyond_the_grazing_the_new_impacts_speed_is_linear_in_p_and_its_orbit_unstable(symmetric_branch):
    params, branch = symmetric_branch
    p_g, x_g, phase = branch.grazing[0]
    assert p_g == pytest.approx(0.51416123, abs=1e-7)
    problem = ImpactOrbitProblem(params, symmetric=True, phase=phase, impacts=1)
    contact = contact_at(problem, x_g, p_g)
    assert contact.kind == "flight"
    probe = problem.replace(impacts=None)
    offsets, largest = [], []
    for v in (1e-3, 2e-3):
        u, equations = unfold(problem, contact, p_g, "impact", v)
        q = float(u[3])
        run = newton_solve(probe, on_section(problem, equations, u), q, tol=1e-12)
        assert run.converged and len(probe.evaluate(run.x, q).impacts) == 2
        offsets.append(q - p_g)
        largest.append(np.abs(probe.map_multipliers(run.x, q)).max())
        # an orbit of (8) under the reference flow, with an impact of speed v
        ref = simulate_impact(params.replace(sigma=q), run.x, (phase, phase + 2 * np.pi), backend="scipy")
        assert np.abs(ref.y[:, -1] - run.x).max() < 1e-7
        assert np.abs(np.abs(ref.impact_v_minus).min() - v) < 1e-6
    assert offsets[1] / offsets[0] == pytest.approx(2.0, rel=1e-2)  # p - p_g linear in v
    assert largest[0] / largest[1] == pytest.approx(2.0, rel=1e-2)  # a multiplier ~ 1/v
    assert largest[1] > 1e3


def test_the_symmetric_branch_is_continued_through_its_grazings_over_the_whole_range(symmetric_branch):
    params, branch = symmetric_branch
    assert branch.complete and [e.reason for e in branch.ends] == ["parameter bound"] * 2
    assert len(branch.grazing) == 4
    assert {pc.impacts for pc in branch.pieces} == {1, 2, 3}  # per half period
    lo = min(pc.branch.p.min() for pc in branch.pieces)
    hi = max(pc.branch.p.max() for pc in branch.pieces)
    assert lo == -6.0 and hi == 8.0
    # each grazing joins two pieces whose impact counts differ by one, both ending within 1e-3 of it
    for p_g, _, _ in branch.grazing:
        near = [pc for pc in branch.pieces if np.min(np.abs(pc.branch.p[[0, -1]] - p_g)) < 1e-3]
        assert len({pc.impacts for pc in near}) == 2
    # the branch has (9)'s sequence of special points (docs/findings/impact.md): 4 folds, 6 pitchforks
    assert len(branch.special("LP")) == 4 and len(branch.special("BP")) == 6


def _slow_impacts(params, piece, p_g):
    """(v, p): the slowest impact's speed v of the piece's orbits within 0.05 of p_g, with v spread
    by at least a factor 1.5 from one to the next."""
    problem = ImpactOrbitProblem(params, symmetric=True, phase=piece.phase)
    rows = []
    for x, p in zip(piece.branch.x, piece.branch.p):
        impacts = problem.evaluate(x, p).impacts
        if abs(p - p_g) < 0.05 and len(impacts):
            rows.append((np.abs(impacts[:, 2]).min(), p))
    spread = []
    for v, p in sorted(rows):
        if 1e-6 < v < 3e-2 and (not spread or v > 1.5 * spread[-1][0]):
            spread.append((v, p))
    return np.array(spread)


def test_each_grazing_is_where_the_orbits_slow_impact_extrapolates_to_zero_speed(symmetric_branch):
    """The GR points reached from the impacting side (where Newton on the section stalls: the
    map's Jacobian grows as 1/v) are located to 1e-9 in sigma: the piece's own orbits with a slow
    impact, their p against its speed v fitted by a polynomial, reach v = 0 there."""
    params, branch = symmetric_branch
    checked = 0
    for p_g, _, _ in branch.grazing:
        fits = []
        for piece in branch.pieces:
            rows = _slow_impacts(params, piece, p_g)
            if len(rows) >= 3:  # a cubic through four where there are: where the slowest impact
                # is at v ~ 1e-3 a quadratic's truncation alone is ~1e-9
                slowest = rows[:4]
                fits.append(np.polyfit(slowest[:, 0], slowest[:, 1], len(slowest) - 1)[-1])
        if fits:
            checked += 1
            assert min(abs(f - p_g) for f in fits) < 1e-9
    assert checked >= 3


def test_a_slow_impact_where_21_has_no_real_kappa_gives_no_orbit_and_no_warning():
    """pbar = -2: (21) loses without bound at slow impacts (kappa^2 = 1 - c v^-2 < 0 below
    v = sqrt(c)), so the orbits just beyond a grazing do not exist: unfolding says so (None),
    without a warning on the user's terminal."""
    import warnings

    params = get_preset("fig10").params.replace(lam=0.1, chi=0.4, n=4, pbar=-2, sigma=1.0)
    problem = ImpactOrbitProblem(params, symmetric=True, phase=0.0, impacts=1)
    contact = Contact(t=1.0, side=1.0, X=0.1, Xd=0.0, kind="flight")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert unfold(problem, contact, 1.0, "impact", 1e-3) is None
