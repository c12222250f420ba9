"""Critical forcing Abar_b(sigma): below it no steady state exists on the stable manifold branch.

Two-parameter continuation of the fold condition and of the end-point condition (A = A_min);
the curve is the least of the two at each sigma. Copy and edit PRESET and the range.

Usage: python examples/critical_curve.py [OUT_DIR]
"""

import sys
from pathlib import Path

from slosh_bif import get_preset
from slosh_bif.slowflow.critical import critical_curve, critical_forcing
from slosh_bif.slowflow.output import plot_critical, write_critical_csv

PRESET = "fig13"
SIGMA_MIN, SIGMA_MAX = -6.0, 8.0


def main(out=Path("results")):
    out.mkdir(parents=True, exist_ok=True)
    params = get_preset(PRESET).params
    curve = critical_curve(params, SIGMA_MIN, SIGMA_MAX)
    write_critical_csv(curve, out / f"{PRESET}_critical.csv")
    plot_critical(curve, out / f"{PRESET}_critical.png")
    point = critical_forcing(params, params.sigma)
    print(
        f"{len(curve.sigma)} points; at sigma = {params.sigma}: Abar_b = {point.Abar_b:.10f} "
        f"({point.kind}, A = {point.A:.6f})"
    )
    print(f"wrote {out / f'{PRESET}_critical.csv'} and {out / f'{PRESET}_critical.png'}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results"))
