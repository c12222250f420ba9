"""Fig. 10: the 'resonant periodic' response, tau in [1100, 1200].

Usage: python examples/figures/fig10.py [OUT_DIR]   (default results/figures)
"""
# Against the paper: Differs in kind: in (9) this response is 1:1 resonant with near-constant amplitude but
# not
# periodic; the 2pi-orbit is unstable (multiplier 16; sigma = 1 lies beyond the NS point 0.881
# and the fold 0.924 of the shooting branch). About 3.4 impacts a period, not 2.

import sys
from pathlib import Path

from slosh_bif.studies.figures import fig10

if __name__ == "__main__":
    print(fig10(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results/figures")))
