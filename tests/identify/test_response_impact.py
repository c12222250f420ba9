"""A frequency response fitted by the stable orbits of the vibro-impact model (8): the first
harmonic's quadrature against an adaptive integral, recovery from points of (8)'s continued branch
(another code path: pseudo-arclength continuation, and A1 by the plain trapezoid on a 40 times
finer sample), the slow flow's bias on the same data, and the refusals."""

import json

import numpy as np
import pytest
from scipy import integrate

from slosh_bif import get_preset
from slosh_bif.cli import main
from slosh_bif.identify.response_data import ResponseData
from slosh_bif.identify.response_fit import fit_response
from slosh_bif.identify.response_impact import first_harmonic_c1
from slosh_bif.orbits.impact.branches import settled_orbit, trace_impact_orbits
from slosh_bif.orbits.impact.output import first_harmonic
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem

TRUTH = get_preset("fig10").params  # lam = 0.35, chi = 0.2, gamma = 0.2, pbar = 0, n = 50, Abar = 3


def test_the_corrected_trapezoid_is_fourth_order_for_a_c1_signal_with_a_kink_in_its_slope():
    """X = sin(t) + 0.3 |t - 2|^1 * (t - 2) (C1: its second derivative jumps at t = 2, a sample
    point, as at an impact): A1 against scipy's quad split at the kink; the error falls 16-fold per
    halving of the step."""

    def X(t):
        return np.sin(t) + 0.3 * np.abs(t - 2.0) * (t - 2.0)

    def Xd(t):
        return np.cos(t) + 0.6 * np.abs(t - 2.0)

    T = 2 * np.pi
    parts = [
        sum(integrate.quad(lambda t, f=f: X(t) * f(t), a, b, epsabs=1e-15)[0] for a, b in ((0, 2), (2, T)))
        for f in (np.cos, np.sin)
    ]
    exact = np.hypot(*parts) / np.pi
    errors = []
    for h in (0.04, 0.02, 0.01):
        t = np.union1d(np.arange(0.0, T, h), [2.0, T])
        errors.append(abs(first_harmonic_c1(t, X(t), Xd(t)) - exact))
    assert errors[-1] < 1e-11
    assert errors[0] / errors[1] > 12 and errors[1] / errors[2] > 12


@pytest.fixture(scope="module")
def impact_points():
    """A1 of the orbits of (8) on the branch continued over sigma in [3.5, 6] (Fig. 10 set) from
    the orbit a simulation settles on at sigma = 5, at 8 of its points; A1 by the trapezoid on a
    sample step of 5e-4."""
    at = TRUTH.replace(sigma=5.0)
    x0 = settled_orbit(at, np.array([0.5, 0.0, 0.9, 0.0]), periods=300)
    branch = trace_impact_orbits(at, x0, p_min=3.5, p_max=6.0)
    sigma, A = [], []
    for piece in branch.pieces:
        b = piece.branch
        for k in range(0, len(b.p), 3):
            orbit = ImpactOrbitProblem(TRUTH, phase=piece.phase).orbit(b.x[k], b.p[k], step=5e-4)
            sigma.append(float(b.p[k]))
            A.append(first_harmonic(orbit[0], orbit[1][0]))
    order = np.argsort(sigma)
    sigma, A = np.array(sigma)[order], np.array(A)[order]
    pick = np.unique(np.linspace(0, len(sigma) - 1, 8).round().astype(int))
    return ResponseData(sigma[pick], A[pick], None, (), "orbits of (8)")


def test_the_impact_model_fit_gives_back_the_wall_and_the_damping(impact_points):
    fit = fit_response(impact_points, TRUTH.replace(lam=0.5, gamma=0.15), ["lam", "gamma"], model="impact")
    assert fit.converged and fit.rms < 1e-6
    assert fit.values["lam"] == pytest.approx(TRUTH.lam, rel=1e-5)
    assert fit.values["gamma"] == pytest.approx(TRUTH.gamma, rel=1e-5)
    # the slow flow (46) on the same points: the expansion's error read as damping
    slow = fit_response(impact_points, TRUTH.replace(lam=0.5, gamma=0.15), ["lam", "gamma"])
    assert abs(slow.values["gamma"] / TRUTH.gamma - 1) > 0.02


def test_lam_and_chi_enter_8_only_through_C_and_eps_is_fitted(impact_points):
    fit = fit_response(impact_points, TRUTH.replace(lam=0.5, chi=0.5), ["lam", "chi"], model="impact")
    assert "(8) with the law (21) depends on lam and chi only" in fit.not_identifiable
    assert "chi" not in fit.values
    mass = fit_response(impact_points, TRUTH.replace(eps=0.04), ["eps"], model="impact")
    assert mass.values["eps"] == pytest.approx(TRUTH.eps, rel=1e-5)


def test_slosh_bif_fit_by_the_impact_model_and_its_refusals(tmp_path, capsys):
    sigma = np.array([4.0, 4.5, 5.0, 5.5])
    data = tmp_path / "r.csv"
    data.write_text("sigma,A\n4.0,0.577\n4.5,0.511\n5.0,0.4585\n5.5,0.416\n")
    out = tmp_path / "fit"
    code = main(
        ["fit", "--preset", "fig10", "--data", str(data), "--free", "gamma", "--model", "impact"]
        + ["--out", str(out)]
    )
    assert code == 0 and (out / "fit.json").exists() and (out / "fit.png").exists()
    assert "the orbits of the vibro-impact model (8)" in capsys.readouterr().out
    # the starts side by side on two processes: the fit run one start after another
    side = tmp_path / "side"
    args = ["fit", "--preset", "fig10", "--data", str(data), "--free", "gamma", "--model", "impact"]
    assert main(args + ["--workers", "2", "--out", str(side)]) == 0
    one, two = (json.loads((folder / "fit.json").read_text()) for folder in (out, side))
    assert two["estimate"] == one["estimate"] and two["minima"] == one["minima"]
    capsys.readouterr()
    assert main(args + ["--workers", "0", "--out", str(side)]) == 2
    assert "--workers takes an integer in [1, 256]; got 0" in capsys.readouterr().err
    with pytest.raises(ValueError, match="n and pbar are profiled by the slow flows only"):
        fit_response(ResponseData(sigma, sigma, None, (), "x"), TRUTH, ["pbar", "gamma"], model="impact")
    with pytest.raises(ValueError, match="eps does not enter"):
        fit_response(ResponseData(sigma, sigma, None, (), "x"), TRUTH, ["eps"], model="slowflow")


def _tank_response(tmp_path, frequencies):
    """A tank file (the README's tank at 0.3 g) and the slow flow's stable steady states at each
    excitation frequency, each from its own parameter set by ``tank_model`` and Newton on (45)
    (scipy's root; the fit's roots of (46) only as its start), in metres."""
    import dataclasses
    import warnings

    from scipy import optimize

    from slosh_bif.identify.response_model import response_curve
    from slosh_bif.model.parameter_file import render_parameter_file
    from slosh_bif.model.tank import Site, Tank, tank_model
    from slosh_bif.slowflow.flow import SlowFlow

    tank = Tank("cylinder", depth=8.0, radius=5.0)
    site = Site(2e6, 0.8, 0.72, 3.0, 1.0, 0.02)
    path = tmp_path / "tank.toml"
    path.write_text(render_parameter_file(tank={**dataclasses.asdict(tank), **dataclasses.asdict(site)}))
    A = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for f in frequencies:
            params = tank_model(tank, dataclasses.replace(site, excitation_frequency=f)).params
            flow = SlowFlow(params)
            (A0, _), *_ = response_curve(params).states_at(params.sigma)
            start = [A0 * 1.01, flow.steady_phase(A0) + 0.01]
            root = optimize.root(lambda z: flow.rhs(z[0], z[1]), start, tol=1e-13)
            assert np.abs(flow.rhs(*root.x)).max() < 1e-13
            assert np.all(np.linalg.eigvals(flow.jac(*root.x)).real < 0)
            A.append(root.x[0] * site.clearance)
    return path, np.array(A)


def test_a_response_in_hz_and_metres_is_fitted_through_the_tank_file(tmp_path, capsys):
    """Each point its own parameter set (gamma ~ 1/f, Abar ~ 1/f**4 at constant ground
    acceleration, as ``tank_model`` makes them): gamma at the file's frequency comes back to 1e-6."""
    from slosh_bif.identify.response_data import read_response_data
    from slosh_bif.model.parameter_file import read_parameter_file, read_site

    frequencies = np.linspace(0.62, 0.84, 9)
    path, A = _tank_response(tmp_path, frequencies)
    data_file = tmp_path / "measured.csv"
    data_file.write_text("f_hz,A_m\n" + "".join(f"{f:.17g},{a:.17g}\n" for f, a in zip(frequencies, A)))
    truth = read_parameter_file(path).params
    data = read_response_data(data_file, truth, read_site(path))
    fit = fit_response(data, truth.replace(gamma=0.8 * truth.gamma), ["gamma"])
    assert fit.values["gamma"] == pytest.approx(truth.gamma, rel=1e-6)
    out = tmp_path / "fit"
    assert (
        main(["fit", "--params", str(path), "--data", str(data_file), "--free", "gamma", "--out", str(out)])
        == 0
    )
    with pytest.raises(
        ValueError, match=r"measured.csv: a response in Hz and metres \(f_hz, A_m\) needs the tank"
    ):
        read_response_data(data_file)
    with pytest.raises(ValueError, match="eps sets the map from Hz to sigma"):
        fit_response(data, truth, ["eps"], model="smooth")


def test_the_impact_free_response_is_the_linear_flights_2pi_orbit():
    """Re Y e^(i tau) integrated by scipy over one period of (8)'s flight returns to itself."""
    from slosh_bif.identify.response_model import impact_free
    from slosh_bif.model.equations import ImpactModel

    for sigma in (-6.0, -2.5, 5.0):
        params = TRUTH.replace(sigma=sigma)
        model = ImpactModel(params)
        Y = np.linalg.solve(1j * np.eye(4) - model.matrix, model.forcing.astype(complex))
        run = integrate.solve_ivp(model.rhs, (0.0, 2 * np.pi), Y.real, rtol=1e-12, atol=1e-13)
        assert np.abs(run.y[:, -1] - Y.real).max() < 1e-9
        A, w = impact_free(params)
        assert A == pytest.approx(np.hypot(Y.real[0], Y.real[1]), rel=1e-12) and w == abs(Y[2])


def test_a_sweep_label_is_evidence_not_a_constraint():
    """Fig. 10 set: resonant states of (46) at every sigma in [-6, 2], the impact-free response
    too below sigma = -2. A down-sweep measured on the impact-free response below sigma = -3 is
    compared with it, as the same points without a direction are: the label does not force a
    point onto a branch it does not fit. Where the points' std makes both states explain them
    (within two std), the label decides: the down-sweep stays on the resonant branch. An up-sweep
    from the impact-free response is compared with it while it lasts, then with the resonant
    branch; a fit of gamma to both sweeps gives it back."""
    from slosh_bif.identify.response_fit import model_amplitudes
    from slosh_bif.identify.response_model import impact_free, response_curve

    sigma = np.linspace(-6.0, 1.0, 15)
    curve = response_curve(TRUTH)
    resonant = np.array([max(a for a, ok in curve.states_at(s) if ok) for s in sigma])
    free = np.array([impact_free(TRUTH.replace(sigma=s)) for s in sigma])
    inside = free[:, 1] < 1.0
    # a "measured" down-sweep that dropped to the impact-free response at sigma = -3
    dropped = np.where(sigma < -3.0, free[:, 0], resonant)
    down = ResponseData(sigma, dropped, None, ("down",) * len(sigma), "down")
    assert np.allclose(model_amplitudes(down, TRUTH), dropped, rtol=1e-9)
    nearest = ResponseData(sigma, dropped, None, (), "no direction")
    assert np.allclose(model_amplitudes(nearest, TRUTH), dropped, rtol=1e-9)
    # a std as large as the states' separation: both explain the points, and the sweep stays
    wide = ResponseData(sigma, dropped, np.abs(resonant - free[:, 0]) + 1e-3, ("down",) * len(sigma), "wide")
    assert np.allclose(model_amplitudes(wide, TRUTH), resonant, rtol=1e-9)
    # an up-sweep from the impact-free response: on it while it lasts, then on the resonant branch
    climbed = np.where(inside, free[:, 0], resonant)
    up = ResponseData(sigma, climbed, None, ("up",) * len(sigma), "up")
    assert np.allclose(model_amplitudes(up, TRUTH), climbed, rtol=1e-9)
    both = ResponseData(
        np.concatenate([sigma, sigma]),
        np.concatenate([climbed, resonant]),
        None,
        ("up",) * len(sigma) + ("down",) * len(sigma),
        "sweeps",
    )
    fit = fit_response(both, TRUTH.replace(gamma=0.15), ["gamma"])
    assert fit.values["gamma"] == pytest.approx(TRUTH.gamma, rel=1e-6)


def test_an_up_sweep_of_8_stays_on_the_impact_free_orbit_while_it_explains_the_points():
    """Fig. 13 set, sigma in [-6, -4.5]: (8)'s impact-free orbit (neutrally stable: the particle's
    relative mode is undamped) and its resonant orbit coexist. Points 1.5 times the impact-free
    amplitude after a first point on it, nearer the resonant orbits: without a direction, or in an
    up-sweep with a small std, they are compared with the resonant orbits; in an up-sweep whose std
    makes the impact-free orbits explain them too (within two std), with the impact-free ones."""
    from slosh_bif.identify.response_impact import ImpactResponse
    from slosh_bif.identify.response_model import impact_free

    params = get_preset("fig13").params
    sigma = np.array([-6.0, -5.5, -5.0, -4.5])
    free = np.array([impact_free(params.replace(sigma=s))[0] for s in sigma])
    A = np.concatenate([free[:1], 1.5 * free[1:]])
    nearest = ImpactResponse(ResponseData(sigma, A, None, (), "no direction"), params)
    resonant = nearest.amplitudes(params)
    assert np.all(resonant[1:] > 1.5 * free[1:]) and all(nearest.stable)
    narrow = ImpactResponse(ResponseData(sigma, A, np.full(4, 1e-3), ("up",) * 4, "up"), params)
    assert np.allclose(narrow.amplitudes(params)[1:], resonant[1:], rtol=1e-6)
    wide = ImpactResponse(ResponseData(sigma, A, np.abs(resonant - free), ("up",) * 4, "up"), params)
    assert np.allclose(wide.amplitudes(params), free, rtol=1e-6) and all(wide.stable)


@pytest.mark.parametrize("variant", ["paper", "corrected"])
def test_the_first_harmonics_own_derivatives_are_the_differences_of_newton_solved_orbits(
    impact_points, variant
):
    """dA1/dq from the flow's sensitivities along each orbit (saltation matrices, no Newton) against
    central differences of A1 of orbits Newton-solved at q +- h, at four points of the Fig. 10
    branch, in a flight parameter (gamma, Abar, eps) and, for (8), a wall parameter (lam)."""
    from slosh_bif.identify.response_impact import ImpactResponse

    data = ResponseData(impact_points.sigma[::2], impact_points.A[::2], None, (), "four points")
    response = ImpactResponse(data, TRUTH, variant=variant)
    names = ["gamma", "Abar", "eps"] + (["lam"] if variant == "paper" else [])
    assert response.differentiates(names) and response.differentiates(["lam"]) == (variant == "paper")
    response.amplitudes(TRUTH)
    gradient = response.gradient(names)
    start = response.state()
    for j, name in enumerate(names):
        h = 1e-6 * getattr(TRUTH, name)
        sides = []
        for s in (1, -1):
            response.restore(start)
            sides.append(response.amplitudes(TRUTH.replace(**{name: getattr(TRUTH, name) + s * h})))
        difference = (sides[0] - sides[1]) / (2 * h)
        np.testing.assert_allclose(gradient[:, j], difference, rtol=1e-5, atol=1e-7, err_msg=name)
