"""Eq. (21) against a direct simulation of one particle rebounding in the wall of eq. (10).

Writes restitution_check.csv and restitution_check.png into the folder given (default: results/)
and prints the table. The error kappa_sim - kappa_21 is second order in the dissipation
delta = 1 - kappa_21**2; at pbar = 0 it is about delta**2/4 = pi**2 lam**2 / (4 chi (n+1)).

Usage: python examples/restitution_check.py [OUT_DIR]
"""

import csv
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from slosh_bif.model import restitution  # noqa: E402

CHI, V0 = 0.2, 1.0
LAMS = (0.01, 0.02, 0.05, 0.1, 0.2, 0.35)
CASES = [(6, 0), (10, 0), (50, 0), (6, -2), (6, 2), (50, -2), (50, 2)]


def main(out=Path("results")):
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for n, pbar in CASES:
        for lam in LAMS:
            try:
                k21 = float(restitution.kappa(V0, lam, CHI, n, pbar))
            except ValueError:
                continue  # kappa not real for this lam: no rebound law to compare
            ksim = restitution.simulate_rebound(V0, lam, CHI, n, pbar)
            delta = 1 - k21**2
            rows.append(
                dict(
                    n=n,
                    pbar=pbar,
                    lam=lam,
                    kappa_21=k21,
                    kappa_sim=ksim,
                    error=ksim - k21,
                    error_over_delta2=(ksim - k21) / delta**2,
                )
            )
    with open(out / "restitution_check.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(
        f"{'n':>3} {'pbar':>4} {'lam':>5} {'kappa_21':>10} {'kappa_sim':>10} {'error':>10} "
        f"{'err/delta^2':>11}"
    )
    for r in rows:
        print(
            f"{r['n']:>3} {r['pbar']:>4} {r['lam']:>5} {r['kappa_21']:>10.6f} "
            f"{r['kappa_sim']:>10.6f} {r['error']:>10.3e} {r['error_over_delta2']:>11.4f}"
        )
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for n, pbar in CASES:
        sel = [r for r in rows if r["n"] == n and r["pbar"] == pbar]
        ax.loglog(
            [1 - r["kappa_21"] ** 2 for r in sel],
            [r["error"] for r in sel],
            "o-",
            label=f"n={n}, pbar={pbar}",
        )
    d = [1e-3, 1.0]
    ax.loglog(d, [x**2 / 4 for x in d], "k--", label=r"$\delta^2/4$")
    ax.set_xlabel(r"dissipation $\delta = 1-\kappa_{21}^2$ at $v_0 = 1$")
    ax.set_ylabel(r"$\kappa_{sim} - \kappa_{21}$")
    ax.set_title(f"Eq. (21) against a rebound simulation (chi = {CHI})")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "restitution_check.png", dpi=120)
    print(f"wrote {out / 'restitution_check.csv'} and {out / 'restitution_check.png'}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results"))
