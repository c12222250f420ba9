"""Pseudo-arclength continuation of any problem F(x, p) = 0; knows nothing of sloshing.

One call joins a problem, options and a result: ``continuation(problem, x0, p0, param=...,
options=ContinuationOptions(...)) -> Branch``. The problem protocol is described in
:mod:`slosh_bif.continuation.engine`; the slow flow's steady states and the full model's
shooting problem are both such problems.
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
from slosh_bif.continuation.corrector import NewtonResult, newton, newton_solve
from slosh_bif.continuation.engine import continuation, switch_branch
from slosh_bif.continuation.options import ContinuationOptions, ConvergenceError

__all__ = [
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
    "NewtonResult",
    "FOLD",
    "BRANCH_POINT",
    "PERIOD_DOUBLING",
    "NEIMARK_SACKER",
    "END",
]
