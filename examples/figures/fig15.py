"""Fig. 15: Fig. 10's parameters with the noise of eq. (47).

Usage: python examples/figures/fig15.py [OUT_DIR]   (default results/figures)
"""
# Against the paper: sigma_bar is not printed (4 assumed, as Fig. 14). With cutoff 10 the envelope varies by
# about 50 %, more than the paper's 'no major qualitative difference'.

import sys
from pathlib import Path

from slosh_bif.studies.figures import fig15

if __name__ == "__main__":
    print(fig15(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results/figures")))
