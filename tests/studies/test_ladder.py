"""The lightest model for each question: choices, escalation, and the answers checked independently."""

import json
import warnings

import numpy as np
import pytest

from slosh_bif import get_preset, regime_map
from slosh_bif.cli import main
from slosh_bif.simulation.direct import simulate
from slosh_bif.simulation.regimes import classify
from slosh_bif.slowflow.flow import AsymptoticsWarning, SlowFlow
from slosh_bif.studies.ladder import QUESTIONS, SLOW_FLOW_ERROR, answer, model_choice

FIG10 = get_preset("fig10").params


@pytest.mark.parametrize("question", QUESTIONS)
def test_the_slow_flow_answers_when_its_measured_error_is_within_tol(question):
    model, reason, error = model_choice(question, FIG10, tol=0.9)
    assert model == "slow flow" and error == SLOW_FLOW_ERROR[question] and "within" in reason


@pytest.mark.parametrize("question", QUESTIONS)
def test_escalates_when_the_tolerance_is_below_the_slow_flows_error(question):
    model, reason, error = model_choice(question, FIG10, tol=0.01)
    assert model != "slow flow" and "exceeds" in reason and error <= 0.01


@pytest.mark.parametrize(
    ("change", "why"),
    [({"eps": 0.3}, "eps = 0.3"), ({"beta": 0.9}, "beta = 0.9"), ({"n": 6}, "loses")],
)
def test_escalates_outside_the_asymptotics_even_at_a_loose_tolerance(change, why):
    # large eps: the expansion is in powers of eps; beta near 1: the particle's own frequency meets
    # the resonance; small n: the wall dissipates more than eq. (21), first order, can describe
    for question in QUESTIONS:
        model, reason, _ = model_choice(question, FIG10.replace(**change), tol=0.9)
        assert model != "slow flow" and why in reason


def test_bad_input_is_named():
    with pytest.raises(ValueError, match="question must be one of"):
        model_choice("amplitude", FIG10, 0.1)
    for tol in (0, -1, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="tol"):
            model_choice("regime", FIG10, tol)
    with pytest.raises(ValueError, match="state0"):
        answer("regime", FIG10, state0=[0, 1, 2])


@pytest.mark.slow  # long simulations (15 s); test_answer_command covers the ladder by default
def test_critical_forcing_of_the_full_model_is_where_simulation_loses_the_resonant_orbit():
    """The escalated critical-forcing answer (Abar_c over every family at sigma) against direct
    simulation of (9) started on the stable orbit just above it: periodic above, not below."""
    pre = get_preset("fig13")
    got = answer("critical-forcing", pre.params, tol=0.01)
    crit = got.result
    assert got.model.startswith("shooting") and crit.bounded_by in ("NS", "LP", "PD")
    assert crit.loss in (("jump",) if crit.bounded_by == "LP" else ("soft", "hard", "undetermined"))
    Abar_c = crit.Abar_c
    # the branch with the special point that sets Abar_c, and its stable orbit just above it
    branch = next(
        ob.branch
        for ob in crit.chart.family.branches
        for sp in ob.branch.special
        if sp.kind == crit.bounded_by and abs(sp.p - Abar_c) < 1e-9
    )
    k = int(np.argmin(np.where(branch.stable & (branch.p > Abar_c + 0.03), branch.p, np.inf)))
    y_start = branch.x[k, :4]
    above = simulate(pre.params.replace(Abar=Abar_c + 0.03), y_start, 400 * 2 * np.pi)
    below = simulate(pre.params.replace(Abar=Abar_c - 0.03), y_start, 400 * 2 * np.pi)
    assert classify(above).regime == "periodic-resonant"
    assert classify(below).regime != "periodic-resonant"


def test_frequency_response_answers_by_the_chosen_model():
    loose = answer("frequency-response", FIG10.replace(sigma=5.0), tol=0.5, sigma_min=3.5, sigma_max=8.0)
    assert loose.model == "slow flow" and len(loose.result.branches) >= 1
    tight = answer("frequency-response", FIG10.replace(sigma=7.0), tol=1e-3, sigma_min=6.0, sigma_max=8.0)
    assert tight.model == "shooting on (9)"
    ob = tight.result.branches[0]
    assert ob.branch.p.min() == pytest.approx(6.0) and ob.branch.p.max() == pytest.approx(8.0)
    assert np.all(ob.measures["A1"] > 0)


def test_where_9_settles_on_no_orbit_at_the_sets_sigma_the_frequency_response_starts_from_the_slow_flow(
    scipy_flow,
):
    """A set (n = 3, pbar = 3, from a random draw) whose response at sigma = 1 a simulation of 1000
    periods leaves unsettled: shooting on (9) answers the frequency response all the same, from
    the slow flow's steady states over the range, as ``shoot`` starts (its orbits are (9)'s: one
    checked by scipy's period map)."""
    from slosh_bif.orbits.starts import settle_and_shoot

    params = FIG10.replace(eps=0.07, beta=0.015, gamma=0.13, Abar=2.4, lam=0.35, chi=1.1, n=3, pbar=3)
    orbit, _ = settle_and_shoot(params, get_preset("fig10").state_for(params))
    assert not (orbit.converged and orbit.stable)  # what sent the answer to the slow flow's start
    got = answer("frequency-response", params, tol=1e-3, sigma_min=-2.0, sigma_max=4.0)
    assert got.model == "shooting on (9)"
    ob = got.result.branches[0]
    assert ob.branch.p.min() == pytest.approx(-2.0) and ob.branch.p.max() == pytest.approx(4.0)
    k = len(ob.branch.p) // 3
    y0 = ob.branch.x[k][:4]  # the orbit's state at tau = 0 (its first arc's start)
    end, _ = scipy_flow(params.replace(sigma=float(ob.branch.p[k])), y0, 2 * np.pi)
    np.testing.assert_allclose(end, y0, rtol=0, atol=1e-7)


@pytest.mark.slow  # a 221-cell regime map of (9) (about a minute on 2 cores)
def test_regime_error_in_the_table_matches_a_fresh_regime_map():
    """SLOW_FLOW_ERROR["regime"] is the disagreement of the slow flow's prediction (integrated from
    the initial state: escape from S+ or a steady state) with the smooth model's classification
    over the Fig. 13 box (17 x 13 simulations of 4,000 time units), simulated here. Border cells
    depend on rounding (the early motion is chaotic: two runs differ in up to 11 of the 221
    cells), so the measured error is within 0.05 of the table's."""
    pre = get_preset("fig13")
    sigmas, abars = np.linspace(-3, 5, 17), np.linspace(0.1, 2.5, 13)
    fresh = regime_map(pre.params, pre.state0, sigmas, abars, tmax=4000)
    assert fresh.complete
    wrong = 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        for i, abar in enumerate(abars):
            for j, sigma in enumerate(sigmas):
                flow = SlowFlow(pre.params.replace(sigma=float(sigma), Abar=float(abar)))
                resonant = not flow.integrate(
                    *flow.start_from_state(pre.state0), (0.0, pre.params.eps * 4000 * 2 * np.pi)
                ).escaped
                wrong += resonant != (fresh.regime[i, j] == "periodic-resonant")
    assert wrong / fresh.regime.size == pytest.approx(SLOW_FLOW_ERROR["regime"], abs=0.05)


def test_answer_command_reports_model_reason_and_error(capsys, tmp_path):
    assert main(["answer", "regime", "--preset", "fig13", "--tol", "0.5", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "slow flow" in out and "error estimate 0.22" in out and "regime:" in out
    record = json.loads((tmp_path / "answer.json").read_text())
    assert (
        record["question"] == "regime"
        and record["error_estimate"] == pytest.approx(0.22)
        and record["params"]["Abar"] == 1.0
    )
    # Fig. 12 (n = 6): the slow flow is out of range, so the full model answers; the paper's
    # strongly modulated response at Abar = 0.5 means no stable resonant orbit there: Abar_c > 0.5.
    assert main(["answer", "critical-forcing", "--preset", "fig12", "--tol", "0.9"]) == 0
    captured = capsys.readouterr()
    assert "outside its checked range" in captured.err
    value = float(captured.out.split("critical forcing at sigma = 1: Abar = ")[1].split()[0])
    assert value > 0.5
    assert "crossing it is" in captured.out  # a jump or soft, as the point's normal form says


def test_a_slow_time_response_that_leaves_the_manifold_hands_over_to_the_full_model():
    # Fig. 10 set at sigma = -6: (45) from the kicked start escapes from S+ (frequency_response.csv:
    # no slow-flow answer there), so the slow flow cannot give X(tau) past the escape
    got = answer("time-response", FIG10.replace(sigma=-6.0), tol=0.5, tmax=200.0)
    assert got.model == "smooth model (9) simulated" and "leaves S+" in got.reason
    assert got.result.success and got.result.t[-1] == pytest.approx(200.0)


def test_the_impact_model_is_the_rung_between_the_slow_flows_and_shooting_on_9():
    """For the frequency response at n = 50, a tolerance below the corrected slow flow's error but
    above (8)'s measured wall error picks the orbits of (8); below that, shooting on (9); below the
    least n measured, (8) is passed over and says so."""
    from slosh_bif.studies.ladder import (
        CORRECTED_ERROR,
        CORRECTED_IMPACT,
        CORRECTED_IMPACT_ERROR,
        IMPACT,
        IMPACT_ERROR,
    )

    table = IMPACT_ERROR["frequency-response"]
    at50 = table[max(n for n in table if n <= 50)]
    assert at50 < CORRECTED_ERROR["frequency-response"]
    tol = 0.5 * (at50 + CORRECTED_ERROR["frequency-response"])
    model, reason, error = model_choice("frequency-response", FIG10, tol=tol)
    assert model == IMPACT and error == at50 and "(8)'s measured error" in reason
    # below (8)'s error, the corrected impact model's orbits (the contact's error alone); below that, (9)
    corrected = CORRECTED_IMPACT_ERROR["frequency-response"][50]
    model, reason, error = model_choice("frequency-response", FIG10, tol=0.5 * at50)
    assert model == CORRECTED_IMPACT and error == corrected and "(8) measured" in reason
    model, reason, _ = model_choice("frequency-response", FIG10, tol=0.5 * corrected)
    assert model == "shooting on (9)" and "the corrected impact model measured" in reason
    model, reason, _ = model_choice("frequency-response", FIG10.replace(n=min(table) - 2), tol=tol)
    assert model == "shooting on (9)" and "not measured below" in reason
    # the answer itself: the orbits of (8) over the range, from the orbit a simulation settles on
    from slosh_bif.orbits.impact.branches import ImpactBranch

    got = answer("frequency-response", FIG10.replace(sigma=5.0), tol=tol, sigma_min=4.5, sigma_max=5.5)
    assert got.model == IMPACT and isinstance(got.result, ImpactBranch)
    ps = np.concatenate([piece.branch.p for piece in got.result.pieces])
    assert ps.min() == pytest.approx(4.5) and ps.max() == pytest.approx(5.5)
