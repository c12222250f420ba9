"""Frequency-response curve of the slow flow (45)/(46) for a preset, by pseudo-arclength continuation.

Copy and edit: change PRESET, OVERRIDES and the sigma range. The branch is saved to .npz and the
figure is then drawn from the saved file, to show that re-plotting never recomputes.

Usage: python examples/frc_preset.py [OUT_DIR]
"""

import sys
from pathlib import Path

from slosh_bif import get_preset
from slosh_bif.continuation.branch import Branch
from slosh_bif.slowflow.output import plot_frc, write_frc_csv
from slosh_bif.slowflow.steady_states import FrequencyResponse, frequency_response

PRESET = "fig10"
OVERRIDES = {}  # e.g. {"Abar": 1.5, "gamma": 0.1}
SIGMA_MIN, SIGMA_MAX = -6.0, 8.0


def main(out=Path("results")):
    out.mkdir(parents=True, exist_ok=True)
    params = get_preset(PRESET).params.replace(**OVERRIDES)
    fr = frequency_response(params, sigma_min=SIGMA_MIN, sigma_max=SIGMA_MAX)
    paths = [branch.save(out / f"{PRESET}_branch{k}.npz") for k, branch in enumerate(fr.branches)]
    for branch in fr.branches:
        print(f"{len(branch)} points; {branch.message}")
        for s in branch.special:
            print(f"  {s.kind:3s} sigma = {s.p:+.10f}  A = {s.x[0]:.8f}  ({s.message})")
    reloaded = FrequencyResponse(params, tuple(Branch.load(p) for p in paths), fr.A_min)
    write_frc_csv(reloaded, out / f"{PRESET}_frc.csv")
    plot_frc(reloaded, out / f"{PRESET}_frc.png")
    print(f"wrote {out / f'{PRESET}_frc.csv'} and {out / f'{PRESET}_frc.png'}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results"))
