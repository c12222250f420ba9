"""Cost of a point on a two-parameter curve against a point of a one-parameter orbit branch.

The Fig. 10 set (n = 50): the symmetric branch of 2pi-orbits over sigma in [-1.6, 1.2] at
Abar = 3, and the fold (LP), pitchfork (BP) and Neimark-Sacker (NS) curves through its special
points over sigma in [-2, 3], Abar in [0.5, 6]. Both by multiple shooting (4 arcs, compiled DOP853); medians
of 3 runs in one process.
Prints the seconds per point of each and the ratios (issue 16's target: at most 3).

Run:  python -m benchmarks.codim2
"""

from __future__ import annotations

import time

import numpy as np

from slosh_bif import get_preset
from slosh_bif.orbits import (
    NO_SWITCHING,
    ShootingSettings,
    orbit_from_simulation,
    trace_orbits,
)
from slosh_bif.orbits.codim2 import CurveSeed, trace_curve
from slosh_bif.orbits.settings import ParameterRange


def _median_per_point(run, repeats=3):
    samples = []
    for _ in range(repeats):
        started = time.perf_counter()
        points = run()
        samples.append((time.perf_counter() - started) / points)
    return float(np.median(samples)), points


def main():
    preset = get_preset("fig10")
    P = preset.params
    start = orbit_from_simulation(P.replace(sigma=-1.2), preset.state0, settle=150)

    def branch():
        family = trace_orbits(
            start.params,
            start.y0,
            shooting=ShootingSettings(points_per_2pi=64),
            branching=NO_SWITCHING,
            interval=ParameterRange(lo=-1.6, hi=1.2),
        )
        branch.result = family.branches[0]
        return len(family.branches[0])

    per_branch_point, n_branch = _median_per_point(branch)
    print(
        f"one-parameter branch: {n_branch} points, {1e3 * per_branch_point:.2f} ms a point (orbit "
        "measures included)"
    )
    # The fold at -1.40, the pitchfork at -1.09 and the Neimark-Sacker point at 0.88 of that branch.
    for kind, near in (("LP", -1.40027), ("BP", -1.09022), ("NS", 0.88058)):
        sp = [s for s in branch.result.branch.special if s.kind == kind and abs(s.p - near) < 1e-3][0]

        def curve():
            return len(
                trace_curve(
                    P,
                    CurveSeed(kind, sp.x, sp.p),
                    box={"sigma": (-2.0, 3.0), "Abar": (0.5, 6.0)},
                    shooting=ShootingSettings(points_per_2pi=64),
                )
            )

        per_curve_point, n_curve = _median_per_point(curve)
        print(
            f"{kind} curve: {n_curve} points, {1e3 * per_curve_point:.2f} ms a point, "
            f"{per_curve_point / per_branch_point:.2f}x a branch point (target <= 3)"
        )


if __name__ == "__main__":
    main()
