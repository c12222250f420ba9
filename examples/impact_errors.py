"""The slow flow's error and the wall's error told apart, orbit by orbit.

At each sigma the stable steady state of the slow flow (46), the stable periodic orbit of the
vibro-impact model (8) and the stable 2pi-orbit of the smooth model (9) on their primary branches
(first-harmonic amplitude A1 of X; A for the slow flow): (46) against (8) is the asymptotic error
of the multiple-scales expansion alone (both have the same rigid wall and restitution law (21)),
(8) against (9) is the error of the rigid-wall idealisation at this n, and (46) against (9) both.
A sigma where one model has no stable state, or several, is left out of that model's columns.

Usage: python examples/impact_errors.py [OUT_DIR] [--preset fig13] [--sigma-min -3] [--sigma-max 5] [--points
17]   (about 15 s)
Writes OUT_DIR/impact_errors.csv (default OUT_DIR: results/impact_errors) and prints the table.
"""

import argparse
from pathlib import Path

import numpy as np

from slosh_bif.continuation import ContinuationOptions
from slosh_bif.model.presets import get_preset
from slosh_bif.orbits import NO_SWITCHING
from slosh_bif.orbits.families import trace_orbits
from slosh_bif.orbits.impact.branches import settled_orbit, trace_impact_orbits
from slosh_bif.orbits.impact.output import impact_rows
from slosh_bif.orbits.settings import ParameterRange
from slosh_bif.orbits.starts import start_orbit
from slosh_bif.report.tables import write_rows
from slosh_bif.slowflow.steady_states import frequency_response
from slosh_bif.studies.compare import impact_orbits_at, orbits_at, states_at


def _stable_one(values):
    """The value of the one stable entry of (value, stable, ...) tuples, or NaN."""
    stable = [v[0] for v in values if v[1]]
    return stable[0] if len(stable) == 1 else float("nan")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="results/impact_errors")
    parser.add_argument("--preset", default="fig13")
    parser.add_argument("--sigma-min", type=float, default=-3.0)
    parser.add_argument("--sigma-max", type=float, default=5.0)
    parser.add_argument("--points", type=int, default=17)
    args = parser.parse_args(argv)
    preset = get_preset(args.preset)
    params, lo, hi = preset.params, args.sigma_min, args.sigma_max
    sigmas = np.linspace(lo, hi, args.points)

    slow = frequency_response(params, sigma_min=lo, sigma_max=hi)
    fine = ContinuationOptions(step=0.02, step_max=0.05, tol=1e-10)  # A1 read between points to about 1e-4
    impact = trace_impact_orbits(
        params, settled_orbit(params, preset.state0, periods=150), p_min=lo, p_max=hi, options=fine
    )
    rows8 = list(impact_rows(impact, params))
    start = start_orbit(params, preset.state0, (lo, hi))
    smooth = trace_orbits(
        start.params, start.y0, branching=NO_SWITCHING, interval=ParameterRange(name="sigma", lo=lo, hi=hi)
    )

    table = []
    for sigma in sigmas:
        A = _stable_one(states_at(slow, sigma))
        A8 = _stable_one(impact_orbits_at(rows8, sigma))
        A9 = _stable_one(orbits_at(smooth.branches, sigma))
        table.append(
            dict(
                sigma=sigma,
                A_46=A,
                A1_8=A8,
                A1_9=A9,
                asymptotic=abs(A - A8) / A8,
                wall=abs(A8 - A9) / A9,
                total=abs(A - A9) / A9,
            )
        )
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_rows(table, list(table[0]), out / "impact_errors.csv")
    print(
        f"{'sigma':>6} {'A (46)':>9} {'A1 (8)':>9} {'A1 (9)':>9} {'(46)-(8)':>9} {'(8)-(9)':>9} "
        f"{'(46)-(9)':>9}"
    )
    for r in table:
        print(
            f"{r['sigma']:6.2f} {r['A_46']:9.4f} {r['A1_8']:9.4f} {r['A1_9']:9.4f} "
            f"{r['asymptotic']:9.2%} {r['wall']:9.2%} {r['total']:9.2%}"
        )
    for key, name in (
        ("asymptotic", "(46) against (8), the expansion"),
        ("wall", "(8) against (9), the wall"),
        ("total", "(46) against (9), both"),
    ):
        values = np.array([r[key] for r in table])
        values = values[np.isfinite(values)]
        if values.size:
            print(f"median {name}: {np.median(values):.2%} over {values.size} sigmas")
    print(f"wrote {out / 'impact_errors.csv'}")


if __name__ == "__main__":
    main()
