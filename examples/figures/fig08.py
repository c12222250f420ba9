"""Fig. 8: the manifold (36) with rho(A) from eq. (39), pbar = -2, 0, 2.

Usage: python examples/figures/fig08.py [OUT_DIR]   (default results/figures)
"""
# Against the paper: The branches differ only near the fold, so a zoomed row is added.

import sys
from pathlib import Path

from slosh_bif.studies.figures import fig8

if __name__ == "__main__":
    print(fig8(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results/figures")))
