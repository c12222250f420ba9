"""``shoot --start scan``: every family found once (issue 17). Checked against patient starts:
Newton from simulations out of many random states at many sigma (a different, denser set of
starts than the scan's) lands only on branches the scan traced, and no two traced branches are
the same curve or mirror images of each other."""

import csv

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.cli import main
from slosh_bif.flows.smooth.integrator import integrate_grid
from slosh_bif.orbits import ShootingProblem, on_traced_branch, orbit_at, scan_families
from slosh_bif.orbits.settings import ParameterRange

N6 = get_preset("fig13").params.replace(n=6)  # the Fig. 13 set at n = 6: Abar = 1, several families


@pytest.fixture(scope="module", params=[0.3, 0.0], ids=["beta=0.3", "beta=0"])
def scanned(request):
    P = N6.replace(beta=request.param)
    return P, scan_families(P, get_preset("fig13").state_for(P), interval=ParameterRange(lo=-6.0, hi=8.0))


def test_patient_starts_land_only_on_scanned_branches(scanned):
    P, family = scanned
    rng = np.random.default_rng(2026)
    landed = 0
    for sigma in np.linspace(-5.5, 7.5, 9):
        at = P.replace(sigma=float(sigma))
        problem = ShootingProblem(at)
        for _ in range(4):
            y = integrate_grid(at, rng.uniform([-3, -3, -1, -3], [3, 3, 1, 3]), [0.0, 2 * np.pi * 200])[-1]
            orbit = orbit_at(problem, problem.initial_states(y), float(sigma), tol=1e-9)
            if orbit.converged:
                landed += 1
                assert on_traced_branch(at, orbit.y0, family.branches) is not None, (sigma, orbit.y0)
    assert landed >= 18


def test_no_branch_is_traced_twice(scanned):
    """The middle point of each 2pi-branch lies on no other branch, nor on another's mirror image."""
    P, family = scanned
    names = [ob.name for ob in family.branches]
    assert len(set(names)) == len(names)
    period_one = [ob for ob in family.branches if ob.problem.period_multiple == 1]
    for ob in period_one:
        i = len(ob) // 2
        others = [o for o in period_one if o is not ob]
        assert on_traced_branch(P.replace(sigma=float(ob.branch.p[i])), ob.branch.x[i, :4], others) is None, (
            ob.name
        )


def test_the_scan_finds_an_isola_the_default_start_misses(scanned):
    P, family = scanned
    kinds = {ob.kind for ob in family.branches}
    assert {"symmetric", "asymmetric"} <= kinds
    isolas = [ob for ob in family.branches if ob.closed and not ob.origin]
    assert isolas and all(ob.branch.status == "ok" for ob in family.branches)


def test_shoot_scan_writes_families_csv_with_unique_names(tmp_path, capsys):
    out = tmp_path / "scan"
    code = main(["shoot", "--preset", "fig13", "--set", "n=6", "--start", "scan", "--out", str(out)])
    assert code == 0
    with open(out / "families.csv", newline="") as fh:
        families = list(csv.DictReader(fh))
    assert list(families[0]) == [
        "family",
        "kind",
        "sigma_min",
        "sigma_max",
        "closed",
        "found_from",
        "points",
        "status",
    ]
    names = [f["family"] for f in families]
    assert len(set(names)) == len(names) >= 3
    with open(out / "branch.csv", newline="") as fh:
        assert {r["branch"] for r in csv.DictReader(fh)} == set(names)
    assert all(f["found_from"] for f in families)
    with open(out / "tasks.csv", newline="") as fh:  # what the scan ran, each with its duration
        tasks = list(csv.DictReader(fh))
    assert {t["kind"] for t in tasks} == {"start", "family"}
    started = {f["found_from"] for f in families if f["found_from"].startswith("Newton")}  # not switched
    assert started and started <= {t["origin"] for t in tasks if t["kind"] == "family"}
    assert all(float(t["seconds"]) > 0 for t in tasks)
    assert "scan tasks" in capsys.readouterr().out
