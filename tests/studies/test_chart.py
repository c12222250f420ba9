"""The chart's curve tracing on several processes gives the sequential result: the same curves,
point for point, each once however the starts repeat (issue 16's speed target, on 2 cores)."""

import dataclasses
from concurrent.futures import Future

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.model.params import Params
from slosh_bif.orbits import (
    NO_SWITCHING,
    ShootingSettings,
    orbit_from_simulation,
    trace_orbits,
)
from slosh_bif.orbits.settings import BranchingSettings, ParameterRange
from slosh_bif.studies.chart import ChartSettings, bifurcation_chart
from slosh_bif.studies.chart.critical import critical_rows
from slosh_bif.studies.chart.curves import (
    CurveStart,
    curve_starts,
    trace_curves,
)
from slosh_bif.studies.chart.reading import exits_below, lowest_stable_boundary, seed_disagreements
from slosh_bif.studies.chart.result import Chart
from slosh_bif.studies.chart.seeds import seed_points, uncovered_points

PRESET = get_preset("fig10")
# A random admissible draw (seed 28 of the chart's campaign, docs/findings/chart.md)
SEED_28 = Params(
    eps=0.13503608402999223,
    beta=0.6242813949181742,
    gamma=0.06448937039741993,
    sigma=-2.049,
    Abar=0.9104394001221893,
    lam=0.1451777130963097,
    chi=1.351204532948671,
    n=21,
    pbar=1,
)


@pytest.fixture(scope="module")
def starts():
    """The fold at sigma = -1.40 and the pitchfork at -1.09 of the symmetric branch at Abar = 3,
    each listed twice (as when two branches share a special point)."""
    P = PRESET.params
    start = orbit_from_simulation(P.replace(sigma=-1.2), PRESET.state0, settle=150)
    family = trace_orbits(
        start.params,
        start.y0,
        shooting=ShootingSettings(points_per_2pi=32),
        branching=NO_SWITCHING,
        interval=ParameterRange(lo=-1.6, hi=-0.9),
    )
    found = list(curve_starts(family.branches[0], P, {"sigma": (-1.6, -0.9), "Abar": (2.8, 3.2)}))
    assert sorted(s.kind for s in found) == ["BP", "LP"]
    return found + found


def test_parallel_curves_are_the_sequential_curves_each_once(starts):
    sequential, status, failures = trace_curves(starts, lambda message: None, workers=1)
    assert failures == ()
    assert status == "complete" and sorted(c.kind for c in sequential) == ["BP", "LP"]
    parallel, status, failures = trace_curves(starts, lambda message: None, workers=2)
    assert failures == ()
    assert status == "complete" and [c.kind for c in parallel] == [c.kind for c in sequential]
    for a, b in zip(sequential, parallel):
        np.testing.assert_array_equal(a.branch.x, b.branch.x)
        np.testing.assert_array_equal(a.branch.p, b.branch.p)


def test_a_fold_starts_side_of_the_circle_is_its_curves(starts):
    # The resonant fold at sigma = -1.40 bounds stable orbits: its other multipliers, read at the
    # located point on the branch in sigma, are inside the circle, as the fold curve's own (on
    # its minimally augmented system) are where it starts.
    fold = next(s for s in starts if s.kind == "LP")
    assert fold.inside is True
    (curve,), _, _ = trace_curves([fold], lambda message: None, workers=1)
    j = int(np.argmin(np.hypot(curve["sigma"] - fold.sigma, curve["Abar"] - fold.value)))
    assert curve["max_abs_multiplier"][j] < 1


def test_a_period_two_branch_turning_where_it_meets_its_parent_gives_no_fold_curve():
    # At the flip where a period-2 branch is born (or meets its parent again), the branch has
    # t_p = 0 and the engine labels an LP; its orbit is the parent's, repeating after 2pi. The Fig.
    # 13 chart tried fold curves from two such points and Newton failed on them (the doubled
    # orbit's +1 is the parent's -1 squared): they are no starts; a genuine period-2 fold is.
    from types import SimpleNamespace

    from slosh_bif.continuation import SpecialPoint
    from slosh_bif.orbits import ShootingProblem
    from slosh_bif.studies.chart.curves import repeats_early

    P = PRESET.params
    problem = ShootingProblem(P, segments=4, period_multiple=2)
    parent = np.array([0.3, -0.1, 0.9, 0.2, -0.2, 0.4, -0.7, 0.1])  # two arcs of pi: the 2pi orbit
    for x, expected in (
        (np.tile(parent, 2), ["PD"]),
        (np.concatenate([parent, parent + 0.05]), ["LP", "PD"]),
    ):
        assert repeats_early(problem, x) == (expected == ["PD"])
        special = tuple(SpecialPoint(kind, 1, -1.0, x, (-1.1, -0.9), "", None) for kind in ("LP", "PD"))
        ob = SimpleNamespace(
            branch=SimpleNamespace(special=special, param="sigma"),
            problem=problem,
            kind="period-2",
            name="period-2",
        )
        assert [s.kind for s in curve_starts(ob, P, {"sigma": (-2.0, 0.0), "Abar": (2.0, 4.0)})] == expected
    assert not repeats_early(
        ShootingProblem(P, segments=4), np.tile(parent, 2)
    )  # a 2pi problem has no parent to meet


def test_an_asymmetric_branch_turning_at_its_symmetric_parent_starts_a_pitchfork_curve():
    # A family traced without its symmetric parent (--no-switch from an asymmetric attractor, or
    # a branch in Abar) sees the pair meet the parent as a turn, an LP whose fold system is
    # singular (the tank example's chart failed to start 8 fold curves there). The orbit is
    # symmetric to the turn's location: the start is the parent's pitchfork, from the orbit made
    # exactly symmetric; a genuine fold of the pair stays a fold.
    from types import SimpleNamespace

    from slosh_bif.continuation import SpecialPoint
    from slosh_bif.orbits import ShootingProblem
    from slosh_bif.studies.chart.curves import is_symmetric

    P = PRESET.params
    problem = ShootingProblem(P, segments=4)
    half = np.array([0.3, -0.1, 0.9, 0.2, -0.2, 0.4, -0.7, 0.1])
    nearly = np.concatenate([half, -half]) + 1e-6 * np.arange(16)
    for x, expected in ((nearly, "BP"), (np.concatenate([half, -half + 0.05]), "LP")):
        assert is_symmetric(problem, x) == (expected == "BP")
        special = (SpecialPoint("LP", 1, -1.0, x, (-1.1, -0.9), "", None),)
        ob = SimpleNamespace(
            branch=SimpleNamespace(special=special, param="sigma"),
            problem=problem,
            kind="asymmetric",
            name="asymmetric",
        )
        (start,) = curve_starts(ob, P, {"sigma": (-2.0, 0.0), "Abar": (2.0, 4.0)})
        seed = start.job["seed"]
        assert start.kind == seed.kind == expected
        if expected == "BP":
            np.testing.assert_allclose(seed.x[8:], -seed.x[:8], rtol=0, atol=0)
            np.testing.assert_allclose(seed.x, x, atol=2e-5)
            assert start.origin.startswith("BP (the turn of the pair")
    assert not is_symmetric(ShootingProblem(P, segments=4, period_multiple=2), nearly)


def test_an_ns_curve_met_at_a_codim2_point_of_a_fold_curve_is_started_there_once():
    # A fold curve's LPNS point lying on no traced NS curve starts an NS curve from the orbit
    # there (its states without the curve's second parameter), at both parameters of the point;
    # one on a traced NS curve starts nothing.
    from types import SimpleNamespace

    from slosh_bif.studies.chart.curves import torus_starts

    P = PRESET.params
    states = np.arange(16.0)  # 4 arcs of one forcing period
    lpns = SimpleNamespace(kind="LPNS", p=-0.07, x=np.append(states, 0.8))
    fold = SimpleNamespace(
        kind="LP", p1="sigma", period_multiple=1, origin="LP at ...", branch=SimpleNamespace(special=[lpns])
    )
    box = {"sigma": (-1.0, 1.0), "Abar": (0.2, 3.0)}
    (start,) = torus_starts([fold], P, box)
    job = start.job
    assert (start.kind, start.sigma, start.value) == ("NS", -0.07, 0.8)
    assert job["seed"].kind == "NS" and np.array_equal(job["seed"].x, states) and job["seed"].p == -0.07
    assert (job["params"].sigma, job["params"].Abar) == (-0.07, 0.8) and job["shooting"].segments == 4

    class Traced:  # an NS curve through the point
        kind, p2 = "NS", "Abar"

        def __len__(self):
            return 2

        def __getitem__(self, name):
            return {"sigma": np.array([-0.2, 0.1]), "Abar": np.array([0.8, 0.8])}[name]

    assert list(torus_starts([fold, Traced()], P, box)) == []


def test_the_pitchfork_curve_from_a_pairs_turn_meets_the_turn_of_a_one_parameter_branch():
    # The tank example's set, whose attractor at sigma = 2 is an asymmetric orbit: its branch in
    # sigma turns where the pair meets the symmetric parent (2.3456). The BP curve started there
    # passes, at Abar = 2.9, through the turn of that Abar's own branch in sigma (an independent
    # one-parameter run from its own simulation).
    from pathlib import Path

    from slosh_bif.model.parameter_file import read_parameter_file

    tank = read_parameter_file(Path(__file__).parents[2] / "docs/identify/tank/tank.toml")
    shooting = ShootingSettings(points_per_2pi=32)

    def branch(P, lo, hi):
        start = orbit_from_simulation(P.replace(sigma=2.0), tank.state0, settle=150)
        family = trace_orbits(
            start.params,
            start.y0,
            shooting=shooting,
            branching=NO_SWITCHING,
            interval=ParameterRange(lo=lo, hi=hi),
        )
        return family.branches[0]

    ob = branch(tank.params, 1.8, 2.6)
    assert ob.kind == "asymmetric"
    box = {"sigma": (1.5, 3.5), "Abar": (2.5, 2.95)}
    (start,) = curve_starts(ob, tank.params, box, shooting=shooting)
    assert start.kind == "BP" and abs(start.sigma - 2.34564) < 1e-5
    (curve,), status, failures = trace_curves([start], lambda message: None)
    assert status == "complete" and failures == () and curve.status == "ok"
    turns = [sp.p for sp in branch(tank.params.replace(Abar=2.9), 1.8, 2.8).branch.special if sp.kind == "LP"]
    order = np.argsort(curve["Abar"])
    on_curve = np.interp(2.9, curve["Abar"][order], curve["sigma"][order])
    assert len(turns) == 1 and abs(turns[0] - on_curve) < 2e-5  # the curve read between its points


def test_seeds_spread_over_the_sigma_the_primary_branch_covers_each_point_once():
    """An isola (the primary branch of eps 0.08, beta 0.15, gamma 0.3, lam 0.25, chi 0.4, n 8,
    pbar 2 at Abar 2 spans sigma in [-0.643, 0.161] only): seven targets spread over the whole
    box would fall on its two ends, whose curves would then be traced three and four times."""
    loop = np.concatenate([np.linspace(-0.643, 0.161, 60), np.linspace(0.161, -0.643, 60)[1:]])
    regular = np.ones(len(loop), dtype=bool)
    regular[:3] = regular[57:63] = False  # near its special points
    chosen = seed_points([(loop, regular)], (-5.0, 6.0), 7)
    assert len(chosen) == len(set(chosen)) == 7
    sigmas = np.array(sorted(loop[i] for _, i in chosen))
    assert np.all(np.diff(sigmas) > 0.05) and -0.643 < sigmas[0] and sigmas[-1] < 0.161
    assert all(regular[i] for _, i in chosen)
    # a branch across the whole range: the nearest regular point to each of the equally spaced
    # targets, on whichever piece has it
    full = np.linspace(-6.0, 8.0, 141)
    pieces = [(full[:70], np.ones(70, dtype=bool)), (full[70:], np.ones(71, dtype=bool))]
    chosen = seed_points(pieces, (-6.0, 8.0), 6)
    assert [pieces[k][0][i] for k, i in chosen] == pytest.approx(np.linspace(-6, 8, 8)[1:-1])
    assert [k for k, _ in chosen] == [0, 0, 0, 1, 1, 1]
    # a branch with fewer regular points than targets gives each once; none gives no seed
    assert len(seed_points([(full, np.arange(141) % 70 == 0)], (-6.0, 8.0), 7)) == 3
    assert seed_points([(full, np.zeros(141, dtype=bool))], (-6.0, 8.0), 7) == []


def test_the_parts_of_the_box_an_isola_leaves_get_seeds_of_their_own_by_their_length():
    """An isola over [-0.22, 0.04] in the box [-4, 5]: the 3.78 to its left gets three of seven
    seeds, the 4.96 to its right four, spread over their insides; a branch across the box, or
    leaving less than 2 % of it, leaves none."""
    isola = np.concatenate([np.linspace(-0.22, 0.04, 30), np.linspace(0.04, -0.22, 30)])
    left, right = np.linspace(-4, -0.22, 5)[1:-1], np.linspace(0.04, 5, 6)[1:-1]
    assert uncovered_points([isola], (-4.0, 5.0), 7) == pytest.approx([*left, *right])
    assert uncovered_points([np.linspace(-4, 5, 50)], (-4.0, 5.0), 7) == []
    assert uncovered_points([isola], (-4.0, 5.0), 0) == []  # no seeds asked for
    assert uncovered_points([np.linspace(-3.9, 5, 50)], (-4.0, 5.0), 7) == []
    # two pieces with a gap between them: the gap, one seed at least
    assert uncovered_points([np.linspace(-4, 0, 9), np.linspace(1, 5, 9)], (-4.0, 5.0), 7) == [0.5]


class _Line:
    """A curve as the chart's bookkeeping sees it: a kind and points in (sigma, Abar)."""

    p2, status = "Abar", "ok"

    def __init__(self, kind, origin):
        self.kind, self.origin = kind, origin
        self.sigma = np.linspace(-1.0, 1.0, 21)
        self.Abar = 2.0 + self.sigma if kind == "LP" else 3.0 - self.sigma
        self.max_abs_multiplier = np.full(21, 0.5)  # every other multiplier inside the circle

    def __len__(self):
        return len(self.sigma)

    def __getitem__(self, name):
        return getattr(self, name)


def _line(kind, origin):
    return _Line(kind, origin)


class _HeldExecutor:
    """Runs each job at once, except the NS curve's, which finishes only when the test says."""

    def __init__(self):
        self.submitted, self.held = [], Future()

    def submit(self, function, job):
        self.submitted.append(job["origin"])
        if job["kind"] == "NS":
            return self.held
        future = Future()
        future.set_result(function(job))
        return future


def test_a_start_on_a_finished_curve_of_its_kind_is_not_traced_while_another_kind_runs():
    """The second fold start lies on the first fold's curve: once that curve is in, the start is
    skipped though the NS curve started before both is still running (only a curve of its own
    kind can cover a start). The curves kept are the sequential run's."""
    starts = [
        CurveStart.with_job(kind, sigma, value, origin, dict(trace=_line, kind=kind, origin=origin))
        for kind, sigma, value, origin in [
            ("NS", 0.0, 3.0, "ns"),
            ("LP", 0.0, 2.0, "lp 1"),
            ("LP", 0.5, 2.5, "lp 2 on lp 1"),
        ]
    ]
    executor = _HeldExecutor()

    def say(message):
        if message.startswith("LP curve from lp 1"):
            executor.held.set_result((_line("NS", "ns"), None, 0.0))

    curves, status, failures = trace_curves(starts, say, workers=2, executor=executor)
    assert executor.submitted == ["ns", "lp 1"]
    sequential, _, _ = trace_curves(starts, lambda message: None, workers=1)
    assert [c.origin for c in curves] == [c.origin for c in sequential] == ["ns", "lp 1"]
    assert status == "complete" and failures == ()


def test_a_fold_start_on_a_fold_curve_of_the_other_side_of_the_circle_is_traced():
    """A fold start within 2e-3 of a traced fold curve lies on it only where the curve's other
    multipliers are on the start's side of the unit circle there (two folds 1.7e-3 apart at
    Abar = 0.28 on a random set of (8), one bounding stable orbits and one not)."""

    def fold_starts(inside):
        job = dict(trace=_line, kind="LP", origin="lp 2")
        return [
            CurveStart.with_job("LP", 0.0, 2.0, "lp 1", dict(trace=_line, kind="LP", origin="lp 1")),
            CurveStart.with_job("LP", 0.5, 2.5005, "lp 2", job, inside),
        ]

    for inside, traced in ((True, ["lp 1"]), (None, ["lp 1"]), (False, ["lp 1", "lp 2"])):
        curves, status, _ = trace_curves(fold_starts(inside), lambda message: None, workers=1)
        assert status == "complete" and [c.origin for c in curves] == traced


ISOLA = Params(eps=0.08, beta=0.15, gamma=0.3, sigma=0.0, Abar=2.0, lam=0.25, chi=0.4, n=8, pbar=2)


def test_a_seed_switches_at_its_pitchfork_to_the_pair_whose_flip_bounds_the_stable_orbits():
    """The fast check of the chart below: at sigma = -0.089 of the isola's set, the seed's family
    in Abar (switched as a chart's seeds are) holds an asymmetric pair with a flip below Abar = 1,
    a PD curve starts there, and the orbit has a multiplier -1 by scipy's integration of (9) and
    its variational equations over the period (the reference path)."""
    from slosh_bif.model.equations import SmoothModel
    from slosh_bif.orbits.period_map import period_map
    from slosh_bif.orbits.settings import BRANCHING
    from slosh_bif.studies.chart.curves import family_starts
    from slosh_bif.studies.chart.seeds import seed_branching

    at = ISOLA.replace(sigma=-0.0892857142857)
    start = orbit_from_simulation(at, PRESET.state_for(ISOLA), settle=150)
    box = {"sigma": (-0.6, 0.1), "Abar": (0.7, 2.5)}
    family = trace_orbits(
        start.params,
        start.y0,
        branching=seed_branching(BRANCHING),
        interval=ParameterRange(name="Abar", **dict(zip(("lo", "hi"), box["Abar"]))),
    )
    flips = [sp for ob in family.branches if ob.kind == "asymmetric" for sp in ob.branch.special_of("PD")]
    low = min(flips, key=lambda sp: sp.p)
    assert low.p < 1.0
    starts = family_starts(family, at, box)
    assert any(s.kind == "PD" and abs(s.value - low.p) < 1e-9 for s in starts)
    y0 = np.asarray(low.x[:4], dtype=float)
    model = SmoothModel(at.replace(Abar=float(low.p)))
    _, M, _ = period_map(model.rhs, model.jac, y0, 2 * np.pi, rtol=1e-11, atol=1e-13)
    assert min(abs(np.linalg.eigvals(M) + 1)) < 1e-5


@pytest.mark.slow  # a whole chart in one process (45 s); the check above is its fast part
def test_below_an_isola_the_chart_finds_the_flip_of_the_pair_born_at_a_pitchfork_in_abar():
    """At eps 0.08, beta 0.15, gamma 0.3, lam 0.25, chi 0.4, n 8, pbar 2 the primary family at
    Abar = 2 is an isola (sigma in [-0.643, 0.161]), and at sigma = -0.089 the stable response is
    lost, as the forcing falls, at a flip of an asymmetric pair that exists only in Abar, born at a
    pitchfork of the seed's symmetric orbits: the chart reaches it by switching there (without,
    it read 1.60 at an NS curve). The chart's Abar_c (a two-parameter curve, corrected at sigma)
    against the flip located on a one-parameter branch in Abar at that sigma."""
    params = ISOLA
    state0 = PRESET.state_for(params)
    box = {"sigma": (-0.6, 0.1), "Abar": (0.7, 2.5)}
    chart = bifurcation_chart(params, state0, box=box, settings=ChartSettings(seeds=2, workers=1))
    sigma = -0.0892857142857
    abar_c, kind, loss = lowest_stable_boundary(chart.curves, sigma, params)
    assert (kind, loss) == ("PD", "soft") and abar_c < 1.0
    # the pair's fold bounds the stable orbits below the box's Abar = 0.7 from about sigma = -0.4
    # (0.668 at -0.48): the chart says where it leaves
    exits = [(kind, s, side) for _, kind, s, side in exits_below(chart)]
    assert any(kind == "LP" and -0.5 < s < -0.3 and side == -1 for kind, s, side in exits)
    rows = list(critical_rows(chart))  # sigma from -0.6 to 0.1: flagged left of the exit only
    assert (rows[0]["sigma"], rows[0]["below_box"], rows[-1]["below_box"]) == (-0.6, 1, 0)
    at = params.replace(sigma=sigma)
    start = orbit_from_simulation(at, state0, settle=150)
    family = trace_orbits(
        start.params,
        start.y0,
        branching=BranchingSettings(doublings=False, max_branches=3),
        interval=ParameterRange(name="Abar", lo=0.5, hi=2.5),
    )
    flips = [sp.p for ob in family.branches if ob.kind == "asymmetric" for sp in ob.branch.special_of("PD")]
    assert min(abs(np.array(flips) - abar_c)) < 1e-7


@pytest.mark.slow  # a whole chart (about 40 s on 2 cores) and two one-sigma answers
@pytest.mark.parametrize("sigma", [-0.482142857143, 0.303571428571])
def test_a_whole_chart_at_a_set_that_is_no_preset_agrees_with_the_one_sigma_critical_forcing(sigma):
    """The isola's set over the box sigma in [-5, 6], Abar in [0.2, 5]: the chart's Abar_c (its
    curves' envelope) against critical_forcing_full at that sigma (every family there in Abar, the
    curves through their special points in a narrow box), a different search for the same
    number: a fold at -0.48, a torus curve at 0.30."""
    from slosh_bif.studies.chart import critical_forcing_full

    params = Params(eps=0.08, beta=0.15, gamma=0.3, sigma=0.0, Abar=2.0, lam=0.25, chi=0.4, n=8, pbar=2)
    state0 = PRESET.state_for(params)
    chart = bifurcation_chart(params, state0, box={"sigma": (-5.0, 6.0), "Abar": (0.2, 5.0)})
    abar_c, kind, _ = lowest_stable_boundary(chart.curves, sigma, params)
    one = critical_forcing_full(params.replace(sigma=sigma), state0)
    assert (one.bounded_by, kind) == (("LP", "LP") if sigma < 0 else ("NS", "NS"))
    assert abar_c == pytest.approx(one.Abar_c, rel=1e-6)


@pytest.mark.slow  # a chart (25 s on 2 cores) and a one-sigma answer (10 s)
def test_where_the_primary_branch_is_an_isola_the_chart_scans_the_rest_of_the_box():
    """eps 0.0727, beta 0.481, gamma 0.278, lam 0.236, chi 1.35, n 13, pbar -7: at Abar = 2.04
    the primary branch is an isola of asymmetric orbits over sigma in [-0.22, 0.04]. At sigma =
    3.58 the stable response is lost at a torus point of the linear response's family (0.945),
    which no curve from the isola reaches (the chart read NaN there). The chart scans for orbits
    at sigmas outside the isola; its Abar_c against critical_forcing_full."""
    from slosh_bif.studies.chart import critical_forcing_full

    params = Params(
        eps=0.0726730510330887,
        beta=0.481053364495394,
        gamma=0.2778798952715666,
        sigma=0.0,
        Abar=2.0412675163465517,
        lam=0.23648117799319274,
        chi=1.3489398374888895,
        n=13,
        pbar=-7,
    )
    state0 = PRESET.state_for(params)
    box = {"sigma": (-0.3, 4.0), "Abar": (0.5, 2.1)}
    chart = bifurcation_chart(params, state0, box=box, settings=ChartSettings(seeds=3))
    abar_c, kind, _ = lowest_stable_boundary(chart.curves, 3.5804, params)
    one = critical_forcing_full(params.replace(sigma=3.5804), state0, abar_range=(0.1, 4.0))
    assert (kind, one.bounded_by) == ("NS", "NS")
    assert abar_c == pytest.approx(one.Abar_c, rel=1e-6)


@pytest.mark.slow  # two one-sigma answers and two simulations (40 s)
def test_where_stable_orbits_with_contact_reach_below_every_bounding_point_the_answer_says_so():
    """eps 0.135, beta 0.624, gamma 0.064, lam 0.145, chi 1.35, n 21, pbar 1, sigma = -2.049: a
    branch of symmetric orbits in Abar is stable with contact (max |w| 1.03-1.07) from its
    pitchfork at 3.234 down to a fold at 0.0455, below every curve that bounds stable orbits. The
    answer is that fold; over a range whose bottom is 0.1 it lies below the range. Simulations of
    (9) from the orbit with contact at Abar = 0.06 agree: at 0.06 the motion stays in contact, at
    0.04 it leaves the walls."""
    from slosh_bif.simulation.direct import integrate_smooth
    from slosh_bif.studies.chart import critical_forcing_full

    params = SEED_28
    short = critical_forcing_full(params, PRESET.state_for(params), abar_range=(0.1, 4.0))
    assert short.below_range and np.isnan(short.Abar_c)
    one = critical_forcing_full(params, PRESET.state_for(params), abar_range=(0.02, 4.0))
    assert (one.bounded_by, one.loss, one.below_range) == ("LP", "jump", False)
    assert 0.04 < one.Abar_c < 0.05
    branch = next(ob for ob in one.chart.family.branches if np.any(ob.branch.p < 0.05))
    contact = branch.branch.stable & (branch["max_abs_w"] >= 1) & (branch.branch.p > 0.06)
    i = np.flatnonzero(contact)[np.argmin(branch.branch.p[contact])]
    y0 = branch.branch.x[i, :4]
    for abar, touches in ((0.06, True), (0.04, False)):
        run = integrate_smooth(
            params.replace(Abar=abar),
            y0,
            (0.0, 400 * np.pi),
            t_eval=np.linspace(360 * np.pi, 400 * np.pi, 20001),
        )
        assert (np.max(np.abs(run.y[2])) >= 1.0) == touches


@pytest.mark.slow  # a chart of three curves (10 s)
def test_a_chart_whose_lowest_curve_has_stable_orbits_with_contact_below_marks_the_rows_below_the_box():
    """The set above charted over sigma in [-2.6, -1.6], Abar in [0.1, 4]: the lowest curve that
    bounds stable orbits is the pitchfork at 3.234, but the symmetric orbits below it are stable
    with contact down to the box's bottom (the one-sigma answer's fold at 0.0455 lies below it):
    the rows where that curve is read say so (no Abar_c, below_box 1), and so do those along the
    branch at the box's bottom."""
    params = SEED_28.replace(Abar=3.0)
    chart = bifurcation_chart(
        params,
        PRESET.state_for(params),
        box={"sigma": (-2.6, -1.6), "Abar": (0.1, 4.0)},
        settings=ChartSettings(seeds=3, workers=2),
    )
    rows = list(critical_rows(chart, 5))
    for row in rows[1:]:
        assert lowest_stable_boundary(chart.curves, row["sigma"])[1] == "BP"
    # Where no curve reaches (sigma = -2.6), the seed's branch in Abar reaches the box's bottom, and
    # the orbit there followed in sigma along it is stable with contact: those rows say so too,
    # and the seed has nothing left to warn of.
    assert np.isnan(lowest_stable_boundary(chart.curves, rows[0]["sigma"])[0])
    assert chart.bottom
    for row in rows:
        assert np.isnan(row["Abar_c_full"]) and row["below_box"] == 1 and row["bounded_by"] == ""
    assert seed_disagreements(chart) == []
    # A simulation of (9) at (sigma, Abar) = (-2.6, 0.1), from the seed's orbit at the bottom,
    # still touches the walls after 200 periods.
    from slosh_bif.simulation.direct import integrate_smooth

    (_, family), *_ = chart.seeds
    ob = min(family.branches, key=lambda b: b.branch.p.min())
    y0 = ob.branch.x[int(np.argmin(ob.branch.p)), :4]
    run = integrate_smooth(
        params.replace(sigma=-2.6, Abar=0.1),
        y0,
        (0.0, 400 * np.pi),
        t_eval=np.linspace(360 * np.pi, 400 * np.pi, 20001),
    )
    assert np.max(np.abs(run.y[2])) >= 1.0


def test_a_seed_with_stable_orbits_with_contact_below_the_curves_reading_is_reported():
    """A chart's seed (its family in Abar at one sigma) against its curves: with none traced, the
    seed's fold at 0.0455, the lower end of its stable orbits with contact, is reported."""
    family = trace_orbits(
        SEED_28.replace(Abar=0.02),
        np.zeros(4),
        interval=ParameterRange(0.02, 4.0, "Abar"),
        branching=NO_SWITCHING,
    )
    chart = Chart(SEED_28, (-2.5, -1.5), (0.02, 4.0), family, [], None, 0.0, seeds=((-2.049, family),))
    ((sigma, read, least, below),) = seed_disagreements(chart)
    assert sigma == -2.049 and np.isnan(read) and not below
    assert 0.04 < least < 0.05
    assert seed_disagreements(dataclasses.replace(chart, abar_range=(0.1, 4.0)))[0][3]
