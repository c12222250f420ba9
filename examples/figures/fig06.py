"""Fig. 6: the slow invariant manifold (36) for kappa = 0.729.

Usage: python examples/figures/fig06.py [OUT_DIR]   (default results/figures)
"""
# Against the paper: Differs from the caption: kappa = 0.729 gives A_min = 0.0993, not the printed 0.06
# (alpha_min = 0.990 agrees). beta = 0.2 in the caption does not enter (36).

import sys
from pathlib import Path

from slosh_bif.studies.figures import fig6

if __name__ == "__main__":
    print(fig6(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results/figures")))
