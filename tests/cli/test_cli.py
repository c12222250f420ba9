"""The slosh-bif command line."""

import csv
import json

import numpy as np
import pytest

from slosh_bif.cli import main
from slosh_bif.model import restitution


def test_info_prints_parameters_and_restitution(capsys):
    assert main(["info", "--preset", "fig10"]) == 0
    out = capsys.readouterr().out
    assert "Abar   = 3.0" in out and "kappa Newtonian (eq. 40)" in out


def test_info_json_applies_overrides(capsys):
    assert main(["info", "--preset", "fig11a", "--set", "n=10", "--set", "lam=0.2", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["params"]["n"] == 10 and report["params"]["lam"] == 0.2
    assert report["kappa_newtonian"] == pytest.approx(restitution.kappa_newtonian(0.2, 0.2, 10), rel=1e-14)
    assert report["A_min_at_unit_speed"] == pytest.approx(
        report["rho_at_unit_speed"] / (1 + report["rho_at_unit_speed"] ** 2) ** 0.5, rel=1e-14
    )


def test_info_reports_bad_overrides(capsys):
    assert main(["info", "--preset", "fig10", "--set", "eps=-1"]) == 2
    assert "parameter eps must be in (0, inf); got -1.0" in capsys.readouterr().err


@pytest.mark.parametrize("argv", [["--help"], ["info", "--help"], ["derive", "--help"]])
def test_help_explains_itself(argv, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 0
    assert "usage: slosh-bif" in capsys.readouterr().out


def test_frc_writes_csv_png_and_branches(tmp_path, capsys):
    import csv

    from slosh_bif.continuation.branch import Branch

    assert (
        main(["frc", "--preset", "fig13", "--sigma-min", "-2", "--sigma-max", "3", "--out", str(tmp_path)])
        == 0
    )
    rows = list(csv.DictReader(open(tmp_path / "frc.csv")))
    assert {"sigma", "A", "psi", "alpha", "stable", "special"} <= set(rows[0])
    assert {r["stable"] for r in rows} <= {"0", "1"} and {r["special"] for r in rows} <= {
        "",
        "LP",
        "BP",
        "END",
    }
    assert rows[0]["special"] == "END" and float(rows[0]["sigma"]) in (-2.0, 3.0)
    assert (tmp_path / "frc.png").stat().st_size > 10_000
    branch = Branch.load(tmp_path / "frc_branch0.npz")
    assert len(branch) == sum(r["component"] == "0" for r in rows)
    assert "component 0" in capsys.readouterr().out


def test_critical_writes_csv_and_png(tmp_path, capsys):
    import csv

    assert (
        main(
            ["critical", "--preset", "fig12", "--sigma-min", "-1", "--sigma-max", "2", "--out", str(tmp_path)]
        )
        == 0
    )
    rows = list(csv.DictReader(open(tmp_path / "critical.csv")))
    assert list(rows[0])[:3] == ["sigma", "Abar_b", "A"]
    sigmas = [float(r["sigma"]) for r in rows]
    assert sigmas == sorted(sigmas) and sigmas[0] == -1.0 and sigmas[-1] == 2.0
    assert (tmp_path / "critical.png").stat().st_size > 10_000
    assert "no steady state on S+" in capsys.readouterr().out  # Fig. 12: Abar = 0.5 < Abar_b(1) = 0.705


def test_range_options_are_checked(tmp_path, capsys):
    assert (
        main(["frc", "--preset", "fig10", "--sigma-min", "3", "--sigma-max", "1", "--out", str(tmp_path)])
        == 2
    )
    assert "--sigma-min must be below --sigma-max" in capsys.readouterr().err


def test_shoot_writes_branch_csv_and_png(tmp_path, capsys):
    """Far above resonance (fig10 set at sigma = 7.5) the symmetric orbits are stable and the
    branch over [7, 8] is quick; every row is a converged orbit with its Liouville check."""
    import csv

    out = tmp_path / "shoot"
    argv = [
        "shoot",
        "--preset",
        "fig10",
        "--set",
        "sigma=7.5",
        "--sigma-min",
        "7",
        "--sigma-max",
        "8",
        "--out",
        str(out),
    ]
    assert main(argv + ["--no-switch"]) == 0
    rows = list(csv.DictReader(open(out / "branch.csv")))
    assert {
        "sigma",
        "A1",
        "max_abs_X",
        "max_abs_w",
        "stable",
        "max_abs_multiplier",
        "special",
        "branch",
    } <= set(rows[0])
    assert rows[0]["special"] == "END" and rows[-1]["special"] == "END"
    assert all(r["branch"] == "symmetric" and r["stable"] == "1" for r in rows)
    assert max(float(r["liouville_error"]) for r in rows) < 1e-8
    assert (out / "branch.png").stat().st_size > 10_000
    assert "start orbit at sigma = 7.5" in capsys.readouterr().err


def test_frc_in_abar_meets_the_frc_in_sigma_where_they_cross(tmp_path):
    # Two one-parameter runs of (46) through the same point (sigma = 1, Abar = 1.5, Fig. 13 set):
    # the Abar-branch at the preset's sigma, interpolated at Abar = 1.5, has the amplitude of the
    # sigma-branch at Abar = 1.5 interpolated at sigma = 1.
    assert (
        main(
            [
                "frc",
                "--preset",
                "fig13",
                "--parameter",
                "Abar",
                "--abar-min",
                "0.5",
                "--abar-max",
                "3",
                "--ds-max",
                "0.005",
                "--out",
                str(tmp_path / "a"),
            ]
        )
        == 0
    )
    assert (
        main(
            [
                "frc",
                "--preset",
                "fig13",
                "--set",
                "Abar=1.5",
                "--sigma-min",
                "0",
                "--sigma-max",
                "2",
                "--ds-max",
                "0.005",
                "--out",
                str(tmp_path / "s"),
            ]
        )
        == 0
    )
    by_abar = [r for r in csv.DictReader(open(tmp_path / "a" / "frc.csv"))]
    by_sigma = [r for r in csv.DictReader(open(tmp_path / "s" / "frc.csv"))]
    assert {float(r["sigma"]) for r in by_abar} == {1.0} and {float(r["Abar"]) for r in by_sigma} == {1.5}
    # the first row is Abar_b, on the manifold's end: (46) there in closed form (alpha = 1/(1 + rho^2))
    rho = float(restitution.rho(restitution.kappa_newtonian(0.35, 0.2, 50)))
    A, a, c = rho / np.sqrt(1 + rho**2), 1 / (1 + rho**2), 1 - 0.3**2
    abar_end = np.hypot(
        0.2 * np.pi**2 * A**2 + 8 * rho * a**2 * c, np.pi**2 * (1.0 - c) * A**2 - 8 * a * (1 - a) * c
    ) / (np.pi**2 * A)
    assert by_abar[0]["special"] == "END" and float(by_abar[0]["Abar"]) == pytest.approx(abar_end, rel=1e-10)

    def amplitude_at(rows, key, value):
        # stable points only: at sigma = 1, Abar = 1.5 the stable resonant state is unique
        pts = sorted((float(r[key]), float(r["A"])) for r in rows if r["stable"] == "1")
        k = np.searchsorted([p for p, _ in pts], value)
        (p0, a0), (p1, a1) = pts[k - 1], pts[k]
        return a0 + (a1 - a0) * (value - p0) / (p1 - p0)

    # linear interpolation over arclength steps of 0.005: error ~ 1e-5
    assert amplitude_at(by_abar, "Abar", 1.5) == pytest.approx(amplitude_at(by_sigma, "sigma", 1.0), rel=1e-4)


def test_continuation_controls_are_checked_and_old_spellings_still_work(tmp_path, capsys):
    assert main(["frc", "--preset", "fig10", "--ds", "0", "--out", str(tmp_path)]) == 2
    assert "--ds must be a positive finite arclength step" in capsys.readouterr().err
    assert main(["frc", "--preset", "fig10", "--max-steps", "0", "--out", str(tmp_path)]) == 2
    assert "--max-steps must be an integer >= 1" in capsys.readouterr().err
    assert main(["frc", "--preset", "fig10", "--out", str(tmp_path / "default")]) == 0
    assert (
        main(
            ["frc", "--preset", "fig10", "--ds", "0.01", "--ds-max", "0.02", "--out", str(tmp_path / "fine")]
        )
        == 0
    )
    default, fine = (list(csv.DictReader(open(tmp_path / name / "frc.csv"))) for name in ("default", "fine"))
    assert len(fine) > 2 * len(default)  # the steps are capped at 0.02 arclength
    assert [r["special"] for r in fine if r["special"]] == [r["special"] for r in default if r["special"]]
    argv = [
        "compare",
        "--preset",
        "fig10",
        "--set",
        "sigma=7.5",
        "--sigma-min",
        "7",
        "--sigma-max",
        "8",
        "--grid",
        "5",
        "--no-switch",
        "--out",
        str(tmp_path / "c"),
    ]
    assert main(argv) == 0
    assert "--grid is deprecated; use --sigma-points" in capsys.readouterr().err
    assert len(list(csv.DictReader(open(tmp_path / "c" / "compare.csv")))) == 5


def test_set_help_lists_the_parameter_names(capsys):
    with pytest.raises(SystemExit):
        main(["frc", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "names: eps, beta, gamma, sigma, Abar, lam, chi, n, pbar" in out


def test_shoot_in_abar_meets_the_shoot_in_sigma_where_they_cross(tmp_path):
    # Orbits of (9), Fig. 10 set at sigma = 7.5: the Abar-branch interpolated at Abar = 3.4 and the
    # sigma-branch at Abar = 3.4 interpolated at sigma = 7.5 are the same orbit.
    common = ["--preset", "fig10", "--set", "sigma=7.5", "--no-switch", "--ds-max", "0.01"]
    assert (
        main(
            [
                "shoot",
                *common,
                "--parameter",
                "Abar",
                "--abar-min",
                "2.8",
                "--abar-max",
                "3.5",
                "--out",
                str(tmp_path / "a"),
            ]
        )
        == 0
    )
    assert (
        main(
            [
                "shoot",
                *common,
                "--set",
                "Abar=3.4",
                "--sigma-min",
                "7.4",
                "--sigma-max",
                "7.6",
                "--out",
                str(tmp_path / "s"),
            ]
        )
        == 0
    )
    by_abar = list(csv.DictReader(open(tmp_path / "a" / "branch.csv")))
    by_sigma = list(csv.DictReader(open(tmp_path / "s" / "branch.csv")))
    assert {r["sigma"] for r in by_abar} == {"7.5"} and {r["Abar"] for r in by_sigma} == {"3.4"}
    a_vals, s_vals = (
        sorted((float(r[k]), float(r["A1"])) for r in rows)
        for rows, k in ((by_abar, "Abar"), (by_sigma, "sigma"))
    )
    A1_abar = np.interp(3.4, *zip(*a_vals))
    A1_sigma = np.interp(7.5, *zip(*s_vals))
    assert A1_abar == pytest.approx(A1_sigma, rel=1e-5)
    # started from the slow flow's states in Abar instead (no simulation): the same orbits
    in_abar = ["--parameter", "Abar", "--abar-min", "2.8", "--abar-max", "3.5", "--start", "slow-flow"]
    assert main(["shoot", *common, *in_abar, "--out", str(tmp_path / "x")]) == 0
    from_slow_flow = list(csv.DictReader(open(tmp_path / "x" / "branch.csv")))
    x_vals = sorted((float(r["Abar"]), float(r["A1"])) for r in from_slow_flow)
    assert np.interp(3.4, *zip(*x_vals)) == pytest.approx(A1_sigma, rel=1e-5)


def test_shoot_says_when_a_branch_is_cut_short(tmp_path, capsys):
    # Five steps cannot cover sigma in [7, 8]: the branch says so in branch.csv, on stderr and in
    # the exit status; never "ok".
    argv = [
        "shoot",
        "--preset",
        "fig10",
        "--set",
        "sigma=7.5",
        "--sigma-min",
        "7",
        "--sigma-max",
        "8",
        "--no-switch",
        "--max-steps",
        "3",
        "--ds-max",
        "0.02",
        "--out",
        str(tmp_path),
    ]
    assert main(argv) == 3
    err = capsys.readouterr().err
    assert "symmetric: step limit" in err and "cut short" in err and "exit status 3" in err
    rows = list(csv.DictReader(open(tmp_path / "branch.csv")))
    assert {r["status"] for r in rows} == {"step limit"}


def test_shoot_flags_orbits_that_fail_the_liouville_check(tmp_path, capsys):
    # At an integration tolerance of 1e-4 the monodromy is poor: Liouville's check says so for
    # some orbits, which are flagged row by row and announced once.
    argv = [
        "shoot",
        "--preset",
        "fig10",
        "--set",
        "sigma=7.5",
        "--sigma-min",
        "7.4",
        "--sigma-max",
        "7.6",
        "--no-switch",
        "--rtol",
        "1e-4",
        "--out",
        str(tmp_path),
    ]
    main(argv)
    rows = list(csv.DictReader(open(tmp_path / "branch.csv")))
    flagged = [r for r in rows if r["flag"] == "liouville"]
    assert flagged and all(float(r["liouville_error"]) > 1e-6 for r in flagged)
    assert all(float(r["liouville_error"]) <= 1e-6 for r in rows if not r["flag"])
    assert capsys.readouterr().err.count("fail Liouville's check") == 1


def test_chart_writes_curves_critical_and_png_and_checks_its_box(tmp_path, capsys, fold_chart):
    out = tmp_path / "chart"
    argv = [*fold_chart, "--out", str(out)]
    assert main(argv) == 0
    curves = list(csv.DictReader(open(out / "curves.csv")))
    assert set(curves[0]) >= {"curve", "kind", "sigma", "Abar", "A1", "max_abs_w", "codim2", "status"}
    assert {r["kind"] for r in curves} == {"LP"} and {r["status"] for r in curves} == {"ok"}
    assert all(-1.6 <= float(r["sigma"]) <= -1.2 and 2.6 <= float(r["Abar"]) <= 3.4 for r in curves)
    critical = list(csv.DictReader(open(out / "critical.csv")))
    assert list(critical[0]) == [
        "sigma",
        "Abar_b_slowflow",
        "Abar_c_full",
        "rel_diff",
        "bounded_by",
        "loss",
        "below_box",
    ]
    assert {r["loss"] for r in critical if r["bounded_by"] == "LP"} <= {"jump"}  # a fold is a jump
    assert (out / "chart.png").stat().st_size > 10_000
    assert main(argv[:9] + ["--abar-min", "3", "--abar-max", "2", "--out", str(out)]) == 2
    assert "need 0 <= --abar-min < --abar-max" in capsys.readouterr().err


def test_chart_in_sigma_and_another_parameter(tmp_path, capsys):
    # --second beta: the fold of the symmetric branch (Abar = 3) continued in (sigma, beta); the
    # CSV's second column is beta, there is no critical forcing, and a one-parameter run in sigma
    # at a curve point's beta finds the fold at the curve's sigma (the curves' own accuracy is
    # tested in tests/orbits/test_codim2.py).
    from slosh_bif import get_preset
    from slosh_bif.orbits import NO_SWITCHING, orbit_from_simulation, trace_orbits
    from slosh_bif.orbits.settings import ParameterRange

    out = tmp_path / "chart"
    box = [
        "--sigma-min",
        "-1.6",
        "--sigma-max",
        "-1.2",
        "--second",
        "beta",
        "--second-min",
        "0",
        "--second-max",
        "0.2",
    ]
    assert (
        main(
            [
                "chart",
                "--preset",
                "fig10",
                "--set",
                "sigma=-1.2",
                *box,
                "--no-switch",
                "--seeds",
                "0",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    rows = list(csv.DictReader(open(out / "curves.csv")))
    assert list(rows[0])[:4] == ["curve", "kind", "sigma", "beta"] and {r["kind"] for r in rows} == {"LP"}
    assert (
        max(float(r["beta"]) for r in rows) == pytest.approx(0.2, abs=0.02)
        and not (out / "critical.csv").exists()
    )
    row = rows[len(rows) // 2]
    P = get_preset("fig10").params.replace(beta=float(row["beta"]), sigma=-1.2)
    start = orbit_from_simulation(P, get_preset("fig10").state0, settle=150)
    (lp,) = (
        trace_orbits(
            start.params, start.y0, branching=NO_SWITCHING, interval=ParameterRange(lo=-1.6, hi=-1.2)
        )
        .branches[0]
        .branch.special_of("LP")
    )
    assert lp.p == pytest.approx(float(row["sigma"]), abs=1e-6)
    capsys.readouterr()
    for bad, says in [
        (["--second", "beta", "--second-min", "-0.1", "--second-max", "0.2"], "leaves the parameter's range"),
        (["--second", "beta"], "needs its range"),
        (
            ["--second", "eps", "--second-min", "0.01", "--second-max", "0.1", "--abar-min", "1"],
            "belong to the (sigma, Abar) chart",
        ),
        (["--second-min", "0.1"], "go with --second NAME other than Abar"),
    ]:
        assert main(["chart", "--preset", "fig10", *bad, "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert says in err and err.strip().count("\n") == 0, err
    assert (out / "curves.csv").exists()  # bad input destroyed nothing


def test_set_eps_recomputes_the_presets_initial_state(capsys):
    # The presets give the initial condition in absolute coordinates (u0, u0', v0, v0') =
    # (0, 3, -0.97, 0); X = u + eps v and w = u - v, so eps changes X but not w.
    assert main(["info", "--preset", "fig10", "--set", "eps=0.1", "--json"]) == 0
    state = json.loads(capsys.readouterr().out)["initial_state"]
    assert state == pytest.approx({"X": 0.1 * -0.97, "Xd": 3.0, "w": 0.97, "wd": 3.0}, abs=1e-15)


def test_no_forcing_is_free_decay(tmp_path, capsys):
    assert (
        main(["simulate", "--preset", "fig10", "--set", "Abar=0", "--tmax", "300", "--out", str(tmp_path)])
        == 0
    )
    assert "regime: free-decay" in capsys.readouterr().out


def test_compare_writes_csv_png_and_table(tmp_path, capsys):
    out = tmp_path / "cmp"
    argv = [
        "compare",
        "--preset",
        "fig10",
        "--set",
        "sigma=7.5",
        "--sigma-min",
        "7",
        "--sigma-max",
        "8",
        "--grid",
        "11",
        "--no-switch",
        "--out",
        str(out),
    ]
    assert main(argv) == 0
    text = (out / "compare.txt").read_text()
    assert "sigma range" in text and (out / "compare.png").is_file() and (out / "compare.csv").is_file()
    assert "how stability is lost:" in text


def test_compare_from_the_slow_flow_reports_the_nearest_stable_orbit_too(tmp_path, capsys):
    out = tmp_path / "cmp"
    argv = [
        "compare",
        "--preset",
        "fig13",
        "--start",
        "slow-flow",
        "--sigma-min",
        "1.5",
        "--sigma-max",
        "3",
        "--grid",
        "16",
        "--no-switch",
        "--out",
        str(out),
    ]
    assert main(argv) == 0
    assert "start orbit from the slow flow at sigma = " in capsys.readouterr().err
    rows = list(csv.DictReader(open(out / "compare.csv")))
    assert len(rows) == 16
    for r in rows:
        # The nearest stable orbit is one of the orbits: never nearer than the nearest of all.
        d, d_stable = float(r["relative_difference"]), float(r["relative_difference_stable_orbit"])
        assert np.isnan(d_stable) or d_stable >= d
        if r["shooting_stable"] == "1":
            assert d_stable == d
    assert (
        "stable slow-flow states with a stable 2pi-orbit of (9) within 5%"
        in (out / "compare.txt").read_text()
    )


def test_trust_writes_the_map_and_checks_its_input(tmp_path, capsys):
    out = tmp_path / "trust"
    argv = [
        "trust",
        "--preset",
        "fig13",
        "--eps",
        "0.05",
        "--beta",
        "0.3",
        "--n",
        "50,20",
        "--sigma-min",
        "1",
        "--sigma-max",
        "3",
        "--grid",
        "21",
        "--no-switch",
        "--impact",
        "--workers",
        "2",
        "--out",
        str(out),
    ]
    assert main(argv) == 0
    rows = list(csv.DictReader(open(out / "trust_map.csv")))
    assert [(r["n"], r["status"]) for r in rows] == [("50", "ok"), ("20", "ok")]
    for r in rows:
        assert 0 <= float(r["confirmed"]) <= float(r["agree"]) <= 1 and int(r["stable_states"]) > 0
        # the orbits of (8) beside (9)'s: the two errors apart on the states where both are stable
        assert r["impact_status"] == "ok" and 0 < int(r["impact_measured"]) <= int(r["stable_states"])
        for key in ("asymptotic", "wall"):
            assert 0 <= float(r[f"{key}_median"]) <= float(r[f"{key}_max"]) < 1
    # n = 20 loses more than half the energy per impact at these parameters: the warning fires.
    assert [r["warned"] for r in rows] == ["False", "True"]
    assert (out / "trust_map.png").stat().st_size > 10_000 and "confirmed %" in (
        out / "trust_map.txt"
    ).read_text()
    assert "(46) vs (8): median" in (out / "trust_map.txt").read_text()
    assert (
        main(["trust", "--preset", "fig13", "--eps", "0.05", "--beta", "0.3", "--n", "0", "--out", str(out)])
        == 2
    )
    assert "parameter n must be in integers >= 1; got 0" in capsys.readouterr().err
    odd = ["trust", "--preset", "fig10", "--set", "n=5", "--set", "pbar=3", "--set", "lam=0.1", "--n", "5,10"]
    assert main([*odd, "--out", str(out)]) == 2
    assert "--n 10: the wall exponent must have the parity of the set's pbar = 3" in capsys.readouterr().err


def test_trust_with_a_set_it_cannot_compare_exits_3(tmp_path, capsys):
    # eps = 2 and n = 50: the slow flow's stable states start no orbit of (9); the map says so.
    argv = ["trust", "--preset", "fig10", "--eps", "2", "--beta", "0", "--n", "50", "--grid", "11"]
    assert main([*argv, "--out", str(tmp_path)]) == 3
    rows = list(csv.DictReader(open(tmp_path / "trust_map.csv")))
    assert rows[0]["status"].startswith("no start")
    assert "1 of 1 parameter set(s) not compared" in capsys.readouterr().err


def test_trust_names_the_corrected_impact_model_and_needs_impact_for_it(tmp_path, capsys):
    from slosh_bif.studies.trust import TrustPoint
    from slosh_bif.studies.trust_output import trust_table

    point = TrustPoint(
        eps=0.05,
        beta=0.3,
        n=50,
        stable_states=30,
        agree=0.2,
        confirmed=0.1,
        median_difference=0.09,
        max_difference=0.2,
        warned=False,
        sigma_start=1.0,
        branches=3,
        seconds=1.0,
        status="ok",
        impact_measured=23,
        asymptotic_median=0.095,
        asymptotic_max=0.19,
        wall_median=0.0012,
        wall_max=0.013,
        impact_status="ok",
    )
    table = trust_table([point], impact_model="corrected")
    assert "(46) vs (C): median" in table and "(C) vs (9): median" in table and "0.12%" in table
    argv = ["trust", "--preset", "fig13", "--impact-model", "corrected", "--out", str(tmp_path)]
    assert main(argv) == 2 and "give --impact too" in capsys.readouterr().err


def test_shoot_without_an_orbit_near_the_guess_says_so(tmp_path, capsys):
    argv = [
        "shoot",
        "--preset",
        "fig10",
        "--guess",
        "50,0,0,0",
        "--settle",
        "1",
        "--sigma-min",
        "0",
        "--sigma-max",
        "2",
        "--out",
        str(tmp_path),
    ]
    assert main(argv) == 2
    assert "no periodic orbit found near --guess" in capsys.readouterr().err


def test_simulate_writes_trajectory_summary_and_figure(tmp_path, capsys):
    out = tmp_path / "sim"
    assert (
        main(["simulate", "--preset", "fig13", "--model", "impact", "--tmax", "150", "--out", str(out)]) == 0
    )
    data = np.load(out / "trajectory.npz")
    for key in ("tau", "X", "Xd", "w", "wd", "impact_t", "impact_v_minus", "impact_v_plus"):
        assert key in data
    assert data["impact_t"].size > 0 and data["tau"][-1] == pytest.approx(150)
    summary = json.loads((out / "summary.json").read_text())
    assert {"regime", "impacts_per_period", "envelope_min", "envelope_max"} <= set(summary)
    assert summary["model"] == "impact" and summary["noise"] is None
    assert (out / "simulate.png").stat().st_size > 10_000
    assert "regime:" in capsys.readouterr().out


def test_a_simulation_that_stops_early_writes_what_it_ran_and_exits_3(tmp_path, capsys):
    """(8) with pbar = 3 (a random draw): the restitution (21) is not real at an impact speed of 3.2
    reached at tau = 4.9. The run to there is written and drawn (the manifold's A_min from the set,
    the run too short to be judged), exit status 3: a partial result."""
    values = dict(eps=0.07, beta=0.015, gamma=0.13, Abar=2.42, lam=0.353, chi=1.1, n=3, pbar=3)
    settings = [a for name, value in values.items() for a in ("--set", f"{name}={value}")]
    out = tmp_path / "sim"
    assert main(["simulate", "--preset", "fig10", *settings, "--model", "impact", "--out", str(out)]) == 3
    err = capsys.readouterr().err
    assert "stopped early (exit status 3)" in err and "kappa (eq. 21) is not real" in err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["regime"] == "failed" and "too early to judge" in summary["reason"]
    tau = np.load(out / "trajectory.npz")["tau"]
    assert 0 < tau[-1] < 2 * np.pi
    assert (out / "simulate.png").stat().st_size > 10_000


def test_simulate_with_noise_records_the_seed_and_is_reproducible(tmp_path):
    runs = []
    for name in ("a", "b"):
        assert (
            main(
                [
                    "simulate",
                    "--preset",
                    "fig15",
                    "--tmax",
                    "60",
                    "--seed",
                    "7",
                    "--out",
                    str(tmp_path / name),
                ]
            )
            == 0
        )
        runs.append(np.load(tmp_path / name / "trajectory.npz")["X"])
    assert np.array_equal(runs[0], runs[1])
    noise = json.loads((tmp_path / "a" / "summary.json").read_text())["noise"]
    assert noise["std"] == 4.0 and noise["seed"] == 7 and noise["cutoff"] == 10.0


def test_simulate_reports_bad_input(tmp_path, capsys):
    assert (
        main(["simulate", "--preset", "fig10", "--model", "impact", "--noise", "1", "--out", str(tmp_path)])
        == 2
    )
    assert "smooth model only" in capsys.readouterr().err
    assert (
        main(["simulate", "--preset", "fig10", "--tmax", "100", "--transient", "200", "--out", str(tmp_path)])
        == 2
    )
    assert "--transient must be in [0, tmax - 4 pi = 87.4336)" in capsys.readouterr().err


def test_regimes_writes_map_csv_and_png(tmp_path, capsys):
    out = tmp_path / "map"
    argv = [
        "regimes",
        "--preset",
        "fig12",
        "--sigma-min",
        "0",
        "--sigma-max",
        "2",
        "--abar-min",
        "0.2",
        "--abar-max",
        "1.0",
    ]
    assert main(argv + ["--grid", "2", "2", "--tmax", "300", "--workers", "2", "--out", str(out)]) == 0
    rows = (out / "regimes.csv").read_text().splitlines()
    assert rows[0].startswith("sigma,Abar,regime") and len(rows) == 5
    assert (out / "regimes.png").stat().st_size > 10_000
    assert main(argv + ["--sigma-points", "0", "--abar-points", "2", "--out", str(out)]) == 2
    assert "--sigma-points and --abar-points take integers in [1, 2000]" in capsys.readouterr().err


def test_figures_writes_every_figure_quickly(tmp_path, capsys):
    from slosh_bif.studies.figures import FIGURES

    assert main(["figures", "--quick", "--out", str(tmp_path)]) == 0
    for name in FIGURES:
        assert (tmp_path / f"{name}.png").stat().st_size > 10_000, name
    assert len(FIGURES) == 13  # Figs. 3-15 (1 and 2 are sketches)
    assert "A_min = 0.0993" in capsys.readouterr().out  # the Fig. 6 note reaches the user
    assert main(["figures", "--only", "fig99", "--out", str(tmp_path)]) == 2


def test_negative_numbers_parse_as_option_values(tmp_path, capsys):
    """`--sigma-min -1e1` and `--guess -1,0,0,0` are values, not options (argparse alone refused
    both with "expected one argument")."""
    assert (
        main(["frc", "--preset", "fig10", "--sigma-min", "-1e1", "--sigma-max", "-5", "--out", str(tmp_path)])
        == 0
    )
    with open(tmp_path / "frc.csv", newline="") as fh:
        sigmas = [float(r["sigma"]) for r in csv.DictReader(fh)]
    assert min(sigmas) == pytest.approx(-10.0)
    assert (
        main(["shoot", "--preset", "fig10", "--guess", "-1,0,0,0", "--no-switch", "--out", str(tmp_path)])
        == 2
    )
    assert "near --guess" in capsys.readouterr().err


def test_shoot_with_the_scipy_backend_agrees_with_the_compiled_one(tmp_path):
    """--backend scipy (solve_ivp's DOP853, no compilation) traces the same branch as the
    compiled default: A1 against sigma to 1e-6 on the stable stretch below resonance."""
    curves = {}
    for backend in ("scipy", "auto"):
        out = tmp_path / backend
        assert (
            main(
                [
                    "shoot",
                    "--preset",
                    "fig10",
                    "--set",
                    "sigma=-6",
                    "--sigma-min",
                    "-6",
                    "--sigma-max",
                    "-5.5",
                    "--no-switch",
                    "--backend",
                    backend,
                    "--out",
                    str(out),
                ]
            )
            == 0
        )
        with open(out / "branch.csv", newline="") as fh:
            rows = list(csv.DictReader(fh))
        curves[backend] = (
            np.array([float(r["sigma"]) for r in rows]),
            np.array([float(r["A1"]) for r in rows]),
        )
    s, a = curves["auto"]
    order = np.argsort(curves["scipy"][0])
    np.testing.assert_allclose(
        np.interp(s, curves["scipy"][0][order], curves["scipy"][1][order]), a, rtol=1e-6
    )


@pytest.mark.slow  # a regime map twice (10 s); the scipy fallback of the simulation has its own fast tests
def test_regimes_with_the_scipy_backend_classify_as_the_compiled_one(tmp_path):
    """--backend on regimes: at sigma = 0.8, Abar = 3 (Fig. 10 set; a stable orbit there) scipy's
    DOP853 and the compiled one both settle on the periodic resonant response, with the same
    impacts per period to 2 %. (Cells still in a transient at tau = 600 can differ: the two
    integrators' step sequences differ, and a chaotic transient amplifies that.)"""
    rows = {}
    for backend in ("scipy", "numba"):
        out = tmp_path / backend
        argv = [
            "regimes",
            "--preset",
            "fig10",
            "--sigma-min",
            "0.8",
            "--sigma-max",
            "1",
            "--sigma-points",
            "1",
            "--abar-min",
            "3",
            "--abar-max",
            "4",
        ]
        assert (
            main(argv + ["--abar-points", "1", "--workers", "1", "--backend", backend, "--out", str(out)])
            == 0
        )
        with open(out / "regimes.csv", newline="") as fh:
            (rows[backend],) = list(csv.DictReader(fh))
    assert rows["scipy"]["regime"] == rows["numba"]["regime"] == "periodic-resonant"
    assert float(rows["scipy"]["impacts_per_period"]) == pytest.approx(
        float(rows["numba"]["impacts_per_period"]), rel=0.02
    )


@pytest.mark.parametrize(
    "extra, says",
    [
        (["--tmax", "1e9"], "more than the 2e+07 allowed"),  # 5e10 samples kept in memory
        (["--noise", "0.1", "--noise-cutoff", "1e6"], "lower the cutoff"),  # a 3e9-sample noise table
    ],
)
def test_runs_too_large_for_memory_are_one_line_errors_before_any_work(tmp_path, capsys, extra, says):
    out = tmp_path / "sim"
    assert main(["simulate", "--preset", "fig10", *extra, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert says in err and err.count("\n") == 1 and not out.exists()


def test_an_output_folder_that_is_a_file_is_a_one_line_error(tmp_path, capsys):
    path = tmp_path / "a-file"
    path.write_text("x")
    for out in (path, path / "below"):
        assert main(["simulate", "--preset", "fig10", "--tmax", "10", "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert "is a file" in err and err.count("\n") == 1


def test_chart_resume_reuses_the_stored_curves_and_checks_the_settings(tmp_path, capsys):
    out = tmp_path / "chart"
    argv = [
        "chart",
        "--preset",
        "fig10",
        "--set",
        "sigma=-1.2",
        "--sigma-min",
        "-1.6",
        "--sigma-max",
        "-0.9",
        "--abar-min",
        "2.8",
        "--abar-max",
        "3.2",
        "--no-switch",
        "--seeds",
        "0",
    ]
    assert main(argv + ["--out", str(out)]) == 0
    first = (out / "curves.csv").read_text()
    assert sorted(p.name for p in (out / "curves").iterdir())[-1] == "settings.json"
    capsys.readouterr()
    assert main(argv + ["--resume", "--out", str(out)]) == 0
    assert "curves from an earlier run" in capsys.readouterr().err
    assert (out / "curves.csv").read_text() == first  # the stored curves, bit for bit
    assert main(argv[:-2] + ["--seeds", "1", "--resume", "--out", str(out)]) == 2
    assert "seeds differ" in capsys.readouterr().err


def test_trust_resume_reuses_the_stored_sets(tmp_path, capsys):
    out = tmp_path / "trust"
    argv = [
        "trust",
        "--preset",
        "fig10",
        "--sigma-min",
        "-6",
        "--sigma-max",
        "-5",
        "--sigma-points",
        "11",
        "--eps",
        "0.05",
        "--beta",
        "0",
        "--n",
        "20,50",
        "--no-switch",
        "--workers",
        "1",
    ]
    assert main(argv + ["--out", str(out)]) == 0
    first = (out / "trust_map.csv").read_text()
    capsys.readouterr()
    assert main(argv + ["--resume", "--out", str(out)]) == 0
    assert "resuming: 2 parameter sets" in capsys.readouterr().err
    assert (out / "trust_map.csv").read_text() == first
    assert (
        main(argv[:-5] + ["--n", "20", "--no-switch", "--workers", "1", "--resume", "--out", str(out)]) == 2
    )
    assert "n differ" in capsys.readouterr().err


def test_basins_writes_csv_attractors_and_png(tmp_path, capsys):
    out = tmp_path / "basins"
    assert (
        main(
            [
                "basins",
                "--preset",
                "fig10",
                "--set",
                "sigma=3",
                "--grid",
                "2",
                "2",
                "--tmax",
                "100",
                "--workers",
                "1",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    assert "4 of 4 initial states simulated" in capsys.readouterr().err  # the last count, however fast
    rows = list(csv.DictReader(open(out / "basins.csv")))
    assert len(rows) == 4 and set(rows[0]) == {"X", "w", "attractor", "uncertain", "periods_to_settle"}
    assert all(
        r["attractor"].endswith("(not settled)") and r["periods_to_settle"] == "nan" for r in rows
    )  # 16 periods: too few to settle
    assert (
        "basins at sigma = 3" in (out / "attractors.txt").read_text()
        and (out / "basins.png").stat().st_size > 10_000
    )
    assert main(["basins", "--preset", "fig10", "--range1", "1", "1", "--out", str(out)]) == 2
    assert "--range1 needs finite LO < HI" in capsys.readouterr().err


def test_quiet_and_verbose(tmp_path, capsys):
    assert (
        main(
            [
                "shoot",
                "--preset",
                "fig10",
                "--no-switch",
                "--sigma-min",
                "4",
                "--sigma-max",
                "5",
                "-q",
                "--out",
                str(tmp_path / "q"),
            ]
        )
        == 0
    )
    quiet = capsys.readouterr()
    assert quiet.err == "" and "special: " in quiet.out
    assert (
        main(
            [
                "shoot",
                "--preset",
                "fig10",
                "--no-switch",
                "--sigma-min",
                "4",
                "--sigma-max",
                "5",
                "-v",
                "--out",
                str(tmp_path / "v"),
            ]
        )
        == 0
    )
    loud = capsys.readouterr()
    assert "point 2," in loud.err and "BP 4.4" not in quiet.out and "END 4," in loud.out


def test_a_warning_says_where_it_comes_from():
    from slosh_bif.cli import warning_origin

    assert (
        warning_origin(RuntimeWarning, "/site/slosh_bif/orbits/shooting.py", 263)
        == " (RuntimeWarning at slosh_bif/orbits/shooting.py:263)"
    )
    assert warning_origin(UserWarning, "/site/slosh_bif/slowflow/flow.py", 10) == ""
