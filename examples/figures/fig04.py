"""Fig. 4: the modal masses m_1, m_2, m_3 and the fixed mass m_0 of an upright cylinder over the
liquid's mass, against the depth ratio h/r (slosh_bif.model.tank).

Usage: python examples/figures/fig04.py [OUT_DIR]   (default results/figures)
"""
# Against the paper: computed from the potential-flow series (the paper reads Abramson's chart);
# checked against mpmath's Bessel zeros and the series in 40 digits in tests/model/test_tank.py.

import sys
from pathlib import Path

from slosh_bif.studies.figures import fig4

if __name__ == "__main__":
    print(fig4(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results/figures")))
