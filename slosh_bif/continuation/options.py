"""Options, end reasons and the start failure of a continuation run.

The end reasons are one table: a branch whose directions all end for a reason in
:data:`COMPLETE` has status "ok"; any other reason becomes the branch's status.
"""

from __future__ import annotations

import dataclasses
import math

from slosh_bif.continuation.branch import Status

__all__ = [
    "ContinuationOptions",
    "ConvergenceError",
    "BOUND",
    "EDGE",
    "LOOP",
    "TERMINAL",
    "STEPS",
    "STALL",
    "TIME",
    "COMPLETE",
]

# End reasons of one direction; the first four make a complete branch (status "ok").
BOUND, EDGE, LOOP, TERMINAL = Status.BOUND.value, Status.EDGE.value, Status.LOOP.value, Status.TERMINAL.value
STEPS, STALL, TIME = Status.STEPS.value, Status.STALL.value, Status.TIME.value
COMPLETE = (BOUND, EDGE, LOOP, TERMINAL)


class ConvergenceError(RuntimeError):
    """The starting point could not be corrected onto the solution curve."""


@dataclasses.dataclass(frozen=True)
class ContinuationOptions:
    """Step control and tolerances; validated on construction (errors name the option).

    Attributes
    ----------
    step, step_min, step_max : float
        Initial, smallest and largest arclength step.
    max_steps : int
        Accepted steps per direction at most.
    p_min, p_max : float
        Bounds of the continued parameter.
    tol : float
        Newton stops when |F| <= tol and the update <= tol * (1 + |u|).
    max_newton : int
        Corrector iterations before a step counts as failed.
    growth : float
        Step factor after an easy step (<= 3 iterations).
    max_angle : float
        The tangent may turn by about this much (radians) per step: the next step is scaled to
        it, and a step turning by more than twice as much is redone, so curves stay smooth
        through sharp peaks.
    direction : str
        "both", "forward" (increasing p at the start) or "backward".
    detect_folds, detect_branch_points : bool
        Locate LP / BP.
    locate_tol : float
        Arclength tolerance when locating a special point.
    max_seconds : float
        An outer safety net of wall-clock time per direction (none by default): past it the
        direction ends ("time limit"). What a run computes is bounded by counts (``max_steps``,
        ``max_newton``, the step halvings down to ``step_min``), never by this: a result cut by
        the clock depends on the machine's load, and says so in its status.
    curved_predictor : bool
        Predict along the cubic through the last two points and their tangents (third order;
        else the tangent plus the turn seen over the last step) rather than along the tangent
        alone (:mod:`slosh_bif.continuation.predictor`).
    """

    step: float = 0.05
    step_min: float = 1e-9
    step_max: float = 0.5
    max_steps: int = 5000
    p_min: float = -math.inf
    p_max: float = math.inf
    tol: float = 1e-11
    max_newton: int = 12
    growth: float = 1.6
    max_angle: float = 0.1
    direction: str = "both"
    detect_folds: bool = True
    detect_branch_points: bool = True
    locate_tol: float = 1e-13
    max_seconds: float = math.inf
    curved_predictor: bool = True

    def __post_init__(self):
        def need(ok, name, allowed):
            if not ok:
                raise ValueError(f"option {name} must be {allowed}; got {getattr(self, name)!r}")

        need(
            0 < self.step_min <= self.step <= self.step_max < math.inf,
            "step",
            "in [step_min, step_max], all positive and finite",
        )
        need(isinstance(self.max_steps, int) and self.max_steps >= 1, "max_steps", "an integer >= 1")
        need(self.p_min < self.p_max, "p_min", "< p_max")
        need(0 < self.tol < 1e-2, "tol", "in (0, 1e-2)")
        need(isinstance(self.max_newton, int) and self.max_newton >= 2, "max_newton", "an integer >= 2")
        need(1 < self.growth <= 4, "growth", "in (1, 4]")
        need(0 < self.max_angle <= math.pi / 2, "max_angle", "in (0, pi/2]")
        need(
            self.direction in ("both", "forward", "backward"), "direction", "'both', 'forward' or 'backward'"
        )
        need(0 < self.locate_tol < 1e-3, "locate_tol", "in (0, 1e-3)")
        need(self.max_seconds > 0, "max_seconds", "> 0 (inf for no limit)")
