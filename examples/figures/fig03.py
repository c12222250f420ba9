"""Fig. 3: the integral I(n, p) and I(n, pbar) of eqs. (18)-(19).

Usage: python examples/figures/fig03.py [OUT_DIR]   (default results/figures)
"""
# Against the paper: Matches the paper: eq. (19) is verified against quadrature in tests/test_restitution.py.

import sys
from pathlib import Path

from slosh_bif.studies.figures import fig3

if __name__ == "__main__":
    print(fig3(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results/figures")))
