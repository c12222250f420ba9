"""A measured-like frequency response of the smooth model (9) at a parameter set that is not a
preset: an up-sweep and a down-sweep of settled 2pi-orbits, as a slow experiment makes them (at
each sigma the vessel starts from the last orbit's state; where that orbit has gone or lost its
stability it settles on another attractor), integrated by scipy's DOP853 only (not the fit's
compiled path), with seeded noise of a stated size. The first-harmonic amplitude A1 of X is the
measured A (eq. 25).

    python examples/sweep_response.py --out results/sweep.csv [--noise 0.01] [--seed 1]

writes ``sigma, A, std, sweep`` (std the noise's size when it is not 0) and prints the truth.
The identify page's example (``docs/identify/sweep/response.csv``) is this script's default run.
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np

from slosh_bif import get_preset
from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.orbits.orbit_tools import orbit_measures
from slosh_bif.orbits.shooting import ShootingProblem
from slosh_bif.simulation.direct import simulate
from slosh_bif.simulation.settings import SimulationSettings

# A set that is no preset: a lighter, softer wall and a more damped vessel than Fig. 10's.
TRUTH = get_preset("fig10").params.replace(eps=0.05, beta=0.3, gamma=0.3, lam=0.3, chi=0.2, n=20, Abar=2.0)
SIGMAS = np.linspace(1.6, 5.0, 10)
SETTLE = 300  # forcing periods a jump is given to settle
SCIPY = SimulationSettings(backend="scipy", rtol=1e-9, atol=1e-11, sample_step=np.pi / 8)


def _settled_orbit(problem, state, sigma):
    """(x, A1) of the stable orbit Newton finds from ``state`` (the vessel's state at tau = 0), or
    from the strobe of a simulation from it settled over SETTLE periods."""
    for attempt in range(2):
        x = problem.initial_states(state, sigma)
        run = newton_solve(problem, x, sigma, tol=1e-10, max_iter=30, criterion="residual")
        if run.converged and problem.is_stable(problem.eigenvalues(run.x, sigma)):
            return run.x, orbit_measures(problem, run.x, sigma)["A1"]
        if attempt == 0:
            at = problem.params.replace(sigma=float(sigma))
            state = simulate(at, state, 2 * np.pi * SETTLE, settings=SCIPY).y[:, -1]
    raise RuntimeError(f"no stable orbit settled at sigma = {sigma:g}")


def sweep(params, sigmas, state):
    """A1 along ``sigmas`` in their order, each orbit started from the last one's state."""
    out = []
    for s in sigmas:
        problem = ShootingProblem(params.replace(sigma=float(s)), segments=4, backend="scipy")
        x, A1 = _settled_orbit(problem, state, s)
        state = x[:4]
        out.append(A1)
    return np.array(out)


def response(params=TRUTH, sigmas=SIGMAS, noise=0.01, seed=1):
    """(sigma, A, std, sweep) of an up-sweep then a down-sweep over ``sigmas``; the noise's size
    is ``noise`` times the largest amplitude (std None without noise)."""
    start = simulate(
        params.replace(sigma=float(sigmas[0])), [0.0, 0.0, 0.0, 0.0], 2 * np.pi * SETTLE, settings=SCIPY
    )
    up = sweep(params, sigmas, start.y[:, -1])
    top = params.replace(sigma=float(sigmas[-1]))
    problem = ShootingProblem(top, segments=4, backend="scipy")
    down = sweep(params, sigmas[::-1], problem.initial_states(start.y[:, -1], sigmas[-1])[:4])[::-1]
    sigma = np.concatenate([sigmas, sigmas])
    A = np.concatenate([up, down])
    size = noise * float(A.max())
    A = A + np.random.default_rng(seed).normal(0.0, size, A.size) if noise > 0 else A
    sweeps = ("up",) * len(sigmas) + ("down",) * len(sigmas)
    return sigma, A, (np.full(A.size, size) if noise > 0 else None), sweeps


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, required=True, help="the CSV to write")
    parser.add_argument("--noise", type=float, default=0.01, help="noise std over the largest amplitude")
    parser.add_argument("--seed", type=int, default=1, help="the noise's seed")
    args = parser.parse_args(argv)
    sigma, A, std, sweeps = response(noise=args.noise, seed=args.seed)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with open(args.out, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["sigma", "A", "std", "sweep"] if std is not None else ["sigma", "A", "sweep"])
        for k in range(len(sigma)):
            row = [repr(float(sigma[k])), repr(float(A[k]))]
            writer.writerow(row + ([repr(float(std[k]))] if std is not None else []) + [sweeps[k]])
    print(f"{args.out}: the truth {TRUTH}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
