"""The stiff-wall limit orbit by orbit: (9)'s orbits against the corrected impact model's and (8)'s
as the wall exponent n grows (:mod:`slosh_bif.studies.stiff_wall`).

Usage: python examples/stiff_wall_orbits.py [--preset fig10] [--sigmas -5,-3,3,6,8]
       [--n 20,50,100,200,500] [--figure docs/figures/stiff_wall_orbits.png]   (20 s)
       python examples/stiff_wall_orbits.py --simplifications [--preset fig13] [--sigmas ...]
Prints a Markdown table (docs/findings/impact.md, "The stiff-wall limit, orbit by orbit") and
draws the errors against n on log axes; with --simplifications, what (8)'s difference to (9) is
made of at the set's n (its flights, its wall).
"""

import argparse
import sys

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from slosh_bif import get_preset  # noqa: E402
from slosh_bif.studies.stiff_wall import (  # noqa: E402
    markdown_table,
    simplifications,
    simplifications_table,
    stiff_wall_points,
)


def _figure(points, path):
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    sigmas = list(dict.fromkeys(p.sigma for p in points))
    colors = plt.cm.viridis(np.linspace(0, 0.9, len(sigmas)))
    for sigma, color in zip(sigmas, colors):
        rows = [p for p in points if p.sigma == sigma and p.status == "ok"]
        n = [p.n for p in rows]
        ax.loglog(n, [p.corrected_error for p in rows], "o-", color=color, label=f"sigma = {sigma:g}")
        ax.loglog(n, [p.paper_error for p in rows], "s--", color=color, alpha=0.6)
    ns = sorted({p.n for p in points})
    ax.set_xticks(ns, [str(n) for n in ns])
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.set_xlabel("wall exponent n")
    ax.set_ylabel("|A1 - A1 of (9)| / A1 of (9)")
    ax.set_title("(9) against the corrected impact model (solid) and (8) (dashed)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main(argv=None):
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--preset", default="fig10")
    parser.add_argument("--sigmas", default="-5,-3,3,6,8")
    parser.add_argument("--n", default="20,50,100,200,500")
    parser.add_argument("--figure", default=None, help="write the errors against n here (PNG)")
    parser.add_argument(
        "--simplifications",
        action="store_true",
        help="instead: at the set's n, (9) against the impact models with either flights and either wall",
    )
    args = parser.parse_args(argv)
    params = get_preset(args.preset).params
    if args.simplifications:
        print(simplifications_table(simplifications(params, [float(s) for s in args.sigmas.split(",")])))
        return
    points = stiff_wall_points(
        params,
        [float(s) for s in args.sigmas.split(",")],
        [int(n) for n in args.n.split(",")],
        progress=lambda p: print(f"sigma = {p.sigma:g}, n = {p.n}: {p.status}", file=sys.stderr),
    )
    print(markdown_table(points))
    if args.figure:
        _figure(points, args.figure)
        print(f"wrote {args.figure}", file=sys.stderr)


if __name__ == "__main__":
    main()
