"""The wall fitted to impact records by eq. (21): exact recovery without noise, 95 % intervals
that hold in about 95 % of seeded noisy repetitions, the lam-chi combination named as the only
thing the records determine, and bad data refused in one line naming the file and the line."""

import json

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.cli import main
from slosh_bif.identify import ImpactRecords, fit_wall, read_impact_records
from slosh_bif.model import restitution
from slosh_bif.model.parameter_file import read_parameter_file

BASE = get_preset("fig13").params  # n = 50
TRUE = dict(lam=0.35, chi=0.2, n=50, pbar=2)
SPEEDS = np.linspace(0.2, 3.0, 25)


def _records(noise=0.0, seed=0, std=True):
    kappa = restitution.kappa(SPEEDS, **TRUE)
    v_out = (
        kappa * SPEEDS + np.random.default_rng(seed).normal(0.0, noise, SPEEDS.size)
        if noise
        else kappa * SPEEDS
    )
    return ImpactRecords(SPEEDS.copy(), v_out, np.full(SPEEDS.size, noise) if (noise and std) else None)


def test_exact_records_give_back_the_wall():
    fit = fit_wall(_records(), BASE.replace(chi=TRUE["chi"], pbar=0), ["lam", "pbar"])
    assert fit.values["pbar"] == 2 and fit.values["n"] == 50
    assert fit.estimate["lam"]["value"] == pytest.approx(TRUE["lam"], rel=1e-9)
    assert fit.C == pytest.approx(restitution.dissipation_at_unit_speed(**TRUE), rel=1e-9)
    assert min(fit.profile, key=fit.profile.get) == 2 and fit.profile[4] > 1e3 * fit.profile[2] + 1e-20
    assert sorted(fit.profile) == list(range(0, 13, 2))  # pbar = 2p - n has the parity of n = 50
    chi_only = fit_wall(_records(), BASE.replace(lam=TRUE["lam"], pbar=2), ["chi"])
    assert chi_only.estimate["chi"]["value"] == pytest.approx(TRUE["chi"], rel=1e-9)


def test_lam_and_chi_together_are_reported_as_their_one_combination():
    fit = fit_wall(_records(), BASE.replace(chi=0.5, pbar=2), ["lam", "chi"])
    a = 2 / 51 / 2 + 0.5
    assert "only as lam * chi^(-" in fit.not_identifiable and "contact time" in fit.not_identifiable
    assert fit.values["lam"] * fit.values["chi"] ** (-a) == pytest.approx(
        TRUE["lam"] * TRUE["chi"] ** (-a), rel=1e-9
    )
    assert fit.values["chi"] == 0.5  # kept, as stated


def test_the_95_percent_intervals_cover_the_truth_in_about_95_percent_of_repetitions():
    inside = 0
    for seed in range(60):
        fit = fit_wall(_records(noise=0.01, seed=seed), BASE.replace(chi=TRUE["chi"], pbar=2), ["lam"])
        low, high = fit.estimate["lam"]["interval_95"]
        inside += low <= TRUE["lam"] <= high
    assert 0.85 <= inside / 60 <= 1.0
    unweighted = [
        fit_wall(_records(noise=0.01, seed=s, std=False), BASE.replace(chi=TRUE["chi"], pbar=2), ["lam"])
        for s in range(60)
    ]
    covered = np.mean(
        [
            f.estimate["lam"]["interval_95"][0] <= TRUE["lam"] <= f.estimate["lam"]["interval_95"][1]
            for f in unweighted
        ]
    )
    assert 0.85 <= covered <= 1.0  # the residuals' own scale (Student's t)


def test_an_exponent_the_records_cannot_fix_is_said_to_be_undetermined():
    # 1 % noise on speeds 0.2-3 cannot tell q = 2/51 from 4/51: both pbar fit within 95 %
    fit = fit_wall(_records(noise=0.01, seed=1), BASE.replace(chi=TRUE["chi"], pbar=0), ["lam", "pbar"])
    assert 2 in fit.estimate["pbar"]["consistent_95"] and len(fit.estimate["pbar"]["consistent_95"]) > 1
    assert "pbar is not determined" in fit.not_identifiable
    exact = fit_wall(_records(noise=1e-4, seed=1), BASE.replace(chi=TRUE["chi"], pbar=0), ["lam", "pbar"])
    assert exact.estimate["pbar"]["consistent_95"] == [2] and "pbar" not in exact.not_identifiable


def test_fit_command_writes_the_estimates_and_a_parameter_file(tmp_path):
    records = _records(noise=0.001, seed=1)
    data = tmp_path / "impacts.csv"
    data.write_text(
        "v0,v_out,std\n"
        + "".join(f"{a:.17g},{b:.17g},{c:.17g}\n" for a, b, c in zip(records.v0, records.v_out, records.std))
    )
    assert (
        main(
            [
                "fit",
                "--data",
                str(data),
                "--preset",
                "fig13",
                "--set",
                "chi=0.2",
                "--free",
                "lam,pbar",
                "--out",
                str(tmp_path / "fit"),
            ]
        )
        == 0
    )
    record = json.loads((tmp_path / "fit" / "fit.json").read_text())
    assert record["values"]["pbar"] == 2 and len(record["data"]["sha256"]) == 64
    low, high = record["estimate"]["lam"]["interval_95"]
    assert low < TRUE["lam"] < high
    fitted = read_parameter_file(tmp_path / "fit" / "params.toml").params
    assert (
        fitted.lam == pytest.approx(record["values"]["lam"])
        and fitted.pbar == 2
        and fitted.sigma == BASE.sigma
    )
    assert (tmp_path / "fit" / "fit.png").stat().st_size > 5_000


@pytest.mark.parametrize(
    "text, message",
    [
        ("v0,out\n1,0.5\n", r"impacts.csv: needs the columns v0 and v_out .* missing v_out"),
        ("v0,v_out\n1,0.5\n2,abc\n3,1\n", r"impacts.csv, line 3: v_out must be a number; got 'abc'"),
        (
            "v0,v_out\n1,0.5\n2,2.5\n3,1\n",
            r"impacts.csv, line 3: the outgoing speed 2.5 exceeds the incoming 2",
        ),
        ("v0,v_out\n1,0.5\n2,-1\n3,1\n", r"impacts.csv, line 3: v_out must be a positive finite number"),
        ("v0,v_out\n1,0.5\n2,1\n", r"impacts.csv: 2 impact records; the fit needs at least 3"),
    ],
)
def test_bad_records_are_refused_in_one_line(tmp_path, text, message):
    path = tmp_path / "impacts.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=message):
        read_impact_records(path)


def test_bad_free_names_are_refused_before_any_work(tmp_path, capsys):
    data = tmp_path / "impacts.csv"
    data.write_text("v0,v_out\n1,0.5\n2,0.9\n3,1.2\n")
    assert (
        main(
            ["fit", "--data", str(data), "--preset", "fig13", "--free", "lam,n", "--out", str(tmp_path / "o")]
        )
        == 2
    )
    assert "--free takes a comma-separated subset of lam, chi, pbar" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()
