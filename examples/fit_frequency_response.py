"""Synthetic measurements of a frequency response, for the worked example of `slosh-bif fit`
(docs/findings/identify.md): the stable steady states of the slow flow (45) on the Fig. 10 set,
continued in sigma, nearest 25 detunings over [-4, 4] (23 distinct points), with Gaussian noise
of 1 % of the largest amplitude (seeded) and that standard deviation as the std column.

    python examples/fit_frequency_response.py --out docs/identify/fig10-response.csv
    slosh-bif fit --preset fig10 --set lam=0.5 --set gamma=0.15 --data docs/identify/fig10-response.csv \
        --free lam,chi,gamma --out docs/identify/fig10-fit

With ``--from-compare FILE`` the points are instead the stable orbits of the full model (9) that
``slosh-bif compare`` wrote (their A1, over sigma in [-4, 4], no noise): what fitting a system
that behaves as (9) does by the slow flow gives (its bias):

    python examples/fit_frequency_response.py --from-compare docs/compare/fig10/compare.csv \
        --out docs/identify/fig10-smooth-response.csv

and ``--column A1_impact`` takes the orbits of the vibro-impact model (8) instead (over sigma in
[3.5, 8], where the compare has them):

    python examples/fit_frequency_response.py --from-compare docs/compare/fig10-impact/compare.csv \
        --column A1_impact --out docs/identify/fig10-impact-response.csv
"""

from __future__ import annotations

import argparse
import csv
import warnings
from pathlib import Path

import numpy as np

from slosh_bif import get_preset
from slosh_bif.slowflow.flow import AsymptoticsWarning
from slosh_bif.slowflow.steady_states import frequency_response


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True, help="CSV to write (sigma, A, std)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the noise (default 0)")
    parser.add_argument(
        "--noise", type=float, default=0.01, help="noise, a fraction of the largest amplitude"
    )
    parser.add_argument("--from-compare", type=Path, help="compare.csv of (9)'s orbits to take A1 from")
    parser.add_argument(
        "--column", default="A1_stable_orbit", help="the compare's column (A1_stable_orbit or A1_impact)"
    )
    args = parser.parse_args(argv)
    if args.from_compare is not None:
        return _from_compare(args.from_compare, args.out, args.column)
    params = get_preset("fig10").params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        response = frequency_response(params, sigma_min=-4.0, sigma_max=4.0)
    sigma = np.concatenate([b.p[b.stable] for b in response.branches])
    A = np.concatenate([b.x[b.stable, 0] for b in response.branches])
    picks = sorted({int(np.argmin(np.abs(sigma - s))) for s in np.linspace(-4.0, 4.0, 25)})
    sigma, A = sigma[picks], A[picks]
    size = args.noise * A.max()
    measured = A + np.random.default_rng(args.seed).normal(0.0, size, A.size)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    rows = "".join(f"{s:.6f},{a:.6f},{size:.6f}\n" for s, a in zip(sigma, measured))
    args.out.write_text("sigma,A,std\n" + rows)
    print(
        f"wrote {args.out}: {len(sigma)} points, noise {size:.3g} (seed {args.seed}); truth lam = "
        f"{params.lam}, chi = {params.chi}, gamma = {params.gamma}"
    )
    return 0


def _from_compare(source: Path, out: Path, column: str) -> int:
    with open(source, newline="") as fh:
        rows = [r for r in csv.DictReader(fh) if r[column] not in ("", "nan")]
    # (9)'s stable orbits over [-4, 4]; (8)'s where the compare has them
    low, high = (-4.0, 4.0) if column == "A1_stable_orbit" else (-np.inf, np.inf)
    points = [(float(r["sigma"]), float(r[column])) for r in rows if low <= float(r["sigma"]) <= high]
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("sigma,A\n" + "".join(f"{s:.6f},{a:.8f}\n" for s, a in points))
    print(f"wrote {out}: {len(points)} stable orbits ({column}) from {source}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
