"""A settled forced record of the smooth model (9), for the worked example of `slosh-bif fit
--record steady` (docs/findings/identify.md): the Fig. 10 set at eps = 0.04, beta = 0.1, n = 20,
lam = 0.4, gamma = 0.25, sigma = -1, simulated by scipy's DOP853 on (9) (not the package's
integrator) from rest until one period's map moves the state by less than 1e-9, then three
forcing periods sampled 48 times each, with 1 % of the record's amplitude as Gaussian noise
(seeded) and that std in a column. With ``--sigmas`` a record at each of several forcing
frequencies, with a sigma column (the noise 1 % of the largest amplitude among them).

    python examples/steady_record.py --out docs/identify/steady/record.csv
    slosh-bif fit --preset fig10 --set eps=0.06 --set beta=0.1 --set n=20 --set lam=0.6 \
        --set gamma=0.15 --set sigma=-1 --data docs/identify/steady/record.csv --record steady \
        --free lam,gamma,eps --out docs/identify/steady/fit
    python examples/steady_record.py --sigmas=-1,0.6 --out docs/identify/steady/two/record.csv
    slosh-bif fit --preset fig10 --set eps=0.06 --set beta=0.1 --set n=20 --set lam=0.6 \
        --set gamma=0.15 --data docs/identify/steady/two/record.csv --record steady \
        --free lam,gamma,eps --out docs/identify/steady/two/fit
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from slosh_bif import get_preset
from slosh_bif.model.equations import SmoothModel

TRUTH = dict(eps=0.04, beta=0.1, n=20, lam=0.4, gamma=0.25, sigma=-1.0)
PERIODS, SAMPLES, NOISE = 3, 48, 0.01


def settled_record(params, periods=PERIODS, samples=SAMPLES, most=2000):
    """(tau, X) over ``periods`` forcing periods of the orbit (9) settles on from rest."""
    model = SmoothModel(params)
    y = np.zeros(4)
    for k in range(most):
        run = solve_ivp(model.rhs, (0.0, 2 * np.pi), y, method="DOP853", rtol=1e-12, atol=1e-13)
        moved = np.abs(run.y[:, -1] - y).max()
        y = run.y[:, -1]
        if moved < 1e-9:
            break
    else:
        raise SystemExit(f"(9) did not settle in {most} periods (last move {moved:.2g})")
    tau = np.arange(periods * samples) * (2 * np.pi / samples)
    run = solve_ivp(model.rhs, (0.0, tau[-1]), y, method="DOP853", rtol=1e-12, atol=1e-13, t_eval=tau)
    return tau, run.y[0], k + 1


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True, help="CSV to write (tau, X, std[, sigma])")
    parser.add_argument("--seed", type=int, default=0, help="seed of the noise (default 0)")
    parser.add_argument(
        "--sigmas",
        default=None,
        help="comma-separated forcing frequencies: a record at each (default: -1 alone)",
    )
    args = parser.parse_args(argv)
    sigmas = [float(text) for text in args.sigmas.split(",")] if args.sigmas else [TRUTH["sigma"]]
    params = get_preset("fig10").params.replace(**TRUTH)
    records = [settled_record(params.replace(sigma=sigma)) for sigma in sigmas]
    std = float(NOISE * max(np.abs(X).max() for _, X, _ in records))
    rng = np.random.default_rng(args.seed)
    column = len(sigmas) > 1 or args.sigmas is not None
    rows = []
    for sigma, (tau, X, settled) in zip(sigmas, records):
        noisy = X + rng.normal(0.0, std, size=len(X))
        tail = f",{sigma!r}" if column else ""
        rows += [f"{float(t)!r},{float(x)!r},{std!r}{tail}\n" for t, x in zip(tau, noisy)]
        print(f"sigma = {sigma:g}: {len(tau)} samples after {settled} periods")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("tau,X,std" + (",sigma" if column else "") + "\n" + "".join(rows))
    print(f"wrote {args.out}; truth {TRUTH | {'sigma': sigmas}}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
