"""Fig. 12: the chaotic strongly modulated response (n = 6).

Usage: python examples/figures/fig12.py [OUT_DIR]   (default results/figures)
"""
# Against the paper: As printed (classified strongly-modulated). With n = 6 eq. (21)'s kappa (0.27) is far
# from
# the wall's (0.63), so the impact model (8) modulates differently from (9).

import sys
from pathlib import Path

from slosh_bif.studies.figures import fig12

if __name__ == "__main__":
    print(fig12(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results/figures")))
