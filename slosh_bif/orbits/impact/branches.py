"""Branches of periodic orbits of the vibro-impact model (8) across the edges of their problem.

A continuation of :class:`~slosh_bif.orbits.impact.problem.ImpactOrbitProblem` ends where an impact
reaches the map's section or where the orbit grazes the wall. :func:`trace_impact_orbits` goes on
in pieces, each direction on its own:

* an impact on the section: the section moves to the middle of the orbit's longest flight (the
  same orbits in new coordinates) and the continuation resumes from the located edge point in the
  same direction of the parameter; a start on orbits an earlier piece holds (a closed branch,
  which meets the section at another point each lap) closes the branch as a loop
  (:mod:`slosh_bif.orbits.impact.retrace`);
* grazing (GR): the point is kept; the family on the other side (an impact more or fewer) is
  found on the contact's own unfolding (:mod:`slosh_bif.orbits.impact.grazing_crossing`),
  attracting or not, and the branch goes on from there in the direction that leads away from the
  grazing (back in the parameter where the grazing is a non-smooth fold). Where that fails (two
  contacts grazing at once, say), the map's iterates are tried for an attracting orbit beyond;
  failing both, the branch ends at the grazing with a status that says so. Orbits of the family's
  parent (a shorter period; for an asymmetric family a symmetric orbit) are refused beyond, and
  a grazing on the parent ends the family there, met with its parent
  (:mod:`slosh_bif.orbits.impact.parents`). A grazing met again (or its mirror image) closes the
  branch as a loop.

The result is an :class:`ImpactBranch`: its pieces (each a :class:`~slosh_bif.continuation.Branch`
with its section and impact count), the grazing points, and how each direction ended.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation import (
    Branch,
    ContinuationOptions,
    ConvergenceError,
    continuation,
)
from slosh_bif.continuation.branch import Kind, Status
from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.flows.impact.flow import END_REASONS
from slosh_bif.model.params import Params
from slosh_bif.orbits.impact.grazing_crossing import attracting_beyond, contact_at, cross_grazing
from slosh_bif.orbits.impact.law_corner import (
    CORNER_STEPS,
    across_the_corner,
    at_the_laws_corner,
    corner_message,
    corner_sides,
    without_corner_points,
)
from slosh_bif.orbits.impact.parents import is_asymmetric, parent_met
from slosh_bif.orbits.impact.problem import GRAZING, SECTION, VARIANT_NAMES, ImpactOrbitProblem
from slosh_bif.orbits.impact.retrace import retraced_piece, state_at_phase

__all__ = [
    "ImpactPiece",
    "ImpactBranch",
    "BranchEnd",
    "trace_impact_orbits",
    "quiet_section",
    "settled_orbit",
    "state_at_zero",
]

# the tracer's own end reasons, beside the engine's
GRAZES, PIECES, PARENT = "grazing", "pieces", "parent"
GRAZING_GAP = 1e-4  # an end at the grazing edge is a grazing point within this gap (as a GR curve's start)


@dataclasses.dataclass(frozen=True)
class ImpactPiece:
    """One continuation run: its :class:`Branch`, the section ``phase`` its states sit on, the
    number of impacts per map period on it, and the map's period in forcing periods."""

    branch: Branch
    phase: float
    impacts: int
    period_multiple: int = 1


@dataclasses.dataclass(frozen=True)
class BranchEnd:
    """How one direction ended: ``reason`` a :class:`~slosh_bif.continuation.Status` value, or
    ``"grazing"`` (no orbit found beyond a GR point), ``"parent"`` (a grazing on the family's
    parent, an orbit of a shorter period or a symmetric one: the family meets its parent there) or
    ``"pieces"`` (``max_pieces`` reached)."""

    direction: str
    reason: str
    message: str

    def __str__(self):
        return f"{self.direction}: {self.message}"


@dataclasses.dataclass(frozen=True)
class ImpactBranch:
    """A branch of orbits of (8) in pieces. ``grazing``: (p, x, phase) of each GR point;
    ``ends``: a :class:`BranchEnd` per direction; ``complete``: both reached a bound, closed or met
    their parent (a direction ending at a grazing with no orbit beyond, where the other direction
    closed a loop, is closed too)."""

    param: str
    pieces: tuple
    grazing: tuple
    ends: tuple
    complete: bool
    variant: str = "paper"  # (8) as the paper states it, or "corrected" (ImpactOrbitProblem)

    def special(self, kind: str):
        """(p, message) of every special point of one kind over all pieces (ends excluded)."""
        return [(s.p, s.message) for piece in self.pieces for s in piece.branch.special if s.kind == kind]


def quiet_section(problem: ImpactOrbitProblem, x, p):
    """(phase, state) with the section moved to the middle of the orbit's longest flight."""
    flow = problem.flow_at(p)
    start = problem.phase
    impacts = flow.run(
        np.asarray(x, dtype=float), start, start + problem.period, stick_speed=1e-9, max_impacts=10_000
    )[2]
    if len(impacts) == 0:
        return start, np.asarray(x, dtype=float)
    times = np.concatenate([impacts[:, 0], [impacts[0, 0] + problem.period]])
    k = int(np.argmax(np.diff(times)))
    middle = 0.5 * (times[k] + times[k + 1])
    if middle > start + problem.period:
        middle -= problem.period
    state = (
        flow.run(np.asarray(x, dtype=float), start, middle, stick_speed=1e-9, max_impacts=10_000)[1][:, -1]
        if middle > start
        else np.asarray(x, dtype=float)
    )
    return float(middle % (2 * np.pi)), state


def settled_orbit(params: Params, state0, *, periods: int, tries: int = 4, variant: str = "paper"):
    """A periodic orbit of (8) (its state at tau = 0) that a simulation from ``state0`` settles on:
    Newton on the map from the strobe after ``periods`` forcing periods, then after twice as many
    more, ... (``tries`` times: the early motion can be chaotic for a long time)."""
    problem = ImpactOrbitProblem(params, variant=variant)
    flow = problem.flow_at(params.sigma)
    x, done = np.asarray(state0, dtype=float), 0
    for k in range(tries):
        count = periods * 2**k
        t, y, _, code = flow.run(x, 0.0, 2 * np.pi * count, stick_speed=1e-9, max_impacts=10**7)
        if code != 0:
            raise ConvergenceError(
                f"the simulation of {VARIANT_NAMES[variant]} for a start orbit stopped after "
                f"{done + t[-1] / (2 * np.pi):.0f} periods at sigma = {params.sigma:g}, Abar = "
                f"{params.Abar:g}: {END_REASONS.get(code, f'code {code}')}"
            )
        x, done = y[:, -1], done + count
        run = newton_solve(problem, x, params.sigma, tol=1e-12)
        if run.converged and problem.in_domain(run.x, params.sigma):
            return run.x
    raise ConvergenceError(
        f"no periodic orbit of {VARIANT_NAMES[variant]} near the strobe of a {done}-period simulation "
        f"at sigma = {params.sigma:g}, Abar = {params.Abar:g} (it has not settled)"
    )


def _seen(starts, phase, p, x) -> bool:
    """Whether a piece starting at (phase, p, x) repeats an earlier start, or the mirror image of
    one (the orbit y(tau + pi) -> -y: the same family, traced again). The starts are the last points
    before an impact reached the section, each where the step fell below its minimum, so they match
    only to the corrector's reach: 1e-4 in p and 1e-3 in the state."""
    for f, q, y in starts:
        if abs(p - q) > 1e-4:
            continue
        if abs((phase - f + np.pi) % (2 * np.pi) - np.pi) < 1e-3 and np.linalg.norm(x - y) < 1e-3:
            return True
        if abs((phase - f) % (2 * np.pi) - np.pi) < 1e-3 and np.linalg.norm(x + y) < 1e-3:
            return True
    return False


def _problem(first: ImpactOrbitProblem, phase, x, p):
    probe = first.replace(phase=phase, impacts=None)
    return probe.replace(impacts=len(probe.evaluate(x, p).impacts))


def _far_end(branch: Branch, p0: float, x0):
    """The END point of a one-direction run that is not its start."""
    ends = [s for s in branch.special if s.kind == Kind.END]
    if not ends:
        return None
    return max(ends, key=lambda s: np.linalg.norm(s.x - x0) + abs(s.p - p0))


def trace_impact_orbits(
    params: Params,
    x0,
    *,
    param: str = "sigma",
    p_min: float,
    p_max: float,
    options: ContinuationOptions | None = None,
    symmetric: bool = False,
    period_multiple: int = 1,
    max_pieces: int = 40,
    variant: str = "paper",
) -> ImpactBranch:
    """Continue the orbit of (8) through ``x0`` (its state at tau = 0, a fixed point of the map
    over ``period_multiple`` forcing periods at the value of ``param`` in ``params``) in both
    directions between ``p_min`` and ``p_max``; ``variant`` the impact model
    (:class:`~slosh_bif.orbits.impact.problem.ImpactOrbitProblem`)."""
    opts = dataclasses.replace(
        options or ContinuationOptions(step=0.05, step_max=0.3, tol=1e-10), p_min=p_min, p_max=p_max
    )
    p0 = float(getattr(params, param))
    first = ImpactOrbitProblem(
        params, param, symmetric=symmetric, period_multiple=period_multiple, variant=variant
    )
    run = newton_solve(first, x0, p0, tol=1e-12)
    if not run.converged:
        raise ConvergenceError(
            f"no periodic orbit of {VARIANT_NAMES[variant]} near x0 at {param} = {p0}: {run.message}"
        )
    # an asymmetric family meets its symmetric parent at the parent's grazing (a symmetric orbit
    # may be traced on the whole-period map too)
    asymmetric = is_asymmetric(first, run.x, p0)
    pieces, grazing, ends, starts, contacts, corners = [], [], [], [], [], []
    dead, met = set(), set()  # contacts a direction ended at (nothing beyond), contacts a loop closed at
    for direction in ("forward", "backward"):
        phase, x = quiet_section(first, run.x, p0)
        p, sign = p0, 1.0 if direction == "forward" else -1.0
        problem = _problem(first, phase, x, p)
        step, this_direction = opts.step, len(pieces)  # the index of this direction's first piece
        while True:
            if len(pieces) >= max_pieces:
                ends.append(BranchEnd(direction, PIECES, f"stopped after {max_pieces} pieces"))
                break
            try:
                branch = continuation(
                    problem,
                    x,
                    p,
                    param=param,
                    options=dataclasses.replace(
                        opts, direction="forward" if sign > 0 else "backward", step=min(opts.step, step)
                    ),
                )
            except ConvergenceError as err:
                if not pieces:  # no branch at all
                    raise
                # a piece that cannot start (beyond a section, grazing or corner): the direction ends
                ends.append(BranchEnd(direction, Status.STALL.value, f"a piece at {param} = {p:.10g}: {err}"))
                break
            step = opts.step
            branch = without_corner_points(problem, branch)
            pieces.append(ImpactPiece(branch, problem.phase, problem.impacts, period_multiple))
            end = _far_end(branch, p, x)
            # a run stalls at the law's corner, or creeps up to it as to a grazing (an impact at
            # v_min has a grazing gap of v_min^2 / 2a, small)
            stopped = end is not None and (
                end.reason == Status.STALL.value or (end.reason == Status.EDGE.value and end.edge == GRAZING)
            )
            if stopped and at_the_laws_corner(problem, end.x, end.p):
                before = pieces[-2] if len(pieces) - 2 >= this_direction else None
                earlier = (
                    None
                    if before is None
                    else (first.replace(phase=before.phase, impacts=before.impacts), before.branch)
                )
                beyond = across_the_corner(problem, branch, end, (p_min, p_max), earlier)
                # the same corner crossed to the same sides again is a loop; a pair of impacts at
                # the corner together crosses it twice, a hair apart, to other sides
                key = None if beyond is None else corner_sides(problem, beyond[0], beyond[1])
                if beyond is not None and not any(
                    k == key and abs(end.p - q) <= 1e-6 * (1 + abs(q)) for q, k in corners
                ):
                    corners.append((end.p, key))
                    x, p, sign = beyond
                    step = CORNER_STEPS[-1]  # the branch beyond turns within a hair of the corner
                    continue
                ends.append(BranchEnd(direction, end.reason, end.message + corner_message(problem, end.p)))
                break
            if end is None or end.reason != Status.EDGE.value or end.edge not in (SECTION, GRAZING):
                reason = (
                    end.reason if end is not None else (branch.ends[-1][1] if branch.ends else branch.status)
                )
                ends.append(BranchEnd(direction, reason, end.message if end is not None else branch.message))
                break
            x_end, p_end = end.x, end.p
            sign = 1.0 if end.tangent is None or end.tangent[-1] >= 0 else -1.0
            if end.edge == SECTION:
                phase, x = quiet_section(problem, x_end, p_end)
                p = p_end
                problem = _problem(first, phase, x, p)
                # a closed branch meets the section at another point each lap: its start repeats
                # no earlier one but lies on an earlier lap's piece (the last piece ends here)
                if _seen(starts, phase, p, x) or retraced_piece(problem, x, p, pieces[:-1]) is not None:
                    ends.append(
                        BranchEnd(
                            direction,
                            Status.LOOP.value,
                            f"closed loop (back on the orbits of {param} = {p:.10g}, or their mirror images)",
                        )
                    )
                    break
                starts.append((phase, p, x))
                continue
            graze = problem.grazing(x_end, p_end)
            if not abs(graze.gap) < GRAZING_GAP:  # an end named for the grazing edge, not on it
                ends.append(
                    BranchEnd(direction, end.reason, f"{end.message} (not on it: a gap of {graze.gap:.3g})")
                )
                break
            contact = contact_at(problem, x_end, p_end, graze)
            seen = [i for i, (c, q) in enumerate(contacts) if contact.same_as(c, p_end, q)]
            if seen:
                met.add(seen[0])
                ends.append(
                    BranchEnd(
                        direction,
                        Status.LOOP.value,
                        f"closed loop (back at the grazing of {param} = {p_end:.10g}, or at its "
                        "mirror image)",
                    )
                )
                break
            contacts.append((contact, p_end))
            grazing.append((p_end, x_end, problem.phase))
            beyond = cross_grazing(problem, x_end, p_end, opts, contact, asymmetric) or attracting_beyond(
                problem, x_end, p_end, sign, opts, asymmetric
            )
            if beyond is None:
                ends.append(_dead_end(problem, x_end, p_end, direction, param, asymmetric))
                if ends[-1].reason == GRAZES:
                    dead.add(len(contacts) - 1)
                break
            problem, x, p, sign = beyond
    # a direction that ended at a grazing with nothing beyond, where the other direction closed
    # (at it or its mirror image), ends a loop through that grazing: nothing of the branch is left
    complete = all(
        e.reason in (Status.BOUND.value, Status.LOOP.value, PARENT) or (e.reason == GRAZES and dead <= met)
        for e in ends
    )
    return ImpactBranch(param, tuple(pieces), tuple(grazing), tuple(ends), complete, variant)


def _dead_end(problem, x, p, direction, param, asymmetric) -> BranchEnd:
    """How a direction ends at the grazing (x, p) with no orbit found beyond it: on its family's
    parent (:func:`~slosh_bif.orbits.impact.parents.parent_met`: the orbits the unfolding finds
    beyond are the parent's), or with nothing beyond."""
    parent = parent_met(problem, x, p, asymmetric)
    if parent is not None:
        return BranchEnd(
            direction,
            PARENT,
            f"grazing at {param} = {p:.10g} on {parent}: the family meets its parent at the parent's grazing",
        )
    return BranchEnd(
        direction,
        GRAZES,
        f"grazing at {param} = {p:.10g}; no orbit with another impact count found beyond it",
    )


def state_at_zero(problem: ImpactOrbitProblem, x, p):
    """The state at tau = 0 of the orbit through x on the problem's section (see
    :func:`~slosh_bif.orbits.impact.retrace.state_at_phase`)."""
    return state_at_phase(problem, x, p, 0.0)
