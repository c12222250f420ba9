"""A family's work side by side in threads: its switches traced ahead (the family is the one
traced a switch at a time; the queue's mechanics, order, progress lines, abandoned traces and
errors, hold for any runs) and its special points judged (the verdicts of one at a time)."""

import threading

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.orbits import BranchingSettings
from slosh_bif.orbits.criticality import describe, family_criticality, special_criticality
from slosh_bif.orbits.families import trace_orbits
from slosh_bif.orbits.settings import ParameterRange
from slosh_bif.orbits.starts import settle_and_shoot
from slosh_bif.orbits.switch_ahead import SwitchesAhead, switch_threads, threads


@pytest.fixture(scope="module")
def families():
    """The family of :func:`_family` traced a switch at a time and two at once."""
    return _family(1), _family(2)


def _family(count):
    """The Fig. 10 family through the asymmetric orbit at sigma = -3 over [-3.9, -1.5]: its two
    period doublings switched (two period-2 branches), ``count`` at once."""
    preset = get_preset("fig10")
    P = preset.params.replace(sigma=-3.0)
    orbit, _ = settle_and_shoot(P, preset.state0)
    said = []
    with switch_threads(count):
        family = trace_orbits(
            P,
            orbit.y0,
            branching=BranchingSettings(max_branches=3),
            interval=ParameterRange(lo=-3.9, hi=-1.5),
            progress=said.append,
        )
    return family, said


def test_a_family_traced_with_its_switches_side_by_side_is_the_one_traced_a_switch_at_a_time(families):
    (one, said_one), (two, said_two) = families
    assert [ob.name for ob in one.branches] == ["asymmetric", "period-2", "period-2-2"]
    assert [ob.name for ob in two.branches] == [ob.name for ob in one.branches]
    for a, b in zip(one.branches, two.branches):
        assert (a.origin, a.kind, a.problem.period_multiple) == (b.origin, b.kind, b.problem.period_multiple)
        for name in ("p", "x", "eigenvalues", "newton_iterations", "arclength"):
            assert np.array_equal(getattr(a.branch, name), getattr(b.branch, name)), (a.name, name)
        special = [[(s.kind, s.index, s.p) for s in ob.branch.special] for ob in (a, b)]
        assert special[0] == special[1], a.name
        assert a.measures.keys() == b.measures.keys()
        for key in a.measures:
            assert np.array_equal(a.measures[key], b.measures[key], equal_nan=True), (a.name, key)
    # The second period doubling was traced while the first was: the progress lines come in the
    # same order all the same, with one more saying so.
    ahead = [m for m in said_two if m.startswith("switches traced ahead")]
    assert ahead and not ahead[0].startswith("switches traced ahead in threads: 0")
    assert [m for m in said_two if m not in ahead] == said_one


def test_a_family_judged_in_threads_gets_the_verdicts_of_one_point_at_a_time(families):
    (one, _), (two, _) = families
    alone = [special_criticality(ob) for ob in one.branches]
    with switch_threads(2):
        side_by_side = family_criticality(two.branches)
    assert sum(len(found) for found in alone) >= 3
    for a, b in zip(alone, side_by_side):
        assert list(a) == list(b)
        for k in a:
            assert describe(a[k]) == describe(b[k])
            if not isinstance(a[k], str):
                numbers = [[v.coefficient, v.growth, v.side] for v in (a[k], b[k])]
                assert np.array_equal(*numbers, equal_nan=True)


def _runs(log, gate=None, fail=None):
    """A ``run(say, trace)`` per key that says two lines and returns its key and whether it ran
    ahead; ``gate``: (arrived, go), events a run ahead sets, then waits for, between its lines;
    ``fail``: the key whose run raises."""

    def make(key):
        def run(say, trace):
            say(f"{key} 1")
            if gate is not None and trace is not None:
                gate[0].set()
                gate[1].wait(5)
            log.append((key, trace is not None, threading.current_thread() is threading.main_thread()))
            if key == fail:
                raise ValueError(f"{key} failed")
            say(f"{key} 2")
            return key, trace is not None

        return run

    return make


def test_switches_come_in_turn_with_their_lines_in_order_and_run_once():
    said, log = [], []
    make = _runs(log)
    keys = ["a", "b", "c", "d"]
    with SwitchesAhead(2, said.append) as switches:
        results = [
            switches.take(k, make(k), [(j, make(j)) for j in keys[i + 1 :]]) for i, k in enumerate(keys)
        ]
    assert [r[0] for r in results] == keys
    assert any(r[1] for r in results)  # some ran ahead, in a thread
    assert sorted(k for k, _, _ in log) == keys  # each ran once
    assert all(in_main == (not ahead) for _, ahead, in_main in log)
    assert said[:-1] == [f"{k} {i}" for k in keys for i in (1, 2)]
    assert said[-1].startswith("switches traced ahead in threads:")


def test_a_trace_ahead_that_ends_makes_way_for_the_next_while_the_turn_runs():
    c_started = threading.Event()

    def make(key):
        def run(say, trace):
            if key == "c":
                c_started.set()
            if key == "a":  # the turn runs here until c, second in line, has been started ahead
                assert c_started.wait(5), "c was not started when b, ahead of it, ended"
            return key

        return run

    with SwitchesAhead(2, lambda message: None) as switches:
        assert switches.take("a", make("a"), [("b", make("b")), ("c", make("c"))]) == "a"
        assert switches.take("b", make("b"), [("c", make("c"))]) == "b"
        assert switches.take("c", make("c")) == "c"


def test_one_thread_runs_each_switch_in_its_turn_here():
    said, log = [], []
    make = _runs(log)
    with SwitchesAhead(1, said.append) as switches:
        assert switches.take("a", make("a"), [("b", make("b"))]) == ("a", False)
        assert switches.take("b", make("b")) == ("b", False)
    assert log == [("a", False, True), ("b", False, True)]
    assert said == ["a 1", "a 2", "b 1", "b 2"]


def test_a_trace_ahead_no_longer_wanted_is_abandoned_at_its_next_line():
    said, log, arrived, go = [], [], threading.Event(), threading.Event()
    make = _runs(log, (arrived, go))
    with SwitchesAhead(2, said.append) as switches:
        switches.take("a", make("a"), [("b", make("b"))])  # b starts ahead and waits
        assert arrived.wait(5)
        assert switches.take("c", make("c"), []) == ("c", False)  # b left the queue
        go.set()
    assert said == ["a 1", "a 2", "c 1", "c 2", "switches traced ahead in threads: 1, 1 of them not needed"]
    assert ("b", True, False) in log  # it got past the gate, then stopped at its next line


def test_an_error_of_a_trace_ahead_is_raised_in_its_turn():
    said, log = [], []
    make = _runs(log, fail="b")
    with SwitchesAhead(2, said.append) as switches:
        switches.take("a", make("a"), [("b", make("b"))])
        with pytest.raises(ValueError, match="b failed"):
            switches.take("b", make("b"))
    assert said[:3] == ["a 1", "a 2", "b 1"]


def test_switch_threads_is_checked_and_scoped():
    with pytest.raises(ValueError, match="switch threads must be an integer >= 1; got 0"):
        with switch_threads(0):
            pass
    default = threads()
    assert default >= 1
    with switch_threads(3):
        assert threads() == 3
    assert threads() == default
