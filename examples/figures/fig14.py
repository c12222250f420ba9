"""Fig. 14: the excitation of eq. (47) and its spectrum.

Usage: python examples/figures/fig14.py [OUT_DIR]   (default results/figures)
"""
# Against the paper: Differs by design: band-limited noise (std 4, cutoff 10, seed 0) replaces one random draw
# per integration step, which made the paper's forcing depend on the step (slosh_bif/noise.py).

import sys
from pathlib import Path

from slosh_bif.studies.figures import fig14

if __name__ == "__main__":
    print(fig14(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results/figures")))
