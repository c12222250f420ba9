"""The corrected slow flow (issue 20): the wall's own kappa and clearance in (36), (45), (46).

Checked against what does not share its code: the paper's generated equations through the exact
scaling of a clearance (lengths and the forcing in units of D), the symbolic reduction to (46) in
the derivation itself, finite differences of the law's slopes and of the flow, an independent
integration of single contacts, shooting on (9), and the ladder's rung."""

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from slosh_bif import get_preset
from slosh_bif.cli import main
from slosh_bif.model._generated import slow_flow as gen
from slosh_bif.model.restitution import manifold_law
from slosh_bif.model.restitution.corrected import V_RANGE
from slosh_bif.slowflow.critical import critical_forcing
from slosh_bif.slowflow.flow import AsymptoticsWarning, SlowFlow
from slosh_bif.slowflow.steady_states import frequency_response
from slosh_bif.studies.ladder import CORRECTED_ERROR, model_choice

FIG10 = get_preset("fig10").params
ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow  # the default run's derive check (tests/model/test_generated.py) runs the reduction too
def test_the_corrected_equations_reduce_to_46_symbolically():
    """D = 1 gives (36), (45), (46) back, and kappa from (21) gives (39) back (sympy, in the
    derivation); and the check can fail: at D = 1.1 the steady-state residual is not (46)'s."""
    sys.path.insert(0, str(ROOT / "derivations"))
    try:
        import slow_flow as derivation
    finally:
        sys.path.remove(str(ROOT / "derivations"))
    assert derivation.corrected_reduces_to_46()
    D = derivation.D
    residual, paper = derivation.steady_state(D)["residual"], derivation.steady_state()["residual"]
    assert (residual.subs(D, 1.1) - paper).simplify() != 0


@pytest.mark.parametrize("D", [1.0, 1.07, 1.31])
def test_a_clearance_is_the_paper_flow_in_units_of_D(D):
    """With the wall at |w| = D every length, and the forcing, scales by D: the corrected steady
    state residual is D^4 times (46)'s at (A/D, Abar/D), D1 A is D times (45)'s, D1 psi is (45)'s."""
    A, psi, rho = 1.7, 0.4, 0.21
    slow = (0.3, 0.2, 1.1, 2.5)  # beta, gamma, sigma, Abar
    scaled = slow[:3] + (slow[3] / D,)
    assert gen.corrected_steady_residual(A, rho, D, *slow) == pytest.approx(
        D**4 * gen.steady_residual(A / D, rho, *scaled), rel=1e-12
    )
    corrected, paper = gen.corrected_slow_rhs(A, psi, rho, D, *slow), gen.slow_rhs(A / D, psi, rho, *scaled)
    assert corrected[0] == pytest.approx(D * paper[0], rel=1e-12) and corrected[1] == pytest.approx(
        paper[1], rel=1e-12
    )
    assert gen.corrected_a_min(rho, D) == pytest.approx(D * gen.sim_a_min(rho), rel=1e-14)


def _independent_contact(v0, lam, chi, n, pbar):
    """Restitution, turning point and equivalent rigid wall of one contact, by Radau on a long
    window and root finding on its dense output (the package uses DOP853 with events)."""
    p = (pbar + n) // 2

    def rhs(_t, y):
        return [y[1], -chi * y[0] ** (2 * n + 1) - lam * y[1] * y[0] ** (2 * p)]

    def back(_t, y):
        return y[0]

    back.terminal, back.direction = True, -1
    sol = solve_ivp(
        rhs,
        (0, 200.0 / v0),
        [0.0, v0],
        method="Radau",
        rtol=1e-13,
        atol=1e-15,
        events=back,
        dense_output=True,
    )
    t_turn = sol.t[np.argmax(sol.y[0])]
    from scipy.optimize import brentq

    t_turn = brentq(
        lambda t: sol.sol(t)[1], 0.5 * t_turn, min(1.5 * t_turn + 1e-9, sol.t_events[0][0]), xtol=1e-15
    )
    kappa = -sol.y_events[0][0][1] / v0
    # the flights x = v0 t in and x = -kappa v0 (t - t_exit) out meet at the equivalent wall
    return kappa, float(sol.sol(t_turn)[0]), kappa * v0 * sol.t_events[0][0] / (1 + kappa)


@pytest.mark.parametrize("n, pbar", [(6, 0), (10, 2)])
def test_the_measured_wall_matches_independent_contacts(n, pbar):
    law = manifold_law(FIG10.replace(n=n, pbar=pbar, lam=0.1), "corrected").wall
    for v0 in (0.3, 2.1, 37.0):
        kappa, depth, clearance = _independent_contact(v0, 0.1, 0.2, n, pbar)
        assert abs(float(law.kappa(v0)) - kappa) < 1e-8
        assert abs(float(law.depth(v0)) - depth) < 1e-8
        assert abs(float(law.clearance(v0)) - clearance) < 1e-8


def test_the_law_solves_its_fixed_point_and_its_slopes_are_its_derivatives():
    law = manifold_law(FIG10.replace(n=10, pbar=2, lam=0.1), "corrected")
    A = np.array([law.A_min * 1.05, 0.8, 2.5, 9.0])
    rho, drho, D, dD = law.slopes(A)
    kappa = law.kappa(A)
    # The impact speed (38) with the wall's kappa and D at that same speed gives them back.
    v = gen.corrected_impact_speed(A, kappa, D)[0]
    assert np.allclose(law.wall.kappa(v), kappa, rtol=1e-13) and np.allclose(
        law.wall.clearance(v), D, rtol=1e-13
    )
    h = 1e-6
    up, down = law.values(A + h), law.values(A - h)
    assert np.allclose(drho, (up[0] - down[0]) / (2 * h), rtol=1e-6, atol=1e-10)
    assert np.allclose(dD, (up[1] - down[1]) / (2 * h), rtol=1e-6, atol=1e-10)
    assert V_RANGE[0] < law.v_end < V_RANGE[1] and law.A_min == pytest.approx(
        float(gen.corrected_a_min(law.end_values(law.lower)[0], law.D_at_end)), rel=1e-14
    )


def test_the_flows_jacobian_is_its_derivative():
    flow = SlowFlow(FIG10.replace(n=20, pbar=2, lam=0.05), "corrected")
    A, psi, h = 1.3, 0.7, 1e-6
    J = flow.jac(A, psi)
    assert np.allclose(J[:, 0], (flow.rhs(A + h, psi) - flow.rhs(A - h, psi)) / (2 * h), rtol=1e-6, atol=1e-9)
    assert np.allclose(J[:, 1], (flow.rhs(A, psi + h) - flow.rhs(A, psi - h)) / (2 * h), rtol=1e-6, atol=1e-9)


def test_frequency_response_and_critical_forcing_hold_on_the_corrected_curve():
    """Every point of the corrected branch is a steady state of the corrected (46); the critical
    forcing at sigma is the least Abar of the Abar-continued states there."""
    P = FIG10.replace(n=20)
    fr = frequency_response(P, sigma_min=-4, sigma_max=5, model="corrected")
    flow = SlowFlow(P, "corrected")
    for b in fr.branches:
        inside = b.x[:, 0] > flow.A_min * 1.001
        residual = [
            flow.steady_residual(A, sigma=s) / (np.pi**4 * A**2) for A, s in zip(b.x[inside, 0], b.p[inside])
        ]
        assert np.max(np.abs(residual)) < 1e-8
        assert any(sp.kind == "END" for sp in b.special)
    cp = critical_forcing(P, 1.0, model="corrected")
    A = np.geomspace(flow.A_min * (1 + 1e-12), 20, 20001)
    from slosh_bif.slowflow.steady_states import abar_on_curve

    assert cp.Abar_b == pytest.approx(
        np.nanmin(abar_on_curve(SlowFlow(P.replace(sigma=1.0), "corrected"), A)), rel=1e-6
    )


# Measured (docs/findings/regimes.md, "The corrected slow flow"): at these five sigmas the corrected slow flow
# is
# 0.8-8.1 % from the stable orbits of (9), eq. (46) 18-32 %; the bound leaves room for rounding
# of the settling simulation, not for a different orbit (the next one is > 30 % away).
N6_BOUND = 0.1


def _amplitudes_at(branch, sigma):
    """A where the branch crosses ``sigma`` (linear between its points; a folded branch crosses
    more than once)."""
    side = np.sign(branch.p - sigma)
    out = []
    for i in np.flatnonzero(side[:-1] * side[1:] <= 0):
        t = (sigma - branch.p[i]) / (branch.p[i + 1] - branch.p[i]) if branch.p[i + 1] != branch.p[i] else 0.0
        out.append(float(branch.x[i, 0] + t * (branch.x[i + 1, 0] - branch.x[i, 0])))
    return out


def test_corrected_frc_at_n_6_against_shooting_at_five_sigmas(capsys):
    from slosh_bif.orbits.starts import settle_and_shoot

    P = FIG10.replace(n=6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        fr = frequency_response(P, sigma_min=-7, sigma_max=-1, model="corrected")
    lines = []
    for sigma in (-6.0, -5.0, -4.0, -3.0, -2.5):
        orbit, A1 = settle_and_shoot(P.replace(sigma=sigma), get_preset("fig10").state0, 1e-10)
        assert orbit.converged and orbit.stable
        A = [a for b in fr.branches for a in _amplitudes_at(b, sigma)]
        difference = min(abs(a - A1) / A1 for a in A)
        lines.append(
            f"sigma = {sigma:g}: shooting A1 = {A1:.4f}, corrected A = "
            f"{min(A, key=lambda a: abs(a - A1)):.4f}, difference {difference:.1%}"
        )
        assert difference < N6_BOUND
    with capsys.disabled():
        print("\n" + "\n".join(lines))


def test_the_ladder_uses_the_corrected_rung_where_46_is_out_of_range():
    # n = 20 with the Fig. 10 wall: (21) is out of its range (the wall loses > 50 % per impact)
    model, reason, error = model_choice("frequency-response", FIG10.replace(n=20), tol=0.3)
    assert (
        model == "corrected slow flow"
        and error == CORRECTED_ERROR["frequency-response"]
        and "loses" in reason
    )
    # ... but not below its own range (n = 6), nor below its measured error (where the impact
    # models' orbits are next: the corrected impact model's, measured from n = 20 on)
    assert model_choice("frequency-response", FIG10.replace(n=6), tol=0.3)[0].startswith("shooting")
    assert model_choice("frequency-response", FIG10.replace(n=20), tol=0.1)[0].startswith("corrected impact")
    assert model_choice("frequency-response", FIG10.replace(n=20), tol=0.01)[0].startswith("shooting")
    # (46) first where it is in range and within the tolerance: it is the cheaper rung
    assert model_choice("frequency-response", FIG10, tol=0.3)[0] == "slow flow"


def test_cli_model_option(tmp_path, capsys):
    assert (
        main(
            [
                "frc",
                "--preset",
                "fig10",
                "--set",
                "n=20",
                "--model",
                "corrected",
                "--out",
                str(tmp_path / "frc"),
            ]
        )
        == 0
    )
    assert (tmp_path / "frc" / "frc.png").stat().st_size > 10_000
    with pytest.raises(SystemExit):
        main(["frc", "--preset", "fig10", "--model", "exact", "--out", str(tmp_path / "bad")])
    assert "invalid choice: 'exact'" in capsys.readouterr().err
    assert (
        main(
            [
                "critical",
                "--preset",
                "fig13",
                "--model",
                "corrected",
                "--sigma-min",
                "0",
                "--sigma-max",
                "2",
                "--out",
                str(tmp_path / "crit"),
            ]
        )
        == 0
    )
    assert (
        "corrected" in (tmp_path / "crit" / "critical.png").name
        or (tmp_path / "crit" / "critical.csv").exists()
    )
