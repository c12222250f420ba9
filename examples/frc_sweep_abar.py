"""A family of frequency-response curves for increasing forcing Abar, on one figure.

Each curve is a full continuation; values below the critical forcing at every sigma in the
range have no curve at all. Copy and edit PRESET and ABARS.

Usage: python examples/frc_sweep_abar.py [OUT_DIR]
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from slosh_bif import get_preset  # noqa: E402
from slosh_bif.report.plotting import plot_branch  # noqa: E402
from slosh_bif.slowflow.steady_states import frequency_response  # noqa: E402

PRESET = "fig13"
ABARS = (0.5, 0.75, 1.0, 1.5, 2.0, 3.0)
SIGMA_MIN, SIGMA_MAX = -4.0, 4.0


def main(out=Path("results")):
    out.mkdir(parents=True, exist_ok=True)
    base = get_preset(PRESET).params
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for k, abar in enumerate(ABARS):
        try:
            fr = frequency_response(base.replace(Abar=abar), sigma_min=SIGMA_MIN, sigma_max=SIGMA_MAX)
        except ValueError as err:
            print(f"Abar = {abar}: {err}")
            continue
        for j, branch in enumerate(fr.branches):
            plot_branch(
                ax,
                branch,
                branch.x[:, 0],
                color=f"C{k}",
                label=f"Abar = {abar:g}" if j == 0 else None,
                label_ends=False,
            )
        print(
            f"Abar = {abar}: {sum(len(b) for b in fr.branches)} points, folds at sigma = "
            f"{[round(s.p, 6) for b in fr.branches for s in b.special_of('LP')]}"
        )
    ax.set_xlabel(r"detuning $\sigma$")
    ax.set_ylabel("amplitude A of X")
    ax.set_title(f"Frequency response on S+ for several forcing amplitudes ({PRESET}; dashed: unstable)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / f"{PRESET}_frc_sweep.png", dpi=120)
    print(f"wrote {out / f'{PRESET}_frc_sweep.png'}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results"))
