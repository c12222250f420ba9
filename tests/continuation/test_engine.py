"""The continuation engine on problems with known answers: a circle, the cubic, a pitchfork."""

import dataclasses

import numpy as np
import pytest

from slosh_bif.continuation import (
    ContinuationOptions,
    ConvergenceError,
    continuation,
    switch_branch,
)
from slosh_bif.continuation.branch import Branch
from slosh_bif.continuation.engine import canonical_sign


@dataclasses.dataclass
class Circle:
    """x^2 + p^2 = 1: one closed curve, folds at p = +-1."""

    names = ("x",)

    def residual(self, x, p):
        return np.array([x[0] ** 2 + p**2 - 1])

    def jacobian(self, x, p):
        return np.array([[2 * x[0]]])

    def dparam(self, x, p):
        return np.array([2 * p])


class Cubic:
    """x^3 - x - p = 0: folds at p = +-2/(3 sqrt 3), x = -+1/sqrt 3; as x' = -F, stable where 3x^2 > 1."""

    names = ("x",)

    def residual(self, x, p):
        return np.array([x[0] ** 3 - x[0] - p])

    def jacobian(self, x, p):
        return np.array([[3 * x[0] ** 2 - 1]])

    def dparam(self, x, p):
        return np.array([-1.0])

    def eigenvalues(self, x, p):  # of x' = -F(x, p)
        return np.array([-(3 * x[0] ** 2 - 1)], dtype=complex)


class Pitchfork:
    """p x - x^3 = 0: the trivial branch x = 0 meets x^2 = p at a branch point (0, 0)."""

    names = ("x",)

    def residual(self, x, p):
        return np.array([p * x[0] - x[0] ** 3])

    def jacobian(self, x, p):
        return np.array([[p - 3 * x[0] ** 2]])

    def dparam(self, x, p):
        return np.array([x[0]])


class HalfLine:
    """x - p = 0 defined only for x > 0.3: the branch must end at the domain's edge."""

    names = ("x",)

    def residual(self, x, p):
        return np.array([x[0] - p])

    def jacobian(self, x, p):
        return np.array([[1.0]])

    def dparam(self, x, p):
        return np.array([-1.0])

    def in_domain(self, x, p):
        return x[0] > 0.3


def test_circle_has_two_folds_and_closes():
    branch = continuation(Circle(), [1.0], 0.0, options=ContinuationOptions(step=0.1))
    folds = branch.special_of("LP")
    assert sorted(round(f.p, 12) for f in folds) == [-1.0, 1.0]
    for f in folds:
        assert abs(f.p) == pytest.approx(1.0, abs=1e-12) and f.x[0] == pytest.approx(0.0, abs=1e-9)
    assert branch.status == "ok" and "closed loop" in branch.message
    assert not branch.special_of("END")  # a closed curve has no end
    np.testing.assert_allclose(branch.x[:, 0] ** 2 + branch.p**2, 1.0, atol=1e-10)


def test_cubic_folds_at_plus_minus_2_over_3_sqrt3_with_stability():
    opts = ContinuationOptions(p_min=-1.0, p_max=1.0, step=0.1)
    branch = continuation(Cubic(), [-1.3], (-1.3) ** 3 - (-1.3), options=opts)
    folds = sorted(branch.special_of("LP"), key=lambda f: f.p)
    p_fold = 2 / (3 * np.sqrt(3))
    assert len(folds) == 2
    assert folds[0].p == pytest.approx(-p_fold, abs=1e-8) and folds[1].p == pytest.approx(p_fold, abs=1e-8)
    assert folds[0].x[0] == pytest.approx(1 / np.sqrt(3), abs=1e-9) and folds[1].x[0] == pytest.approx(
        -1 / np.sqrt(3), abs=1e-9
    )
    # Between the folds the middle branch (|x| < 1/sqrt 3) is unstable, the outer ones stable.
    np.testing.assert_array_equal(branch.stable, 3 * branch.x[:, 0] ** 2 - 1 > 0)
    ends = branch.special_of("END")
    assert sorted(e.p for e in ends) == [-1.0, 1.0] and branch.status == "ok"
    assert not branch.special_of("BP")


def test_pitchfork_branch_point_is_detected_and_is_not_a_fold():
    opts = ContinuationOptions(p_min=-1.0, p_max=1.0, step=0.07)
    branch = continuation(Pitchfork(), [0.0], -0.5, options=opts)
    bps = branch.special_of("BP")
    assert len(bps) == 1 and bps[0].p == pytest.approx(0.0, abs=1e-8)
    assert not branch.special_of("LP")


@dataclasses.dataclass
class LineWithGap(HalfLine):
    """x - p = 0 with a gap in its domain, 0.74 < x < 0.76, just short of the bound 0.75."""

    def in_domain(self, x, p):
        return not 0.74 < x[0] < 0.76


def test_a_bound_inside_a_gap_of_the_domain_ends_the_branch_at_the_edge_on_its_last_point():
    """A step from below the gap lands beyond it and the bound: the bound's point lies in the gap,
    where Newton fails, so the branch ends on its last point as at an edge, not on a point outside
    the domain called the bound."""
    branch = continuation(
        LineWithGap(), [0.5], 0.5, options=ContinuationOptions(p_min=0.0, p_max=0.75, step=0.3, step_max=0.3)
    )
    assert all(LineWithGap().in_domain(x, p) for x, p in zip(branch.x, branch.p))
    (end,) = [e for e in branch.special_of("END") if e.p > 0.5]
    assert end.reason == "domain edge" and end.p <= 0.74 and "before the parameter bound" in end.message


class ThinCircle(Circle):
    """The circle with a domain that ends 1e-3 inside it: a chord's point, up to h^2 / 8 inside
    the circle, lies outside the domain for steps longer than 0.09."""

    def in_domain(self, x, p):
        return np.hypot(x[0], p) > 1 - 1e-3


def test_a_bound_whose_chord_point_leaves_a_thin_domain_ends_on_the_curve():
    """Newton at the bound from the chord's point fails at once (outside the domain); from the
    step's own end it lands on the circle at the bound, x = sqrt(1 - p^2)."""
    branch = continuation(
        ThinCircle(),
        [1.0],
        0.0,
        options=ContinuationOptions(p_min=-0.5, p_max=0.5, step=0.3, step_max=0.3, direction="forward"),
    )
    (end,) = [e for e in branch.special_of("END") if e.p > 0]
    assert end.reason == "parameter bound" and end.p == 0.5
    assert end.x[0] == pytest.approx(np.sqrt(0.75), abs=1e-10)


def test_branch_ends_at_the_domain_edge_with_the_reason():
    branch = continuation(HalfLine(), [1.0], 1.0, options=ContinuationOptions(p_max=2.0))
    assert branch.status == "ok"
    ends = branch.special_of("END")
    edge = [e for e in ends if "domain edge" in e.message]
    assert len(edge) == 1 and edge[0].x[0] == pytest.approx(0.3, abs=1e-7)
    assert np.all(branch.x[:, 0] > 0.3)


def test_step_limit_ends_the_branch_with_status():
    branch = continuation(
        HalfLine(), [1.0], 1.0, options=ContinuationOptions(max_steps=3, step=0.01, step_max=0.01)
    )
    assert branch.status == "step limit" and "step limit" in branch.message


def test_bad_start_and_bad_options_fail_before_any_work():
    with pytest.raises(ConvergenceError, match="left the problem's domain"):
        continuation(HalfLine(), [0.5], 0.1)
    with pytest.raises(ValueError, match="option step must be in \\[step_min, step_max\\]"):
        ContinuationOptions(step=2.0, step_max=1.0)
    with pytest.raises(ValueError, match="option direction must be"):
        ContinuationOptions(direction="up")
    with pytest.raises(ValueError, match="outside \\[p_min, p_max\\]"):
        continuation(Cubic(), [0.0], 5.0, options=ContinuationOptions(p_max=1.0))


def test_branch_round_trips_through_npz(tmp_path):
    branch = continuation(Cubic(), [-1.3], (-1.3) ** 3 + 1.3, options=ContinuationOptions(p_min=-1, p_max=1))
    loaded = Branch.load(branch.save(tmp_path / "cubic.npz"))
    for field in ("p", "x", "stable", "eigenvalues", "newton_iterations", "arclength"):
        np.testing.assert_array_equal(getattr(loaded, field), getattr(branch, field))
    assert loaded.special_labels() == branch.special_labels()
    assert [(s.kind, s.index, s.p, s.bracket, s.message) for s in loaded.special] == [
        (s.kind, s.index, s.p, s.bracket, s.message) for s in branch.special
    ]
    assert (loaded.param, loaded.names, loaded.status, loaded.message, loaded.options) == (
        branch.param,
        branch.names,
        branch.status,
        branch.message,
        branch.options,
    )
    for a, b in zip(loaded.special, branch.special):
        np.testing.assert_array_equal(a.tangent, b.tangent)
        assert (a.located, a.reason) == (b.located, b.reason)


def test_special_points_carry_their_tangent_and_ends_their_reason():
    # At a fold of the cubic the tangent is vertical in p: (dx, dp) = (+-1, 0) (closed form).
    branch = continuation(Cubic(), [-1.3], (-1.3) ** 3 + 1.3, options=ContinuationOptions(p_min=-1, p_max=1))
    folds = branch.special_of("LP")
    assert len(folds) == 2
    for fold in folds:
        assert fold.located and abs(fold.tangent[-1]) < 1e-6 and abs(abs(fold.tangent[0]) - 1) < 1e-6
    assert {e.reason for e in branch.special_of("END")} == {"parameter bound"}
    edge = continuation(HalfLine(), [1.0], 1.0, options=ContinuationOptions(p_max=2.0)).special_of("END")
    assert sorted(e.reason for e in edge) == ["domain edge", "parameter bound"]


def test_branch_columns_by_name():
    branch = continuation(Cubic(), [-1.3], (-1.3) ** 3 + 1.3, options=ContinuationOptions(p_min=-1, p_max=1))
    np.testing.assert_array_equal(branch["x"], branch.x[:, 0])
    np.testing.assert_array_equal(branch["p"], branch.p)
    assert branch.columns == ("p", "x")
    with pytest.raises(KeyError, match="its columns are p, x"):
        branch["A"]


def test_switch_branch_leaves_the_trivial_branch_onto_the_parabola():
    """At the pitchfork (0, 0) of p x - x^3 the crossing branch is x^2 = p: every point of the
    switched branch satisfies it, and it starts along x (the new direction, not along p)."""
    opts = ContinuationOptions(p_min=-1.0, p_max=1.0, step=0.07)
    branch = continuation(Pitchfork(), [0.0], -0.5, options=opts)
    bp = branch.special_of("BP")[0]
    new = switch_branch(Pitchfork(), bp, options=opts, along=np.array([0.0, 1.0]))
    assert len(new) > 5 and new.status == "ok"
    np.testing.assert_allclose(new.x[:, 0] ** 2, new.p, atol=1e-10)
    assert abs(new.x[1, 0]) > 0.01 and new.p.max() == pytest.approx(1.0)


@pytest.mark.parametrize("flip", [(1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)])
def test_the_switched_branch_does_not_depend_on_the_signs_the_svd_gives(monkeypatch, flip):
    """Which of the pitchfork's two mirror branches is traced is a rule of the direction (its
    largest component positive: x > 0 here), not the sign of the singular vectors, which LAPACK's
    kernels pick by the CPU: with the two null vectors negated, the same branch, point for point."""
    opts = ContinuationOptions(p_min=-1.0, p_max=1.0, step=0.07)
    bp = continuation(Pitchfork(), [0.0], -0.5, options=opts).special_of("BP")[0]
    plain = switch_branch(Pitchfork(), bp, options=opts, along=np.array([0.0, 1.0]))
    svd = np.linalg.svd

    def flipped(a, *args, **kwargs):
        u, s, vh = svd(a, *args, **kwargs)
        vh = vh.copy()
        vh[-2:] *= np.array(flip)[:, None]
        return u, s, vh

    monkeypatch.setattr(np.linalg, "svd", flipped)
    again = switch_branch(Pitchfork(), bp, options=opts, along=np.array([0.0, 1.0]))
    assert plain.x[1, 0] > 0.01
    np.testing.assert_array_equal(again.x, plain.x)
    np.testing.assert_array_equal(again.p, plain.p)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_the_direction_is_signed_by_its_first_largest_component_ties_within_rounding(sign):
    """A period doubling's two copies have components equal and opposite; rounding makes either
    the larger by 1e-13, and the rule must not follow it: the first of the tied ones is positive."""
    v = sign * np.array([0.5, -(0.5 + 1e-13), 0.1])
    t = canonical_sign(v)
    assert t[0] > 0 and t[1] < 0
    assert np.linalg.norm(t) == pytest.approx(1.0)
    np.testing.assert_allclose(canonical_sign(-v), t)


@pytest.mark.parametrize("x0", [-1.3, -1.1])
def test_a_start_on_a_parameter_bound_is_the_end_and_appears_once(x0):
    bounds = [x**3 - x for x in (-1.3, -1.1)]  # the branch x < -1/sqrt 3 between these two points
    branch = continuation(
        Cubic(), [x0], x0**3 - x0, options=ContinuationOptions(p_min=bounds[0], p_max=bounds[1], step=0.05)
    )
    assert np.all(
        np.linalg.norm(np.diff(np.column_stack([branch.x, branch.p]), axis=0), axis=1) > 1e-6
    )  # no point twice
    assert [e.p for e in branch.special_of("END")] == pytest.approx(bounds) and branch.status == "ok"


@dataclasses.dataclass
class CoarseCircle(Circle):
    """The circle with a Jacobian of the wrong sign on the stretch 0.3 < p < 0.7, x > 0 (a coarse
    evaluation there); ``refined()`` gives the exact one."""

    coarse: bool = True

    def jacobian(self, x, p):
        wrong = self.coarse and abs(p - 0.5) < 0.2 and x[0] > 0
        return np.array([[-2 * x[0] if wrong else 2 * x[0]]])

    def refined(self):
        return CoarseCircle(coarse=False) if self.coarse else None


def test_a_stalled_direction_is_resumed_with_the_problems_finer_version():
    options = ContinuationOptions(step=0.02, step_max=0.05)
    branch = continuation(CoarseCircle(), [1.0], 0.0, options=options)
    assert branch.status == "ok" and "closed loop" in branch.message
    assert "resumed with the finer problem after a stall at p = 0.3" in branch.message
    np.testing.assert_allclose(branch.x[:, 0] ** 2 + branch.p**2, 1.0, atol=1e-10)
    without = dataclasses.replace(CoarseCircle(), coarse=True)
    without.refined = lambda: None  # no finer version: the same stall is reported
    stalled = continuation(without, [1.0], 0.0, options=options)
    assert stalled.status == "step below minimum" and "resumed" not in stalled.message
    assert not np.any(
        (np.abs(stalled.p - 0.5) < 0.18) & (stalled.x[:, 0] > 0)
    )  # both directions stop at the stretch


class LineWithTests(HalfLine):
    """x - p = 0 everywhere, with its own tests: "PD" p - 1/2, and "NS" (p - 1/2)^2 - d^2, which is
    positive at both ends of any step across p = 1/2 longer than 2d, and zero at 1/2 -+ d."""

    test_kinds = ("PD", "NS")

    def __init__(self, d):
        self.d = d

    def in_domain(self, x, p):
        return True

    def test_functions(self, x, p):
        return (p - 0.5, (p - 0.5) ** 2 - self.d**2)


def test_two_crossings_in_one_step_are_found_at_the_point_located_between_them():
    """Steps of 0.1 pass p = 1/2 -+ 1e-4 at once (the NS test has one sign at both ends); the PD
    located between them has the other sign, so both are located on either side of it."""
    opts = ContinuationOptions(step=0.1, step_min=0.1, step_max=0.1, p_min=0.0, p_max=1.0)
    branch = continuation(LineWithTests(1e-4), [0.03], 0.03, options=opts)
    assert [s.kind for s in branch.special if s.kind != "END"] == ["NS", "PD", "NS"]
    np.testing.assert_allclose([s.p for s in branch.special_of("NS")], [0.4999, 0.5001], atol=1e-12)
    assert np.all(np.diff(branch.p) > 0)  # in the branch's order


class RingOnLine:
    """x (x^2 + (p - 1)^2 - 1) = 0: the line x = 0 and the circle of radius 1 about (0, 1), which
    cross at the branch points p = 0 and p = 2 (where the circle turns back in p)."""

    names = ("x",)

    def residual(self, x, p):
        return np.array([x[0] * (x[0] ** 2 + (p - 1) ** 2 - 1)])

    def jacobian(self, x, p):
        return np.array([[3 * x[0] ** 2 + (p - 1) ** 2 - 1]])

    def dparam(self, x, p):
        return np.array([2 * x[0] * (p - 1)])


def test_stop_ends_a_switched_branch_at_the_special_point_it_picks():
    """Switched onto the circle at p = 0, the branch meets the line again at p = 2; a stop at
    branch points past the start ends it there, where without it the branch runs on around the
    circle and closes."""
    opts = ContinuationOptions(p_min=-0.5, p_max=3.0, step=0.05)
    line = continuation(RingOnLine(), [0.0], -0.5, options=opts)
    bp = line.special_of("BP")[0]
    assert bp.p == pytest.approx(0.0, abs=1e-9)
    asked = []

    def stop(kind, x, p, index):
        asked.append(kind)
        return kind == "BP" and index > 1

    cut = switch_branch(RingOnLine(), bp, options=opts, along=np.array([0.0, 1.0]), stop=stop)
    full = switch_branch(RingOnLine(), bp, options=opts, along=np.array([0.0, 1.0]))
    assert asked == ["BP"]
    assert cut.special[-1].kind == "BP" and cut.p[-1] == pytest.approx(2.0, abs=1e-9)
    assert cut.ends == (("forward", "terminal point"),) and cut.status == "ok"
    assert len(full) > 1.5 * len(cut) and full.ends == (("forward", "closed loop"),)
    np.testing.assert_array_equal(full.x[: len(cut) - 1], cut.x[:-1])  # the same steps up to the stop
