"""The chart of the impact model (8): ``chart --model impact`` from a fresh folder, its critical
forcing checked against a one-parameter branch of (8) in Abar (another problem class, its fold
located by its own test), one of its grazing curves against a closed form, and a curve ending near
grazing by its stated rule."""

import csv

import numpy as np
import pytest

from slosh_bif import ImpactModel, get_preset
from slosh_bif.cli import main
from slosh_bif.orbits.impact.branches import settled_orbit, trace_impact_orbits


@pytest.mark.slow  # 8-28 s; the file's other tests keep the capability in the default run
def test_the_impact_chart_from_a_fresh_folder(tmp_path):
    """One chart of (8) (about 40 s), read by the checks below (one test: pytest-xdist would draw
    a module-scoped chart once per worker)."""
    folder = _impact_chart(tmp_path / "chart8")
    _writes_every_curve_and_names_its_model(folder)
    _critical_forcing_is_the_fold_of_a_one_parameter_branch(folder)
    _grazing_curve_of_the_impact_free_response_is_its_closed_form(folder)


def _impact_chart(out):
    argv = [
        "chart",
        "--preset",
        "fig13",
        "--model",
        "impact",
        "--sigma-min",
        "-3",
        "--sigma-max",
        "5",
        "--abar-min",
        "0.1",
        "--abar-max",
        "2.5",
        "--out",
        str(out),
    ]
    assert main(argv) == 0
    return out


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _writes_every_curve_and_names_its_model(impact_chart_folder):
    curves = _rows(impact_chart_folder / "curves.csv")
    last = {r["curve"]: r for r in curves}
    assert {r["kind"] for r in last.values()} >= {"LP", "PD", "NS", "BP"}
    assert all(r["status"] == "ok" for r in last.values())
    assert all("branch of (8)" in r["origin"] for r in last.values())
    assert (impact_chart_folder / "chart.png").stat().st_size > 10_000


def _critical_forcing_is_the_fold_of_a_one_parameter_branch(impact_chart_folder):
    # Below the resonance the least forcing with a stable orbit of (8) is the fold of its
    # resonant symmetric orbits: the one-parameter branch in Abar at sigma = -2 locates it.
    row = next(r for r in _rows(impact_chart_folder / "critical.csv") if float(r["sigma"]) == -2.0)
    pre = get_preset("fig13")
    P = pre.params.replace(sigma=-2.0, Abar=0.4)
    branch = trace_impact_orbits(
        P, settled_orbit(P, pre.state_for(P), periods=150), param="Abar", p_min=0.1, p_max=1.0, symmetric=True
    )
    (fold,) = branch.special("LP")
    # the chart's reading is corrected on the fold curve's own system at sigma = -2 (the chords
    # between its points lie 7e-4 above)
    assert row["bounded_by"] == "LP" and float(row["Abar_c_full"]) == pytest.approx(fold[0], rel=1e-8)
    assert float(row["Abar_b_slowflow"]) == pytest.approx(0.3266, abs=1e-3)


def test_an_impact_curve_ends_near_grazing_by_its_rule():
    # The Fig. 13 set's fold curve of (8) from sigma = 1 runs down in sigma towards an orbit whose
    # slowest impact vanishes (grazing); it ends where that impact falls below MIN_IMPACT_SPEED,
    # at the domain's edge, named.
    from slosh_bif.orbits.impact.branches import state_at_zero
    from slosh_bif.orbits.impact.curves import ImpactCurveSeed, trace_impact_curve
    from slosh_bif.orbits.impact.problem import ImpactOrbitProblem
    from slosh_bif.orbits.impact.strobe import MIN_IMPACT_SPEED, NEAR_GRAZING

    pre = get_preset("fig13")
    P = pre.params.replace(sigma=1.0)  # Abar = 1: the resonant symmetric orbit, continued down in Abar
    x0 = settled_orbit(P, pre.state_for(P), periods=150)
    branch = trace_impact_orbits(P, x0, param="Abar", p_min=0.1, p_max=1.2, symmetric=True)
    ((piece, lp),) = [(pc, s) for pc in branch.pieces for s in pc.branch.special if s.kind == "LP"]
    seed = ImpactCurveSeed("LP", lp.x, lp.p, "Abar", symmetric=True, phase=piece.phase, impacts=piece.impacts)
    curve = trace_impact_curve(P, seed, box={"sigma": (-3.0, 5.0), "Abar": (0.1, 2.5)})
    ends = [s for s in curve.branch.special if s.kind == "END" and s.edge == NEAR_GRAZING]
    assert curve.status == "ok" and len(ends) == 1
    assert np.nanmin(curve["min_impact_speed"]) >= MIN_IMPACT_SPEED
    # the state-at-zero helper: the section's orbit mapped back to tau = 0 is a fixed point there
    problem = ImpactOrbitProblem(P.replace(Abar=lp.p), "Abar", symmetric=True, phase=piece.phase)
    at_zero = ImpactOrbitProblem(P.replace(Abar=lp.p), "Abar", symmetric=True)
    assert np.linalg.norm(at_zero.residual(state_at_zero(problem, lp.x, lp.p), lp.p)) < 1e-9


def _grazing_curve_of_the_impact_free_response_is_its_closed_form(impact_chart_folder):
    """Where the impact-free response of (8), y = Re(Y e^{i tau}) with (i - M) Y = F, first touches
    the walls: Abar |W| = 1 for the w-part W of Y at Abar = 1. One of the chart's grazing curves is
    this curve over sigma in [0.5, 3] (the lowest there, across its minimum near sigma = 0.9)."""
    P = get_preset("fig13").params
    curves = _rows(impact_chart_folder / "curves.csv")
    grazing = {}
    for r in curves:
        if r["kind"] == "GR" and 0.5 <= float(r["sigma"]) <= 3.0:
            grazing.setdefault(r["curve"], []).append((float(r["sigma"]), float(r["Abar"])))

    def closed_form(sigma):
        model = ImpactModel(P.replace(sigma=sigma, Abar=1.0))
        Y = np.linalg.solve(1j * np.eye(4) - model.matrix, model.forcing)
        return 1.0 / abs(Y[2])

    matches = [
        points
        for points in grazing.values()
        if len(points) > 5 and all(abs(a - closed_form(s)) < 1e-8 * a for s, a in points)
    ]
    assert matches, "no grazing curve on the closed form"
    fine = np.linspace(0.5, 3, 501)
    lowest = fine[np.argmin([closed_form(s) for s in fine])]
    sigmas = [s for s, a in matches[0]]
    assert min(sigmas) < lowest < max(sigmas)  # the curve runs across the closed form's minimum


def test_chart_of_the_corrected_impact_model_refuses_what_it_cannot_draw(tmp_path, capsys):
    base = ["chart", "--preset", "fig13", "--model", "impact-corrected", "--out", str(tmp_path)]
    assert main([*base, "--regimes", "3", "3"]) == 2
    assert "--regimes simulates (9) or (8)" in capsys.readouterr().err
    assert main([*base, "--second", "beta", "--second-min", "0", "--second-max", "1"]) == 2
    assert "--model impact-corrected draws the (sigma, Abar) chart" in capsys.readouterr().err
