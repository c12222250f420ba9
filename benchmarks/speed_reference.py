"""The yardsticks of the speed issues, measured in the same run as what they measure.

* :func:`one_period_reference`: the speed issue's reference, one forcing period of (9) on the
  Fig. 10 set at sigma = 3 (n = 50, or another n) from a state on its attractor, integrated by
  scipy's ``solve_ivp(method="DOP853", rtol=1e-10, atol=1e-12)`` as one call; the median over 5
  repetitions of the mean of 20 calls. A target "x 1,000 periods" is 1,000 times this.
* :func:`chained_reference`: the earlier reference, 1,000 periods chained from the preset's
  state (a transient first, so slower per period).
* :func:`stage_profile` and :func:`first_newton`: where a whole-process ``slosh-bif`` run spends
  its time (imports, the start orbit, the continuation, the orbit measures, the plot), and how
  long a ``shoot`` run takes from the interpreter's start to its first Newton step.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import time

import numpy as np

from slosh_bif.model.equations import SmoothModel
from slosh_bif.model.presets import get_preset
from slosh_bif.simulation.direct import simulate

__all__ = [
    "one_period_reference",
    "chained_reference",
    "stage_profile",
    "first_newton",
    "run_child",
    "STAGES",
]


def _scipy_period(model, y0):
    from scipy.integrate import solve_ivp

    with np.errstate(all="ignore"):  # rejected trial steps into the wall overflow harmlessly
        return solve_ivp(model.rhs, (0.0, 2 * np.pi), y0, method="DOP853", rtol=1e-10, atol=1e-12)


def one_period_reference(n: int = 50, repeats: int = 5, calls: int = 20) -> float:
    """Seconds of one reference period (see the module docstring); the attractor's state is that
    of a 200-period compiled simulation from the preset's state at sigma = 3."""
    params = get_preset("fig10").params.replace(sigma=3.0, n=n)
    y0 = simulate(params, get_preset("fig10").state_for(params), 400 * np.pi).y[:, -1].copy()
    model = SmoothModel(params)
    _scipy_period(model, y0)
    means = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(calls):
            _scipy_period(model, y0)
        means.append((time.perf_counter() - start) / calls)
    return statistics.median(means)


def chained_reference(params, y0, count: int = 1000) -> float:
    """Seconds of ``count`` one-period integrations chained from y0 (the earlier reference)."""
    model = SmoothModel(params)
    start = time.perf_counter()
    y = np.asarray(y0, dtype=float)
    for _ in range(count):
        y = _scipy_period(model, y).y[:, -1]
    return time.perf_counter() - start


STAGES = (
    "imports",
    "start orbit",
    "continuation",
    "orbit measures and files",
    "plot",
    "rest",
    "interpreter and unmeasured",
)

_PROFILE = """
import sys, time
t0 = time.perf_counter()
marks = []
import slosh_bif.cli as cli
import slosh_bif.orbits.families as fam, slosh_bif.report.plot_process as pp
marks.append(time.perf_counter())
trace, result = fam.continuation, pp.PlotProcess.result
def continuation(*a, **k):
    marks.append(time.perf_counter()); r = trace(*a, **k); marks.append(time.perf_counter()); return r
def plot_result(self):  # the wait for the figure (drawn by a child that imported matplotlib meanwhile)
    marks.append(time.perf_counter()); r = result(self); marks.append(time.perf_counter()); return r
fam.continuation, pp.PlotProcess.result = continuation, plot_result
sys.argv = ['slosh-bif', *sys.argv[1:]]
def done():
    print('stage_marks', t0, *marks, time.perf_counter(), file=sys.stderr)
import atexit; atexit.register(done)
cli.run()  # the console entry: its exit functions, then it leaves
"""


def run_child(code, arguments, timeout):
    """(wall seconds, completed process) of ``python -c CODE ARGUMENTS`` with warnings silenced."""
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-c", code, *arguments],
        capture_output=True,
        text=True,
        timeout=timeout,
        env={**os.environ, "PYTHONWARNINGS": "ignore"},
    )
    return time.perf_counter() - start, done


def stage_profile(arguments, timeout: float = 900.0) -> dict:
    """Seconds per stage (:data:`STAGES`) of ``slosh-bif ARGUMENTS`` (a ``shoot`` of one family of
    (9)) in a fresh interpreter; the continuations of all its branches are added up. "plot" is
    the wait for the figure once the files are written (a child forked at the start imports
    matplotlib and draws it: see :mod:`slosh_bif.report.plot_process`)."""
    wall, done = run_child(_PROFILE, arguments, timeout)
    line = next((x for x in done.stderr.splitlines() if x.startswith("stage_marks")), None)
    if line is None:
        raise RuntimeError(f"slosh-bif {' '.join(arguments)} failed: {done.stderr.strip()[-300:]}")
    t0, imported, *middle, end = map(float, line.split()[1:])
    *traced, (plot_start, plot_end) = zip(middle[0::2], middle[1::2])  # continuations, then the plot
    tracing = sum(b - a for a, b in traced)
    seconds = {
        "imports": imported - t0,
        "start orbit": traced[0][0] - imported,
        "continuation": tracing,
        "orbit measures and files": plot_start - traced[0][0] - tracing,  # and switching, if any
        "plot": plot_end - plot_start,
        "rest": end - plot_end,
    }
    seconds["interpreter and unmeasured"] = wall - (end - t0)
    return seconds


_FIRST_NEWTON = """
import os, sys, time
import slosh_bif.newton as newton
def first(*a, **k):
    print('first_newton', file=sys.stderr, flush=True)
    os._exit(0)
newton.newton_loop = first
sys.argv = ['slosh-bif', *sys.argv[1:]]
import slosh_bif.cli as cli
cli.main()
"""


def first_newton(arguments, timeout: float = 300.0) -> float:
    """Wall seconds from launching ``slosh-bif ARGUMENTS`` to its first Newton step, interpreter
    start included: read when the step announces itself, not when the pipes close (the figure's
    process, forked at the start, holds them open while it imports matplotlib)."""
    start = time.perf_counter()
    child = subprocess.Popen(
        [sys.executable, "-c", _FIRST_NEWTON, *arguments],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONWARNINGS": "ignore"},
    )
    lines = []
    try:
        for line in child.stderr:
            if line.startswith("first_newton"):
                return time.perf_counter() - start
            lines.append(line)
            if time.perf_counter() - start > timeout:
                break
    finally:
        child.kill()
        child.wait()
        child.stderr.close()
    raise RuntimeError(f"slosh-bif {' '.join(arguments)} reached no Newton step: {''.join(lines)[-300:]}")
