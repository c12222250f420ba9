"""Pseudo-arclength continuation of any problem F(x, p) = 0; knows nothing of sloshing.

One call joins a problem, options and a result: ``continuation(problem, x0, p0, param=...,
options=ContinuationOptions(...)) -> Branch``. The problem interface is written as types in
:mod:`slosh_bif.continuation.problem`; the slow flow's steady states, the shooting problem of (9),
the orbits of (8) and the bifurcation curves are all such problems.
"""

from slosh_bif.continuation.branch import (
    BRANCH_POINT,
    END,
    FOLD,
    NEIMARK_SACKER,
    PERIOD_DOUBLING,
    Branch,
    Kind,
    SpecialPoint,
    Status,
)
from slosh_bif.continuation.corrector import newton, newton_solve
from slosh_bif.continuation.engine import continuation, switch_branch
from slosh_bif.continuation.options import ContinuationOptions, ConvergenceError
from slosh_bif.continuation.problem import Capabilities, Problem, capabilities
from slosh_bif.newton import NewtonResult as NewtonResult  # documented in slosh_bif.newton

__all__ = [
    "Problem",
    "Capabilities",
    "capabilities",
    "Branch",
    "SpecialPoint",
    "Kind",
    "Status",
    "ContinuationOptions",
    "ConvergenceError",
    "continuation",
    "switch_branch",
    "newton",
    "newton_solve",
    "FOLD",
    "BRANCH_POINT",
    "PERIOD_DOUBLING",
    "NEIMARK_SACKER",
    "END",
]
