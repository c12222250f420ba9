"""The problem interface as types: every problem of the package satisfies it, the capabilities are
read as the problems declare them, and a non-problem is refused before any work."""

import numpy as np
import pytest

from slosh_bif import get_preset
from slosh_bif.continuation import (
    ContinuationOptions,
    Problem,
    capabilities,
    continuation,
)
from slosh_bif.continuation.problem import Domain, Edges, OwnTests, Stability
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem
from slosh_bif.orbits.shooting import ShootingProblem
from slosh_bif.slowflow.critical import FoldProblem
from slosh_bif.slowflow.steady_states import SteadyStateProblem

P10 = get_preset("fig10").params


class Circle:
    """x^2 + p^2 = 1 with one test function of its own, x itself (zero at the circle's top and bottom in
    p)."""

    names = ("x",)
    test_kinds = ("XZ",)

    def __init__(self):
        self.calls = 0

    def residual(self, x, p):
        self.calls += 1
        return np.array([x[0] ** 2 + p**2 - 1])

    def jacobian(self, x, p):
        return np.array([[2 * x[0]]])

    def dparam(self, x, p):
        return np.array([2 * p])

    def test_functions(self, x, p):
        return (x[0],)

    def confirm(self, kind, x, p):
        return f"x = 0 at p = {p:.6f}"


def test_every_problem_of_the_package_satisfies_the_interface():
    problems = [SteadyStateProblem(P10), ShootingProblem(P10), ImpactOrbitProblem(P10), FoldProblem(P10)]
    for problem in problems:
        assert isinstance(problem, Problem), type(problem).__name__
    shooting, impact = problems[1], problems[2]
    assert all(isinstance(shooting, kind) for kind in (Stability, OwnTests, Domain)) and capabilities(
        shooting
    ).test_kinds == ("PD", "NS")
    assert isinstance(impact, Edges) and capabilities(impact).test_kinds == ("PD", "NS")
    assert capabilities(problems[0]).from_jacobian


def test_a_bare_problem_gets_the_defaults_and_its_own_tests_are_located():
    problem = Circle()
    caps = capabilities(problem)
    assert caps.in_domain(np.array([0.5, 0.5])) and not caps.in_domain(np.array([np.nan, 0.0]))
    assert not caps.has_stability and np.all(np.isnan(caps.eigenvalues(np.array([0.5]), 0.1)))
    branch = continuation(
        problem, [1.0], 0.0, options=ContinuationOptions(step=0.1, step_max=0.2, p_min=-0.5, p_max=0.5)
    )
    assert branch.status == "ok" and np.all(branch.stable)
    own = [s for s in branch.special if s.kind == "XZ"]
    assert not own  # x stays near 1 for |p| <= 0.5: no sign change
    full = continuation(
        Circle(), [1.0], 0.0, options=ContinuationOptions(step=0.1, step_max=0.2, max_steps=200)
    )
    crossings = [s for s in full.special if s.kind == "XZ"]
    assert crossings and all(abs(abs(s.p) - 1.0) < 1e-8 for s in crossings)  # x = 0 where p = +-1 (the folds)
    assert crossings[0].message.startswith("x = 0 at p =")


def test_a_non_problem_is_refused_before_any_work():
    class Missing:
        names = ("x",)

        def residual(self, x, p):
            raise AssertionError("evaluated")

    with pytest.raises(TypeError, match="lacks jacobian, dparam"):
        continuation(Missing(), [1.0], 0.0)


def test_end_reasons_and_edge_names_are_fields_that_survive_save_and_load(tmp_path):
    """The Fig. 10 frequency response of (46) ends at the manifold's end on both sides: each END
    carries its reason and the problem's name for the edge, and the branch its ends, through save
    and load."""
    import json

    from slosh_bif.continuation import Branch
    from slosh_bif.slowflow.steady_states import frequency_response

    frc = frequency_response(get_preset("fig10").params)
    edges = [(b, s) for b in frc.branches for s in b.special if s.kind == "END" and s.reason == "domain edge"]
    assert edges
    branch, end = edges[0]
    assert end.edge.startswith("end of S+ at A = 0.06677")
    assert branch.ends == (("backward", "domain edge"), ("forward", "domain edge"))
    again = Branch.load(branch.save(tmp_path / "b.npz"))
    assert again.ends == branch.ends
    assert [s.edge for s in again.special] == [s.edge for s in branch.special]
    # a branch saved before ``ends`` was stored: read from its message
    with np.load(tmp_path / "b.npz") as data:
        files = {k: data[k] for k in data.files}
    meta = json.loads(str(files["meta"]))
    del meta["ends"]
    files["meta"] = np.array(json.dumps(meta))
    np.savez(tmp_path / "old.npz", **files)
    assert Branch.load(tmp_path / "old.npz").ends == branch.ends


class Line:
    """x = p with three tests of its own: ``NOISE``, a value of 1e-15 whose sign flips with every
    hundredth of p (rounding, below the problem's floor), ``RISE``, -1e-15 (rounding) up to p = 0
    and p^2 / 1000 beyond (a multiplier pair that nears the unit circle and never crosses it), and
    ``STOP``, p - 0.3, where the line ends by nature; and stability and a diagnostic counted per
    call."""

    names = ("x",)
    test_kinds = ("NOISE", "RISE", "STOP")
    test_floor = {"NOISE": 1e-12, "RISE": 1e-12}
    terminal_kinds = ("STOP",)

    def __init__(self):
        self.asked = 0

    def residual(self, x, p):
        return x - p

    jacobian = staticmethod(lambda x, p: np.eye(1))
    dparam = staticmethod(lambda x, p: -np.ones(1))

    def test_functions(self, x, p):
        return (1e-15 * (-1) ** int(np.floor(100 * p)), p * p / 1000 if p > 0 else -1e-15, p - 0.3)

    def eigenvalues(self, x, p):
        self.asked += 1
        return np.array([-1.0 + 0j])

    def diagnostics(self, x, p):
        return {"twice": 2 * p}


def test_rounding_flips_are_no_crossings_and_a_terminal_point_ends_the_branch(tmp_path):
    from slosh_bif.continuation import Branch

    problem = Line()
    branch = continuation(
        problem, [0.0], 0.0, options=ContinuationOptions(step=0.01, step_max=0.02, p_min=-1.0, p_max=1.0)
    )
    # a sign change with rounding at either end is none, whatever the other end's value
    assert not [s for s in branch.special if s.kind in ("NOISE", "RISE")]
    (stop,) = [s for s in branch.special if s.kind == "STOP"]
    assert (
        stop.p == pytest.approx(0.3, abs=1e-12)
        and stop.index == len(branch) - 1
        and stop.reason == "terminal point"
    )
    assert branch.status == "ok" and branch.ends == (
        ("backward", "parameter bound"),
        ("forward", "terminal point"),
    )
    assert branch.p.max() == pytest.approx(0.3, abs=1e-12)  # nothing beyond the terminal point is kept
    # stability asked once per point of the branch; the diagnostics recorded beside it, saved and loaded
    assert problem.asked == len(branch)
    assert np.allclose(branch.diagnostics["twice"], 2 * branch.p)
    again = Branch.load(branch.save(tmp_path / "line.npz"))
    assert np.array_equal(again.diagnostics["twice"], branch.diagnostics["twice"])
