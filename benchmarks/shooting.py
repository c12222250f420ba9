"""Speed target of the shooting issue, and the integrators charted speed against accuracy.

1. The whole symmetric branch of 2pi-orbits of (9) for the Fig. 10 set (n = 50, Abar = 3) over
   sigma in [-6, 8], every special point located (multiple shooting, 4 arcs, compiled DOP853),
   against 1,000 one-period integrations of (9) by scipy's solve_ivp DOP853 at rtol = 1e-10,
   atol = 1e-12, measured in the same run (the bar is the ratio, not seconds).
2. Work-precision of one period of (9) at n = 50 and n = 6 for every integrator (the integration
   question of `python -m benchmarks`, :func:`benchmarks.integration.integration_bench`). Writes
   OUT/integrators.png, integrators.csv and integrators_ratios.csv (OUT: results/charts by default).

Run:  python -m benchmarks.shooting [--repeats 3] [--out results/charts]
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from benchmarks.run import run
from slosh_bif import SmoothModel, get_preset
from slosh_bif.continuation import continuation
from slosh_bif.flows.smooth import integrator
from slosh_bif.orbits.families import SHOOTING_OPTIONS
from slosh_bif.orbits.orbit_tools import orbit_at
from slosh_bif.orbits.shooting import ShootingProblem

FIG10_ORBIT_GUESS = np.array([-2.29697839, 0.4870925, 0.62950163, -1.6026986])  # a simulated state


def one_period_scipy(params, y0):
    model = SmoothModel(params)
    return solve_ivp(model.rhs, (0.0, 2 * np.pi), y0, method="DOP853", rtol=1e-10, atol=1e-12)


def speed_target(repeats):
    P = get_preset("fig10").params
    y0 = get_preset("fig10").state0
    one_period_scipy(P, y0)
    baseline = []
    for _ in range(repeats):
        t = time.perf_counter()
        for _ in range(100):
            one_period_scipy(P, y0)
        baseline.append((time.perf_counter() - t) * 10)  # scaled to 1,000 integrations
    problem = ShootingProblem(P, segments=4)
    orbit_at(problem, problem.initial_states(FIG10_ORBIT_GUESS), 1.0)  # compile/load outside the timing
    branch_times, branch = [], None
    for _ in range(repeats):
        problem = ShootingProblem(P, segments=4)
        t = time.perf_counter()
        start = orbit_at(problem, problem.initial_states(FIG10_ORBIT_GUESS), 1.0, tol=1e-9)
        branch = continuation(
            problem,
            problem.initial_states(start.y0),
            1.0,
            param="sigma",
            options=dataclasses.replace(SHOOTING_OPTIONS, p_min=-6.0, p_max=8.0),
        )
        branch_times.append(time.perf_counter() - t)
    base, mine = np.median(baseline), np.median(branch_times)
    print(f"1,000 one-period DOP853 integrations (scipy, rtol 1e-10): median {base:.2f} s (of {repeats})")
    print(
        f"whole symmetric branch, sigma in [-6, 8]: median {mine:.2f} s, {len(branch)} points, "
        f"{problem.evaluations} arc integrations,"
    )
    print("  special points: " + ", ".join(f"{s.kind} {s.p:.5f}" for s in branch.special))
    print(f"ratio branch / baseline = {mine / base:.3f} (target < 1)")
    return base, mine


def main():
    np.seterr(all="ignore")  # scipy's trial steps deep in the wall overflow; the error control rejects them
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--out", type=Path, default=Path("results/charts"))
    args = parser.parse_args()
    if not integrator.HAVE_NUMBA:
        print("numba is not installed: the compiled path is unavailable (pip install -e '.[fast]')")
    speed_target(args.repeats)
    for path in run(
        args.out, only=["integration"], repeats=args.repeats
    ):  # the same chart as `python -m benchmarks`
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
