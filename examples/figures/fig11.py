"""Fig. 11: non-resonant responses, beta = 0 and 0.3, with Morlet wavelet plots.

Usage: python examples/figures/fig11.py [OUT_DIR]   (default results/figures)
"""
# Against the paper: As printed. Our wavelet plot is amplitude-normalised (a cosine of amplitude a reads a).

import sys
from pathlib import Path

from slosh_bif.studies.figures import fig11

if __name__ == "__main__":
    print(fig11(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results/figures")))
