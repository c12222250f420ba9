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
    assert [r["loss"] for r in mine] == [r["loss"] for r in single]
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
