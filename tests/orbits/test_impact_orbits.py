"""Periodic orbits of (8) against independent evaluations: the saltation monodromy against finite
differences of the compiled map, the orbits and multipliers against a scipy Newton with a
finite-difference Jacobian on the expm event loop (the reference flow), grazing against scipy's
event location of the turning point, and the branch across sections and grazings."""

from types import SimpleNamespace

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import root

from slosh_bif import ImpactModel, get_preset, simulate_impact
from slosh_bif.continuation.corrector import newton
from slosh_bif.flows.impact.flow import ImpactFlow
from slosh_bif.flows.smooth.integrator import HAVE_NUMBA
from slosh_bif.model.params import Params
from slosh_bif.orbits.impact.branches import trace_impact_orbits
from slosh_bif.orbits.impact.law_corner import across_the_corner, corner_sides, slowest_impact
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the compiled flow needs numba")

SETS = {
    "fig10 sigma=3": ("fig10", {"sigma": 3.0}),
    "fig13 sigma=0.5": ("fig13", {"sigma": 0.5}),
    "pbar=2 wall": ("fig10", {"sigma": 3.0, "n": 20, "pbar": 2, "lam": 0.2}),
}


def _settled(name):
    preset, changes = SETS[name]
    p = get_preset(preset)
    params = p.params.replace(**changes)
    run = simulate_impact(params, p.state0, (0.0, 300 * np.pi))
    later = simulate_impact(params, run.y[:, -1], (0.0, 2 * np.pi))
    assert run.success and np.abs(later.y[:, -1] - run.y[:, -1]).max() < 1e-2  # settled near an orbit
    return params, run.y[:, -1]


def _reference_map(params, x):
    """The 2pi map by the expm event loop (backend 'scipy'), independent of the compiled flow."""
    return simulate_impact(params, x, (0.0, 2 * np.pi), backend="scipy").y[:, -1]


def _fd_jacobian(f, x, h=1e-6):
    return np.column_stack([(f(x + h * e) - f(x - h * e)) / (2 * h) for e in np.eye(len(x))])


@pytest.mark.parametrize("name", list(SETS))
def test_the_saltation_monodromy_and_parameter_derivative_match_finite_differences(name):
    params, x = _settled(name)
    for param in ("sigma", "Abar", "beta", "lam", "chi"):
        flow = ImpactFlow(params, param=param)
        _, phi, dp, impacts, code = flow.strobe(x, 0.0, 2 * np.pi)
        assert code == 0 and len(impacts) >= 1
        fd = _fd_jacobian(lambda z: flow.strobe(z, 0.0, 2 * np.pi)[0], x, h=1e-7)
        np.testing.assert_allclose(phi, fd, rtol=0, atol=1e-6 * max(1.0, np.abs(fd).max()))
        value, h = getattr(params, param), 1e-6

        def image(s):
            return ImpactFlow(params.replace(**{param: value + s * h})).strobe(x, 0.0, 2 * np.pi)[0]

        # central differences, or one-sided second-order ones at the end of beta's range (beta = 0)
        fd = (
            (image(1) - image(-1)) / (2 * h)
            if value - h >= 0
            else (-3 * image(0) + 4 * image(1) - image(2)) / (2 * h)
        )
        np.testing.assert_allclose(dp, fd, rtol=0, atol=1e-6 * max(1.0, np.abs(dp).max()))


@pytest.mark.parametrize("name", list(SETS))
def test_an_orbit_and_its_multipliers_match_an_independent_newton_on_the_reference_flow(name):
    params, x0 = _settled(name)
    problem = ImpactOrbitProblem(params)
    p = params.sigma
    x = newton(problem, x0, p, tol=1e-12)
    independent = root(lambda z: _reference_map(params, z) - z, x0, method="hybr", options={"xtol": 1e-13})
    assert independent.success
    np.testing.assert_allclose(x, independent.x, rtol=0, atol=1e-8)
    mu_fd = np.linalg.eigvals(_fd_jacobian(lambda z: _reference_map(params, z), independent.x))
    mu = problem.eigenvalues(x, p)
    np.testing.assert_allclose(np.sort_complex(mu), np.sort_complex(mu_fd), rtol=0, atol=1e-6)


def _turning_gap(params, phase, x, t_graze):
    """1 - |w| at the turning point nearest t_graze, by scipy's DOP853 with event location on the
    flight (no walls in the way), from the orbit's state at the section."""
    model = ImpactModel(params)
    run = simulate_impact(params, x, (phase, t_graze - 0.3), backend="scipy")
    t0, y0 = run.t[-1], run.y[:, -1]

    def turn(t, y):
        return y[3]

    sol = solve_ivp(model.rhs, (t0, t0 + 0.6), y0, method="DOP853", rtol=1e-13, atol=1e-14, events=turn)
    return 1.0 - np.abs(sol.y_events[0][:, 2]).max()


def test_a_branch_locates_its_period_doubling_and_crosses_its_grazing():
    """The Fig. 10 set from sigma = 3 down: the asymmetric pair's orbit, its period doubling, and
    its grazing near sigma = 2.16 (checked by scipy: the turning point touches the wall), beyond
    which the branch goes on with a third impact: its first orbit there returns to itself under
    scipy's event loop."""
    params, x0 = _settled("fig10 sigma=3")
    branch = trace_impact_orbits(params, x0, p_min=1.0, p_max=3.2)
    assert branch.grazing and branch.complete
    p_gr, x_gr, phase = branch.grazing[0]
    assert p_gr == pytest.approx(2.16104015, abs=1e-6)
    where = ImpactOrbitProblem(params, phase=phase).grazing(x_gr, p_gr)  # only where to look
    assert where.kind == "flight"
    assert _turning_gap(params.replace(sigma=p_gr), phase, x_gr, where.t) == pytest.approx(0.0, abs=1e-8)
    beyond = next(pc for pc in branch.pieces if pc.impacts == 3)
    x, q = beyond.branch.x[0], float(beyond.branch.p[0])
    assert abs(q - p_gr) < 1e-2
    ref = simulate_impact(
        params.replace(sigma=q), x, (beyond.phase, beyond.phase + 2 * np.pi), backend="scipy"
    )
    assert len(ref.impact_t) == 3 and np.abs(ref.y[:, -1] - x).max() < 1e-7
    pds = [(pc, s) for pc in branch.pieces for s in pc.branch.special if s.kind == "PD"]
    assert pds
    piece, point = pds[0]
    mu = ImpactOrbitProblem(params, phase=piece.phase).eigenvalues(point.x, point.p)
    assert np.min(np.abs(mu + 1)) < 1e-6


def test_a_period_doubling_of_8_gives_a_branch_of_twice_the_period():
    """Switching at the period doubling of the Fig. 10 set's asymmetric orbit (sigma ~ 2.9): the
    doubled branch passes through the doubling (its branch point there), and the middle orbit of
    each of its pieces returns after 4 pi but not after 2 pi under the reference flow (scipy's
    expm between impacts). Across its grazing near sigma = 2.34 (a second contact near grazing
    too) it goes on with five impacts down to the parent's own grazing (sigma = 2.16104), where
    its orbit is the parent's: a period-2 family born at the period-1 orbit's grazing, which ends
    the branch there."""
    from slosh_bif.orbits.impact.switching import doubled_branches

    params, x0 = _settled("fig10 sigma=3")
    parent = trace_impact_orbits(params, x0, p_min=1.0, p_max=3.2)
    pd = next(s.p for pc in parent.pieces for s in pc.branch.special if s.kind == "PD")
    (origin, doubled), *_ = doubled_branches(params, parent, p_min=1.0, p_max=3.2, max_branches=1)
    assert origin.startswith("PD at sigma") and all(pc.period_multiple == 2 for pc in doubled.pieces)
    assert any(abs(p - pd) < 1e-5 for p, _ in doubled.special("BP"))

    def returns(piece, i, periods):
        at, x = params.replace(sigma=float(piece.branch.p[i])), piece.branch.x[i]
        end = simulate_impact(at, x, (piece.phase, piece.phase + 2 * np.pi * periods), backend="scipy")
        return np.linalg.norm(end.y[:, -1] - x) / (1 + np.linalg.norm(x))

    for piece in doubled.pieces:
        middle = len(piece.branch) // 2
        assert returns(piece, middle, 2) < 1e-7 and returns(piece, middle, 1) > 1e-3
    p_gr = parent.grazing[0][0]
    last = min(doubled.pieces, key=lambda pc: pc.branch.p.min())
    i = int(np.argmin(last.branch.p))
    assert last.impacts == 5 and last.branch.p[i] == pytest.approx(p_gr, abs=1e-4)
    assert returns(last, i, 1) < 1e-3
    # which ends the branch there as met with its parent: complete, not cut short
    assert "parent" in [e.reason for e in doubled.ends] and doubled.complete


def test_bad_input_is_refused_before_any_work():
    params = get_preset("fig10").params
    with pytest.raises(ValueError, match="param must be one of eps, beta, gamma, sigma, Abar, lam, chi"):
        ImpactOrbitProblem(params, "n")
    with pytest.raises(ValueError, match="stiffness"):
        ImpactOrbitProblem(params.replace(sigma=25.0))


def test_shoot_model_impact_traces_the_fig13_branch_with_its_pitchforks_and_torus(tmp_path, capsys):
    """``slosh-bif shoot --model impact`` on the Fig. 13 set: the symmetric primary branch over
    sigma in [-3, 5] with two branch points and a Neimark-Sacker point, whose multipliers an
    independent finite-difference Jacobian of the reference flow's map puts on the unit circle."""
    import csv

    from slosh_bif.cli import main

    assert (
        main(
            [
                "shoot",
                "--preset",
                "fig13",
                "--model",
                "impact",
                "--sigma-min",
                "-3",
                "--sigma-max",
                "5",
                "--no-switch",
                "--out",
                str(tmp_path),
            ]
        )
        == 0
    )
    rows = list(csv.DictReader(open(tmp_path / "branch.csv")))
    assert {r["branch"] for r in rows} == {"symmetric"}  # a symmetric start: traced on the half-period map
    kinds = [k for r in rows for k in r["special"].split()]
    assert kinds.count("BP") == 2 and kinds.count("NS") == 1
    ns = next(r for r in rows if "NS" in r["special"].split())
    params = get_preset("fig13").params.replace(sigma=float(ns["sigma"]))
    piece = np.load(tmp_path / f"symmetric-piece{ns['piece']}.npz")
    x = piece["x"][np.argmin(np.abs(piece["p"] - float(ns["sigma"])))]
    phase = float(ns["phase"])

    def reference_map(z):
        return simulate_impact(params, z, (phase, phase + 2 * np.pi), backend="scipy").y[:, -1]

    mu = np.linalg.eigvals(_fd_jacobian(reference_map, x))
    assert np.sort(np.abs(mu))[-2:] == pytest.approx([1.0, 1.0], abs=1e-5)
    out = capsys.readouterr().out
    assert "wrote" in out
    # how each is crossed (the pitchforks' verdicts are checked against the switched branch in
    # test_impact_criticality): printed and in branch.csv's criticality column
    assert "BP at sigma = -2.00827: soft (b = " in out and "BP at sigma = 0.437172: hard (b = " in out
    assert "NS at sigma = 3.51104: hard (d = " in out
    verdicts = sorted(r["criticality"].split(" ")[0] for r in rows if r["criticality"])
    saved = [np.load(path) for path in sorted(tmp_path.glob("symmetric-piece*.npz"))]
    assert verdicts == sorted(v for s in saved for v in s["special_verdict"] if v) == ["hard", "hard", "soft"]
    # where an impact reached the section the branch went on from a section moved along the orbit:
    # the new piece's first state is the old piece's last one carried there by the reference flow
    pieces = [np.load(tmp_path / f"symmetric-piece{k}.npz") for k in sorted({int(r["piece"]) for r in rows})]
    pairs = [
        (a, b, i, j)
        for a in pieces
        for b in pieces
        if float(a["phase"]) != float(b["phase"])
        for i in (0, -1)
        for j in (0, -1)
        if a["p"][i] == b["p"][j]
    ]
    assert pairs
    old, new, i, j = pairs[0]
    phase_old, phase_new = float(old["phase"]), float(new["phase"])
    at = get_preset("fig13").params.replace(sigma=float(old["p"][i]))
    later = phase_new if phase_new > phase_old else phase_new + 2 * np.pi
    carried = simulate_impact(at, old["x"][i], (phase_old, later), backend="scipy").y[:, -1]
    np.testing.assert_allclose(carried, new["x"][j], atol=1e-6)


def test_a_symmetric_orbit_is_a_fixed_point_of_the_half_period_map_whose_multipliers_square_to_the_periods():
    """Fig. 13 at sigma = -3: the orbit a simulation settles on is symmetric, y(tau + pi) = -y(tau);
    Newton on the half-period map G = -phi_pi finds the same state, and the squares of G's
    multipliers are the period map's (a separate product of propagators and saltations)."""
    p = get_preset("fig13")
    params = p.params.replace(sigma=-3.0)
    x0 = simulate_impact(params, p.state0, (0.0, 300 * np.pi)).y[:, -1]
    full, half = ImpactOrbitProblem(params), ImpactOrbitProblem(params, symmetric=True)
    x_full = newton(full, x0, -3.0, tol=1e-12)
    x_half = newton(half, x0, -3.0, tol=1e-12)
    np.testing.assert_allclose(x_half, x_full, atol=1e-9)
    mu_full = np.sort_complex(full.eigenvalues(x_full, -3.0))
    mu_half = np.sort_complex(half.map_multipliers(x_half, -3.0) ** 2)
    np.testing.assert_allclose(mu_half, mu_full, atol=1e-9)
    np.testing.assert_allclose(np.sort_complex(half.eigenvalues(x_half, -3.0)), mu_full, atol=1e-9)


def test_shoot_model_impact_switches_at_the_pitchforks_of_the_symmetric_branch(tmp_path, capsys):
    """The asymmetric branch of (8) born at the pitchforks of the Fig. 13 symmetric branch (sigma =
    0.43717 and -2.00827, located on the half-period map): continued through its grazings it joins
    the two; its orbits are periodic but not symmetric under the reference flow (scipy's expm
    between impacts), which also checks that the pitchfork's orbit is symmetric."""
    import csv

    from slosh_bif.cli import main

    assert (
        main(
            [
                "shoot",
                "--preset",
                "fig13",
                "--model",
                "impact",
                "--sigma-min",
                "-3",
                "--sigma-max",
                "5",
                "--out",
                str(tmp_path),
            ]
        )
        == 0
    )
    # every branch is whole: the period-2 branch born at 0.553359 ends at a grazing beside its
    # parent's (0.6113707), on the parent's orbit, and the other doubled branches close as loops
    assert "meets its parent at the parent's grazing" in capsys.readouterr().err
    rows = list(csv.DictReader(open(tmp_path / "branch.csv")))
    # and the cascade born at the asymmetric branch's period doublings (six branches, the default;
    # which doublings come first depends on the order the loop is traced in)
    names = {r["branch"] for r in rows}
    assert len(names) == 6 and {"symmetric", "asymmetric", "period-2"} <= names
    bps = sorted(
        float(r["sigma"]) for r in rows if r["branch"] == "symmetric" and "BP" in r["special"].split()
    )
    assert bps == pytest.approx([-2.00827, 0.43717], abs=1e-4)
    P = get_preset("fig13").params
    part = [r for r in rows if r["branch"].startswith("asymmetric")]
    for bp in bps:
        assert min(abs(float(r["sigma"]) - bp) for r in part) < 1e-4  # they reach both pitchforks
    for k in (0, 1):
        piece = np.load(tmp_path / f"asymmetric-piece{k}.npz")
        i = len(piece["p"]) // 2
        x, sigma, phase = piece["x"][i], float(piece["p"][i]), float(piece["phase"])
        assert min(abs(sigma - bp) for bp in bps) > 0.02
        at = P.replace(sigma=sigma)
        full = simulate_impact(at, x, (phase, phase + 2 * np.pi), backend="scipy").y[:, -1]
        half = simulate_impact(at, x, (phase, phase + np.pi), backend="scipy").y[:, -1]
        np.testing.assert_allclose(full, x, atol=1e-7)
        assert np.linalg.norm(half + x) > 1e-2  # y(tau + pi) != -y(tau): not symmetric


def test_an_asymmetric_start_finds_its_symmetric_parent_by_switching_at_its_branch_point():
    """From the Fig. 10 set's asymmetric orbit (sigma = 3) the family of (8) switches at the
    asymmetric branch's branch point onto the symmetric branch (traced on the half-period map): it
    has its pitchfork at the same sigma, 3.49970, and its orbits are symmetric under the reference
    flow (scipy's expm between impacts): y(tau + pi) = -y(tau)."""
    from slosh_bif.orbits.settings import BranchingSettings
    from slosh_bif.studies.chart.impact import impact_family

    params, x0 = _settled("fig10 sigma=3")
    family = impact_family(
        params, x0, param="sigma", p_range=(2.5, 4.0), branching=BranchingSettings(doublings=False)
    )
    names = [nb.name for nb in family]
    assert names[:2] == ["primary", "symmetric"] and family[1].symmetric
    bps = [s.p for nb in family[:2] for pc in nb.branch.pieces for s in pc.branch.special if s.kind == "BP"]
    assert len(bps) >= 2 and max(bps) - min(bps) < 1e-5 and bps[0] == pytest.approx(3.49970, abs=1e-4)
    piece = family[1].branch.pieces[0]
    i = len(piece.branch) // 2
    y0, p, phase = piece.branch.x[i], piece.branch.p[i], piece.phase
    half = simulate_impact(params.replace(sigma=p), y0, (phase, phase + np.pi), backend="scipy").y[:, -1]
    assert np.abs(half + y0).max() < 1e-8


def test_a_torus_point_behind_a_pair_meeting_in_the_same_step_is_located():
    """Symmetric orbits of (8) at eps 0.080, beta 0.14, gamma 0.29, lam 0.047, chi 0.42, n 27,
    pbar 3, sigma 1.1296, continued down in Abar: two real multipliers above 1 meet, and the
    complex pair they make crosses the unit circle, within one step of 0.2, where no test
    changed sign and the branch turned stable with no special point. A step whose ends differ in
    stability is shortened: the NS point is the one a run with steps of at most 0.01 locates."""
    from slosh_bif.continuation import ContinuationOptions
    from slosh_bif.model.params import Params
    from slosh_bif.orbits.impact.branches import settled_orbit, trace_impact_orbits

    params = Params(
        eps=0.07994907227438248,
        beta=0.1412897694323314,
        gamma=0.28517375827351965,
        sigma=1.1296,
        Abar=1.389,
        lam=0.047223027937772666,
        chi=0.41876001098223814,
        n=27,
        pbar=3,
    )
    x0 = settled_orbit(params, [-0.60363, 0.08571, 0.88036, -0.92619], periods=100)

    def torus_points(options=None):
        branch = trace_impact_orbits(
            params, x0, param="Abar", p_min=0.5, p_max=1.389, symmetric=True, options=options
        )
        return [p for p, _ in branch.special("NS")]

    fine = torus_points(ContinuationOptions(step=0.01, step_max=0.01, tol=1e-10))
    assert len(fine) == 1 and torus_points() == pytest.approx(fine, abs=1e-8)


def test_a_switch_newton_cannot_settle_is_passed_over_and_said_not_fatal_to_the_family():
    """A tank near 1:1 (beta = 0.93): the symmetric branch's pitchfork at sigma = -5.47 is so flat
    (b = -0.014) that the switched start, 1e-8 from it in sigma, leaves F_x singular to 1e-13 and
    Newton at fixed sigma stalls at |F| = 3e-7. The family keeps its symmetric branch and says
    which switch it passed over."""
    from slosh_bif.orbits.impact.starts import impact_start
    from slosh_bif.orbits.settings import BranchingSettings
    from slosh_bif.studies.chart.impact import impact_family

    params = Params(
        eps=0.02522159110675746, beta=0.9347875095748552, gamma=1.5198551406668455, sigma=1.494378875761165,
        Abar=5.705038614922699, lam=0.35, chi=0.2, n=50, pbar=0,
    )  # fmt: skip
    start = impact_start(params, get_preset("fig10").state_for(params), periods=150, p_range=(-6.0, 8.0))
    said = []
    family = impact_family(
        start.params,
        start.x,
        param="sigma",
        p_range=(-6.0, 8.0),
        branching=BranchingSettings(),
        say=said.append,
    )
    assert family[0].name == "symmetric" and family[0].branch.pieces
    assert any(m.startswith("no branch switched at the BP at sigma = -5.470") for m in said)


def test_a_corrected_orbit_whose_strobe_leaves_the_wall_from_beyond_its_slowest_clearance():
    """The corrected impact model at a wall of n = 20 (lam 0.35, chi 0.23; sigma 0.63, Abar 1.17):
    at tau = 0 the settled orbit's particle has just left the wall at |w| = 0.9995, beyond the
    clearance of the slowest measured speed D(v_min) (where g still reads it as inside the wall),
    moving away. Such a state is the flow's own: Newton on the map accepts it (it was refused as
    outside the domain, so every fit, start and chart from such a strobe failed), and the orbit
    found returns to itself over one period when simulated at another sample step."""
    from slosh_bif.flows.impact.band import inside_measured_wall
    from slosh_bif.orbits.impact.branches import settled_orbit

    at = get_preset("fig10").params.replace(
        eps=0.076, beta=0.14, gamma=0.37, sigma=0.63, Abar=1.17, lam=0.35, chi=0.23, n=20, pbar=0
    )
    y0 = np.array([-0.55276892, 0.32357286, 0.80555477, -0.70499684])  # the slow flow's motion
    x = settled_orbit(at, y0, periods=100, tries=1, variant="corrected")
    problem = ImpactOrbitProblem(at, variant="corrected")
    assert inside_measured_wall(problem.flow_at(at.sigma).wall, x) < 0 and np.sign(x[2]) * x[3] < 0
    assert problem.in_domain(x, at.sigma)
    run = simulate_impact(at, x, (0.0, 2 * np.pi), sample_step=0.02, variant="corrected", continued=True)
    assert run.success and len(run.impact_t) == 2
    np.testing.assert_allclose(run.y[:, -1], x, rtol=0, atol=1e-9)


def _corrected_run(at, x, p, phase, periods=1):
    """The corrected impact model from x on the section tau = phase at sigma = p, over ``periods``
    forcing periods, simulated at its own sample step (0.02), not the map's."""
    return simulate_impact(
        at.replace(sigma=float(p)),
        x,
        (phase, phase + 2 * np.pi * periods),
        sample_step=0.02,
        variant="corrected",
        continued=True,
    )


def test_a_corrected_branch_goes_on_past_the_corner_of_the_laws_least_speed():
    """A random set's corrected impact model (n = 35, pbar = 1, lam 0.589, chi 0.137): its symmetric
    branch's slow impact reaches the measured law's least speed 0.05 twice, where the law is held
    constant below and the map has a corner (each a fold: the branch turns back there). The
    continuation stalled there, ending the branch at sigma = 0.52 and -0.51 of [-6, 8]; it now
    goes on past both along the other side's tangent and covers the range. Every piece's first
    orbit, those just beyond the corners included, returns to itself over a period when simulated
    at another sample step (to 1e-7: impacts at 0.05 amplify the flows' rounding 20-fold)."""
    from slosh_bif.orbits.impact.branches import settled_orbit

    at = get_preset("fig10").params.replace(
        eps=0.0371, beta=0.074, gamma=0.437, sigma=4.758, Abar=3.441, lam=0.589, chi=0.137, n=35, pbar=1
    )
    x0 = settled_orbit(at, get_preset("fig10").state0, periods=150, variant="corrected")
    branch = trace_impact_orbits(at, x0, p_min=-6.0, p_max=8.0, symmetric=True, variant="corrected")
    assert branch.complete and {e.reason for e in branch.ends} == {"parameter bound"}
    lows = [p.branch.p.min() for p in branch.pieces] + [p.branch.p.max() for p in branch.pieces]
    assert min(lows) == -6.0 and max(lows) == 8.0
    for piece in branch.pieces:
        x, p = piece.branch.x[0], piece.branch.p[0]
        run = _corrected_run(at, x, p, piece.phase)
        assert run.success
        np.testing.assert_allclose(run.y[:, -1], x, rtol=0, atol=1e-7)


@pytest.mark.slow  # a branch of eight pieces (3 s); the corner's fast test is the one above
def test_a_corner_the_branch_passes_straight_through_is_crossed_on_the_side_the_parameter_takes():
    """A random set's corrected impact model (seed 304 of the robustness draws): its asymmetric
    branch reaches the law's least speed at sigma = 0.23658 with sigma falling and goes on below
    it with sigma still falling. Along the other side's tangent the slowest speed moves with sigma
    as much as with the state; orienting the tangent by the state's part alone sent the steps back
    onto the side it came from, and the branch ended there. It now crosses and closes as a loop;
    its orbits just beyond the corner return to themselves at another sample step (to 1e-7)."""

    at = get_preset("fig10").params.replace(
        eps=0.0909,
        beta=0.192,
        gamma=0.332,
        sigma=-1.0281034715762218,
        Abar=3.226,
        lam=0.136,
        chi=0.113,
        n=35,
        pbar=3,
    )
    x0 = [3.27702578459555, 1.6005908583382151, -0.9484647402436985, 1.8552596843950633]
    branch = trace_impact_orbits(at, x0, p_min=-6.0, p_max=8.0, variant="corrected")
    assert branch.complete and not any("least speed" in e.message for e in branch.ends)
    beyond = []
    for piece in branch.pieces:
        problem = ImpactOrbitProblem(at, phase=piece.phase, variant="corrected")
        for x, p in zip(piece.branch.x, piece.branch.p):
            if abs(p - 0.23658) < 1e-3 and slowest_impact(problem, x, p) < 0.05 * (1 - 1e-4):
                beyond.append((piece.phase, x, p))
    assert beyond
    for phase, x, p in beyond[:3]:
        run = _corrected_run(at, x, p, phase)
        assert run.success
        np.testing.assert_allclose(run.y[:, -1], x, rtol=0, atol=1e-7)


@pytest.mark.slow  # a branch of several pieces (7 s); the corner's fast test is the one above
def test_a_corner_crept_up_to_is_crossed_and_not_called_a_grazing():
    """Another random set (n = 6, pbar = 2, lam 0.563, chi 1.082): the asymmetric branch creeps up
    to the law's corner (an impact at 0.05, whose grazing gap v^2 / 2a is 7e-4) and ended there as
    at a grazing point, from which a chart then tried to start a grazing curve and failed. The
    corner is crossed (the side it came from read off the piece before, whose points are clear of
    it), and every grazing point the branch records is one: its gap vanishes."""
    from slosh_bif.orbits.impact.branches import settled_orbit

    at = get_preset("fig10").params.replace(
        eps=0.0723, beta=0.223, gamma=0.297, sigma=-2.389, Abar=2.583, lam=0.563, chi=1.082, n=6, pbar=2
    )
    x0 = settled_orbit(at, get_preset("fig10").state0, periods=150, variant="corrected")
    branch = trace_impact_orbits(at, x0, p_min=-4.389, p_max=-0.389, variant="corrected")
    assert len(branch.grazing) == 2
    for p, x, phase in branch.grazing:
        problem = ImpactOrbitProblem(at, variant="corrected", phase=phase)
        assert abs(problem.grazing(x, p).gap) < 1e-9
    assert max(piece.branch.p.max() for piece in branch.pieces) > -0.5  # beyond the corner at -0.5525


def test_a_fold_tests_sign_change_at_the_laws_corner_is_no_fold():
    """A soft wall's period-2 orbits (n = 3, pbar = 3, lam 0.056, chi 1.255; a random set), stepped
    across the law's corner without stalling: the fold test changes sign there and was located as
    an LP at sigma = 0.425527 (judged "a jump, a = -2.7"), whose multipliers (1.244 +- 0.063i,
    0.787, 0.387) have none at 1, and a chart's fold curve failed to start from it. The corner is
    where the slowest impact is at 0.05 (by ``simulate_impact``'s own impact speeds), and no
    special point is reported there; the fold of the smooth part (0.426109) is."""
    at = get_preset("fig10").params.replace(
        eps=0.0426,
        beta=0.281,
        gamma=0.059,
        sigma=0.4301023757693159,
        Abar=1.23,
        lam=0.056,
        chi=1.255,
        n=3,
        pbar=3,
    )
    y0 = np.array([-1.96486609, 0.41721625, 0.28745567, 1.63980181])  # tau = 0, from the family's orbit
    x0 = newton(ImpactOrbitProblem(at, variant="corrected", period_multiple=2), y0, at.sigma)
    branch = trace_impact_orbits(at, x0, p_min=0.40, p_max=0.44, period_multiple=2, variant="corrected")
    special = [(s, piece) for piece in branch.pieces for s in piece.branch.special if s.kind != "END"]
    assert any(s.kind == "LP" and abs(s.p - 0.426109) < 1e-5 for s, _ in special)
    for s, piece in special:
        run = _corrected_run(at, s.x, s.p, piece.phase, periods=2)
        assert abs(np.abs(run.impact_v_minus).min() - 0.05) > 1e-4, (s.kind, s.p)


# the run's last points (sigma, state on the section tau = PAIR_PHASE), the slower of the pair falling
# to v_min = 0.05 with sigma; the last is the stalled END
PAIR_RUN = [
    (-0.5251563570820801, [-1.6031229435695493, 3.618795591930465, 0.46458308997853404, 0.19632091207931918]),
    (-0.5251593076893788, [-1.6031098936143207, 3.618790952247515, 0.4645836689033572, 0.1963213607892584]),
    (-0.5251604879367475, [-1.6031046736409538, 3.6187890963518328, 0.4645839004720587, 0.1963215402666246]),
    (-0.5251614321365495, [-1.603100497666332, 3.6187876116246414, 0.46458408572646914, 0.1963216838450211]),
    (
        -0.5251614557415135,
        [-1.6031003932664118, 3.6187875745080986, 0.46458409035787973, 0.19632168743541678],
    ),
    (-0.5251614651835559, [-1.6031003515070656, 3.618787559659662, 0.46458409221038266, 0.19632168887056045]),
    (-0.5251614661277719, [-1.603100347331232, 3.618787558174525, 0.4645840923956209, 0.196321689013914]),
]
PAIR_PHASE = 5.144708599910398


def test_one_of_a_pair_of_impacts_at_the_corner_is_taken_across_and_the_orbit_closes():
    """A branch of a random set's corrected impact model (seed 305 of the robustness draws)
    stalls where a mirror pair of slow impacts reaches the law's least speed together. The orbit
    beyond, found from the run's last points, takes one of the pair across and holds the other,
    and returns to itself when simulated at another sample step."""
    at = get_preset("fig10").params.replace(
        eps=0.0723, beta=0.223, gamma=0.297, sigma=-0.4822, Abar=2.583, lam=0.563, chi=1.082, n=6, pbar=2
    )
    problem = ImpactOrbitProblem(at, phase=PAIR_PHASE, impacts=4, variant="corrected")
    p_end, x_end = PAIR_RUN[-1]
    speeds = np.abs(problem.evaluate(np.array(x_end), p_end).impacts[:, 2])
    assert np.sum(np.abs(speeds - 0.05) < 1e-6) == 2  # the pair, both at the corner
    branch = SimpleNamespace(p=np.array([p for p, _ in PAIR_RUN]), x=np.array([x for _, x in PAIR_RUN]))
    end = SimpleNamespace(index=len(PAIR_RUN) - 1, x=np.array(x_end), p=p_end)
    found = across_the_corner(problem, branch, end, (-6.0, 8.0))
    assert found is not None
    x, q, _ = found
    assert abs(q - p_end) < 1e-4 and sum(corner_sides(problem, x, q)) == 1  # one across, one held
    run = simulate_impact(
        at.replace(sigma=float(q)),
        x,
        (PAIR_PHASE, PAIR_PHASE + 2 * np.pi),
        sample_step=0.02,
        variant="corrected",
        continued=True,
    )
    assert run.success
    np.testing.assert_allclose(run.y[:, -1], x, rtol=0, atol=1e-7)
