"""The chart as a user runs it: every special point of the Fig. 10 family gives its curve, a
start that cannot is a failure (exit 3, a row in curves.csv), and what is computed depends on
counts only, not on the worker count or the machine's load."""

import csv
import dataclasses
import subprocess
import sys

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.cli import main
from slosh_bif.slowflow.flow import SlowFlow
from slosh_bif.slowflow.steady_states import abar_on_curve
from slosh_bif.studies.chart import Chart, CurveFailure
from slosh_bif.studies.chart.critical import critical_rows
from slosh_bif.studies.chart.output import curve_rows
from slosh_bif.studies.chart.reading import seed_disagreements
from slosh_bif.studies.design import Study, StudyValue, study_rows

FIG10_NO_SWITCH = [
    "chart",
    "--preset",
    "fig10",
    "--sigma-min",
    "-6",
    "--sigma-max",
    "8",
    "--abar-min",
    "0.2",
    "--abar-max",
    "6",
    "--no-switch",
]


def _rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


# the Fig. 10 chart without switching (about a minute); the (sigma, beta) chart below is the fast check
@pytest.mark.slow
def test_the_fig10_chart_draws_a_curve_from_every_start(tmp_path, capsys):
    code = main([*FIG10_NO_SWITCH, "--out", str(tmp_path)])
    err = capsys.readouterr().err
    rows = _rows(tmp_path / "curves.csv")
    assert code == 0, err
    assert {r["status"] for r in rows} == {"ok"} and "no " not in err.replace("no steady", "")
    kinds = {r["kind"] for r in rows}
    assert {
        "LP",
        "NS",
        "BP",
    } <= kinds  # the fold curves are back (lost when a failed arc raised in the corrector)
    # Abar_b of (46) in critical.csv at each sigma: the least Abar over S+, so at most the least of a
    # dense sampling of S+, and within the sampling's own error of it (a chord of the traced curve
    # between its points lay 2e-3 above)
    flow_rows = [r for r in _rows(tmp_path / "critical.csv") if r["Abar_b_slowflow"] not in ("", "nan")]
    P = get_preset("fig10").params
    for r in flow_rows[::8]:
        flow = SlowFlow(P.replace(sigma=float(r["sigma"])))
        A = np.geomspace(flow.A_min * (1 + 1e-12), 50.0, 200_001)
        dense = np.nanmin(abar_on_curve(flow, A))
        assert dense * (1 - 1e-5) <= float(r["Abar_b_slowflow"]) <= dense * (1 + 1e-12)


def test_a_start_without_a_curve_is_a_failure_row():
    chart = Chart(
        params=get_preset("fig10").params,
        sigma_range=(-1, 1),
        abar_range=(0, 1),
        family=None,
        curves=[],
        slow_flow_critical=None,
        seconds=0.0,
        failures=(CurveFailure("LP", -0.5, 0.7, "LP at sigma = -0.5", "Newton failed"),),
    )
    (row,) = curve_rows(chart)
    assert row["kind"] == "LP" and row["status"] == "failed to start: Newton failed" and row["sigma"] == -0.5
    assert chart.incomplete == ["no LP curve from LP at sigma = -0.5: Newton failed"]


def test_a_chart_stopped_part_way_reads_no_critical_forcing():
    """Off part of the curves the lowest boundary may be a higher curve's: a stopped chart gives
    no Abar_c rows (the command writes no critical.csv), and a study shows it as one row with its
    status."""
    stopped = Chart(
        params=get_preset("fig10").params,
        sigma_range=(-1, 1),
        abar_range=(0.2, 1),
        family=None,
        curves=[],
        slow_flow_critical=None,
        seconds=0.0,
        status="interrupted (SIGINT) after 0 curves, 3 starts",
    )
    assert list(critical_rows(stopped)) == [] and seed_disagreements(stopped) == []
    assert len(list(critical_rows(dataclasses.replace(stopped, status="complete"), 5))) == 5
    study = Study("beta", (StudyValue(0.2, stopped, stopped.status),), (-1, 1), (0.2, 1))
    (row,) = study_rows(study)
    assert row["status"] == stopped.status and np.isnan(row["Abar_c_full"])


@pytest.mark.slow  # 17 s; the chart command's other tests keep it in the default run
def test_the_curves_do_not_depend_on_workers_or_load(tmp_path, beta_chart):
    assert main([*beta_chart, "--workers", "1", "--out", str(tmp_path / "one")]) == 0
    burners = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(2)]
    try:
        assert main([*beta_chart, "--workers", "2", "--out", str(tmp_path / "two")]) == 0
    finally:
        for b in burners:
            b.kill()
    one, two = (tmp_path / name / "curves.csv" for name in ("one", "two"))
    assert one.read_text() == two.read_text()
    rows = _rows(one)
    # every start gives its curve, the fold curves included (they were lost once, silently)
    assert {r["status"] for r in rows} == {"ok"} and {"LP", "NS", "BP"} <= {r["kind"] for r in rows}


REGIMES = ["--regimes", "3", "2", "--tmax", "60"]


def test_a_regime_map_shares_the_workers_with_the_curves_and_changes_no_file(
    tmp_path, monkeypatch, fold_chart
):
    """On two workers the --regimes map's cells are submitted before the first curve (they run
    while this process traces the orbit family) to the same two processes; every file, the
    picture with the map included, is the one-worker run's, byte for byte."""
    from slosh_bif.simulation import sweep

    submitted, pools = [], []

    class Recording(sweep.WorkerPool):
        def __init__(self, max_workers=None):
            super().__init__(max_workers)
            pools.append(self)

        def submit(self, function, *arguments):
            submitted.append(function.__name__)
            return super().submit(function, *arguments)

    monkeypatch.setattr(sweep, "WorkerPool", Recording)
    assert main([*fold_chart, *REGIMES, "--workers", "1", "--out", str(tmp_path / "one")]) == 0
    assert [p.threads for p in pools] == [1]  # the map's own process, after the curves
    assert main([*fold_chart, *REGIMES, "--workers", "2", "--out", str(tmp_path / "two")]) == 0
    assert [p.threads for p in pools] == [1, 2]  # one pool of two, shared by the map and the curves
    cells = [name for name in submitted if "classify" in name]
    assert len(cells) == 6 and submitted[:6] == cells and len(submitted) > 6  # the map first, then curves
    for name in ("curves.csv", "critical.csv", "codim2.csv", "chart.png"):
        assert (tmp_path / "one" / name).read_bytes() == (tmp_path / "two" / name).read_bytes(), name
