"""The slosh-bif command line."""

import json

import pytest

from slosh_bif import restitution
from slosh_bif.cli import main


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
