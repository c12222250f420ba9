"""A free decay of the vibro-impact model (8), for the worked example of `slosh-bif fit` on a record
in time (docs/findings/identify.md): the Fig. 10 set with the forcing off, the vessel started at
X = 3 at rest with the particle in the middle, simulated by the exact flow of (8) over tau in
[0, 400], X sampled every 0.05.

    python examples/free_decay.py --out docs/identify/decay/fig10-decay.csv
    slosh-bif fit --preset fig10 --set lam=0.5 --set gamma=0.15 --data docs/identify/decay/fig10-decay.csv \
        --free lam,gamma --out docs/identify/decay/fit

With ``--noise LEVEL`` Gaussian noise of LEVEL times the start's 3 is added (seeded by ``--seed``)
and written as a std column; by the trajectory of (8) itself up to its horizon:

    python examples/free_decay.py --tau 120 --noise 0.01 --out docs/identify/decay/noisy.csv
    slosh-bif fit --preset fig10 --set lam=0.5 --set gamma=0.15 --data docs/identify/decay/noisy.csv \
        --free lam,gamma --model impact --out docs/identify/decay/noisy-fit
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from slosh_bif import get_preset
from slosh_bif.flows.impact.flow import ImpactFlow

STEP = 0.05


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True, help="CSV to write (tau, X)")
    parser.add_argument("--tau", type=float, default=400.0, help="length of the record (default 400)")
    parser.add_argument("--noise", type=float, default=0.0, help="noise's std over the start's X (default 0)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the noise (default 0)")
    args = parser.parse_args(argv)
    params = get_preset("fig10").params.replace(Abar=0.0)
    t, y, impacts, code = ImpactFlow(params, STEP).run(
        np.array([3.0, 0.0, 0.0, 0.0]), 0.0, args.tau, stick_speed=1e-9, max_impacts=10**6
    )
    if code != 0:
        raise SystemExit(f"the simulation of (8) stopped early (code {code})")
    grid = np.arange(0.0, args.tau, STEP)
    X = np.interp(grid, t, y[0])  # the sample times with the impact instants, back on the grid
    args.out.parent.mkdir(parents=True, exist_ok=True)
    if args.noise > 0:
        std = args.noise * 3.0
        noisy = X + np.random.default_rng(args.seed).normal(0.0, std, size=len(X))
        args.out.write_text(
            "tau,X,std\n" + "".join(f"{a:.6f},{b:.7g},{std:g}\n" for a, b in zip(grid, noisy))
        )
    else:
        args.out.write_text("tau,X\n" + "".join(f"{a:.6f},{b:.7g}\n" for a, b in zip(grid, X)))
    print(f"wrote {args.out}: {len(grid)} samples, {len(impacts)} impacts; truth lam = 0.35, gamma = 0.2")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
