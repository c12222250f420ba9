"""Fig. 5: f(T0) = (2 alpha/pi) arcsin(cos(T0 - eta)) of the multiple-scales ansatz, alpha = 1, eta = pi/2.

Usage: python examples/figures/fig05.py [OUT_DIR]   (default results/figures)
"""
# Against the paper: as printed; its Fourier series (42) is checked in tests/slowflow/test_flow.py.

import sys
from pathlib import Path

from slosh_bif.studies.figures import fig5

if __name__ == "__main__":
    print(fig5(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results/figures")))
