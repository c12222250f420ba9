"""Fig. 7: restitution coefficient kappa against amplitude A on S+ (eq. 39).

Usage: python examples/figures/fig07.py [OUT_DIR]   (default results/figures)
"""
# Against the paper: Same trend as printed: kappa does not depend on A for pbar = 0 (eq. 40).

import sys
from pathlib import Path

from slosh_bif.studies.figures import fig7

if __name__ == "__main__":
    print(fig7(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results/figures")))
