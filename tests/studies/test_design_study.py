"""``slosh-bif study --vary``: one chart per value of a third parameter. Each value's rows are
those of a chart run on its own at that value (the parameter really varied), a value outside
the admissible set is recorded with its reason, and bad requests fail before any work."""

import csv

import pytest

from slosh_bif.cli import main
from slosh_bif.studies.design import parse_vary

BOX = ["--sigma-min", "-1.6", "--sigma-max", "-1.2", "--abar-min", "2.6", "--abar-max", "3.4", "--seeds", "0"]


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_each_values_rows_are_its_own_charts_and_a_bad_value_is_recorded(tmp_path, capsys):
    out = tmp_path / "study"
    argv = ["study", "--preset", "fig10", "--set", "sigma=-1.2", "--vary", "beta=0:0.2:2", *BOX]
    assert main([*argv, "--out", str(out)]) == 0
    rows = _rows(out / "study.csv")
    assert {r["value"] for r in rows} == {"0", "0.2"} and (out / "study.png").stat().st_size > 10_000
    alone = tmp_path / "chart"
    chart = ["chart", "--preset", "fig10", "--set", "sigma=-1.2", "--set", "beta=0.2", *BOX, "--no-switch"]
    assert main([*chart, "--out", str(alone)]) == 0
    single = _rows(alone / "critical.csv")
    mine = [r for r in rows if r["value"] == "0.2"]
    assert [r["Abar_c_full"] for r in mine] == [r["Abar_c_full"] for r in single]
    assert [(r["loss"], r["below_box"]) for r in mine] == [(r["loss"], r["below_box"]) for r in single]
    assert {r["loss"] for r in mine if r["bounded_by"] == "LP"} == {"jump"}  # a fold is a jump
    differ = [
        a["Abar_c_full"] != b["Abar_c_full"] for a, b in zip(mine, (r for r in rows if r["value"] == "0"))
    ]
    assert any(differ)  # beta moved the critical forcing
    capsys.readouterr()
    bad = ["study", "--preset", "fig10", "--set", "sigma=-1.2", "--vary", "eps=-0.1:0.05:2", *BOX]
    assert main([*bad, "--out", str(tmp_path / "bad")]) == 3
    first = _rows(tmp_path / "bad" / "study.csv")[0]
    assert first["status"].startswith("not charted: parameter eps must be in (0, inf)")


@pytest.mark.parametrize(
    "text, message",
    [
        ("beta=0:0.2", "NAME=LO:HI:COUNT"),
        ("Abar=0:1:3", "sigma and Abar are the chart's axes"),
        ("beta=0.3:0.1:3", "need finite LO < HI and COUNT >= 2"),
        ("beta=a:1:3", "two numbers and an integer"),
    ],
)
def test_bad_requests_are_refused_in_one_line(text, message):
    with pytest.raises(ValueError, match=message):
        parse_vary(text)


TANK = ["--shape", "cylinder", "--radius", "5", "--structure-mass", "2e6", "--structure-frequency", "0.8"]
TANK += ["--excitation-frequency", "0.72", "--ground-acceleration", "0.5", "--clearance", "1"]
TANK_BOX = ["--set", "sigma=-0.2", "--set", "Abar=2", "--sigma-min", "-0.6", "--sigma-max", "0"]
TANK_BOX += ["--abar-min", "1.6", "--abar-max", "2.4", "--seeds", "0"]  # a fold curve at 4 m


def test_a_study_over_a_tanks_fill_depth_charts_the_tank_converted_at_each_depth(tmp_path, capsys):
    """Each depth's rows are those of a chart of the tank file written by ``slosh-bif tank`` at that
    depth (the conversion done again, independently of the study); a depth above the tank's height
    is recorded with the tank's own reason."""
    files = {}
    for depth in ("2", "4"):
        files[depth] = tmp_path / f"tank-{depth}.toml"
        assert main(["tank", *TANK, "--height", "5", "--depth", depth, "--out", str(files[depth])]) == 0
    out = tmp_path / "study"
    argv = ["study", "--params", str(files["2"]), "--vary", "depth=2:6:3", *TANK_BOX, "--out", str(out)]
    assert main(argv) == 3  # 6 m does not fit a 5 m tank
    rows = _rows(out / "study.csv")
    assert {r["value"] for r in rows} == {"2", "4", "6"}
    assert [r["status"] for r in rows if r["value"] == "6"] == [
        "not charted: depth 6 m exceeds the tank's height 5 m"
    ]
    alone = tmp_path / "chart"
    assert main(["chart", "--params", str(files["4"]), *TANK_BOX, "--no-switch", "--out", str(alone)]) == 0
    single = _rows(alone / "critical.csv")
    mine = [r for r in rows if r["value"] == "4"]
    # the same curves to the corrector's tolerance (each chart's simulations start from the
    # preset's initial state in the scaling of its own eps, as the chart's do)
    assert [float(r["Abar_c_full"]) for r in mine] == pytest.approx(
        [float(r["Abar_c_full"]) for r in single], rel=1e-8, nan_ok=True
    )
    assert "LP" in {r["bounded_by"] for r in mine}
    assert any(
        a["Abar_c_full"] != b["Abar_c_full"] for a, b in zip(mine, (r for r in rows if r["value"] == "2"))
    )
    capsys.readouterr()
    # a tank's quantity needs a tank file
    assert (
        main(["study", "--preset", "fig10", "--vary", "depth=2:4:2", *TANK_BOX, "--out", str(tmp_path / "x")])
        == 2
    )
    assert "with --params of a [tank] file" in capsys.readouterr().err


def test_the_least_critical_forcing_below_the_box_is_not_read_as_the_lowest_inside_it():
    """Where stable orbits reach the box's bottom at some sigma, the least Abar_c lies below the
    box: the study's lowest point is the box's bottom, flagged, not the least value read inside."""
    from slosh_bif.studies.design import least_critical

    inside = [
        dict(sigma=-1.0, Abar_c_full=0.4, below_box=0),
        dict(sigma=0.0, Abar_c_full=0.3, below_box=0),
        dict(sigma=1.0, Abar_c_full=0.5, below_box=0),
    ]
    assert least_critical(inside, 0.2) == (0.3, 0.0, False)
    reaching = [dict(sigma=-2.0, Abar_c_full=float("nan"), below_box=1), *inside]
    value, sigma, below = least_critical(reaching, 0.2)
    assert (value, below) == (0.2, True) and sigma != sigma


IMPACT_BOX = [
    "--sigma-min",
    "0.5",
    "--sigma-max",
    "1.5",
    "--abar-min",
    "0.5",
    "--abar-max",
    "1.2",
    "--seeds",
    "1",
]


@pytest.mark.slow  # 8-28 s; the file's other tests keep the capability in the default run
def test_an_impact_models_study_is_its_charts_and_resumes_from_its_stored_curves(tmp_path, capsys):
    """``--model impact``: each value's rows are those of ``chart --model impact`` run on its own
    at that value (the same orbits of (8), read the same way); a value whose stored curves were
    lost is traced again on ``--resume`` and the other reuses its own, the file unchanged (and a
    chart of (8) resumes from its stored curves)."""
    out = tmp_path / "study"
    argv = ["study", "--preset", "fig13", "--model", "impact", "--vary", "beta=0.1:0.3:2", *IMPACT_BOX]
    assert main([*argv, "--out", str(out)]) == 0
    rows = _rows(out / "study.csv")
    alone = tmp_path / "chart"
    chart = ["chart", "--preset", "fig13", "--model", "impact", "--set", "beta=0.1", *IMPACT_BOX]
    assert main([*chart, "--out", str(alone)]) == 0
    single = _rows(alone / "critical.csv")
    capsys.readouterr()
    assert main([*chart, "--out", str(alone), "--resume", "-v"]) == 0  # the chart resumes too
    assert "1 curves from an earlier run" in capsys.readouterr().err
    assert _rows(alone / "critical.csv") == single
    mine = [r for r in rows if r["value"] == "0.1"]
    assert [(r["Abar_c_full"], r["bounded_by"], r["loss"]) for r in mine] == [
        (r["Abar_c_full"], r["bounded_by"], r["loss"]) for r in single
    ]
    assert {(r["bounded_by"], r["loss"]) for r in mine} == {("NS", "soft")}
    assert any(
        a["Abar_c_full"] != b["Abar_c_full"] for a, b in zip(mine, (r for r in rows if r["value"] == "0.3"))
    )
    first = (out / "study.csv").read_bytes()
    stored = sorted((out / "value-000" / "curves").glob("curve-*.npz"))
    assert stored and sorted((out / "value-001" / "curves").glob("curve-*.npz"))
    stored[0].unlink()
    capsys.readouterr()
    assert main([*argv, "--out", str(out), "--resume", "-v"]) == 0
    said = capsys.readouterr().err  # the progress
    before, after = said.split("beta = 0.3: chart")
    assert f"beta = 0.1: {len(stored) - 1} curves from an earlier run" in before or (
        len(stored) == 1 and "curves from an earlier run" not in before
    )
    assert "beta = 0.3: 1 curves from an earlier run" in after
    assert (out / "study.csv").read_bytes() == first
    assert stored[0].exists()  # traced again and stored
    # values whose vessel has no restoring force at the start (eps sigma >= 1): recorded, not failed
    limp = ["study", "--preset", "fig13", "--model", "impact", "--vary", "eps=1.1:1.2:2", *IMPACT_BOX]
    assert main([*limp, "--out", str(tmp_path / "limp")]) == 3
    assert {r["status"].split(":")[0] for r in _rows(tmp_path / "limp" / "study.csv")} == {"not charted"}
    assert "the vessel's stiffness" in _rows(tmp_path / "limp" / "study.csv")[1]["status"]
