"""The one Newton loop (slosh_bif.newton) against closed forms, and its failures named."""

import math

import numpy as np
import pytest

from slosh_bif.newton import NewtonSettings, newton_loop


def square_root_of_two(criterion):
    return newton_loop(
        lambda x: x**2 - 2.0, lambda x: np.array([[2.0 * x[0]]]), [1.0], NewtonSettings(criterion=criterion)
    )


@pytest.mark.parametrize("criterion", ["step", "residual", "corrector", "lookahead"])
def test_each_rule_converges_to_the_closed_form(criterion):
    run = square_root_of_two(criterion)
    # the residual rule stops at |F| <= 1e-11 (1 + |x|), i.e. |x - sqrt 2| <~ 1e-11
    assert run.converged and run.x[0] == pytest.approx(math.sqrt(2.0), abs=1e-11)
    assert 3 <= run.iterations <= 7  # quadratic convergence from 1


def test_a_start_that_solves_the_system_takes_no_step_and_forms_no_jacobian():
    def no_jacobian(x):
        raise AssertionError("formed")

    run = newton_loop(lambda x: x - 3.0, no_jacobian, [3.0])
    assert run.converged and run.iterations == 0 and run.message == "the start is a solution"


def test_halving_keeps_the_iterates_in_the_domain():
    # log x = 0 from x = 5: the full step goes to x = 5 - 5 log 5 < 0, where log is undefined
    settings = NewtonSettings(halvings=0)
    domain = {"admissible": lambda x: x[0] > 0}
    refused = newton_loop(np.log, lambda x: np.array([[1.0 / x[0]]]), [5.0], settings, **domain)
    assert not refused.converged and "left the domain" in refused.message
    run = newton_loop(
        np.log, lambda x: np.array([[1.0 / x[0]]]), [5.0], NewtonSettings(halvings=20), **domain
    )
    assert run.converged and run.x[0] == pytest.approx(1.0, abs=1e-12)


def test_failures_say_why_in_bounded_steps():
    singular = newton_loop(lambda x: np.array([x[0] ** 2 + 1.0]), lambda x: np.array([[0.0]]), [0.0])
    assert not singular.converged and "singular" in singular.message
    undefined = newton_loop(lambda x: np.array([np.nan]), lambda x: np.eye(1), [0.0])
    assert not undefined.converged and "not finite" in undefined.message
    # x^2 + 1 has no real root: Newton wanders; the run stops after max_iter with the count
    wander = newton_loop(
        lambda x: x**2 + 1.0, lambda x: np.array([[2.0 * x[0]]]), [0.3], NewtonSettings(max_iter=12)
    )
    assert not wander.converged and wander.iterations == 12 and "no convergence in 12" in wander.message
    with pytest.raises(ValueError, match="criterion"):
        NewtonSettings(criterion="norm")


def test_lookahead_stops_one_evaluation_before_the_corrector_rule_at_the_same_accuracy():
    # x^2 = 2 from 1.4142 at tol 1e-6: after one update |F| is at the tolerance; the corrector rule
    # evaluates F once more to see the next update, the look-ahead rule solves for it where it is
    calls = {"corrector": 0, "lookahead": 0}

    def run(criterion):
        def F(x):
            calls[criterion] += 1
            return x**2 - 2.0

        settings = NewtonSettings(tol=1e-6, criterion=criterion)
        return newton_loop(F, lambda x: np.array([[2.0 * x[0]]]), [1.4142], settings)

    strict, ahead = run("corrector"), run("lookahead")
    assert strict.converged and ahead.converged
    assert calls["lookahead"] == calls["corrector"] - 1 == 2
    assert ahead.x[0] == pytest.approx(math.sqrt(2.0), abs=1e-6 * (1 + math.sqrt(2.0)))


def test_lookahead_gives_up_on_a_run_that_makes_no_progress():
    # x^2 + 1 = 0 has no real root: Newton wanders; the look-ahead rule stops after three updates
    # without the residual halving, flagged as stalled (not as a domain exit), the corrector rule
    # only at max_iter
    F, J = lambda x: x**2 + 1.0, lambda x: np.array([[2.0 * x[0]]])
    ahead = newton_loop(F, J, [0.5], NewtonSettings(criterion="lookahead"))
    strict = newton_loop(F, J, [0.5], NewtonSettings(criterion="corrector"))
    assert not ahead.converged and ahead.stalled and ahead.iterations < 30 and "no progress" in ahead.message
    assert not strict.converged and not strict.stalled and strict.iterations == 30
