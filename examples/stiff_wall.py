"""How far the wall of (9) is from the rigid wall of (8) with eq. (21), as the wall stiffens.

For each wall exponent n, the wall of (9) is measured by single contacts
(:func:`slosh_bif.model.restitution.wall.wall_law`): its restitution kappa_wall and the clearance
D(v0) of the equivalent rigid wall, against (21)'s kappa (the rigid wall of (8) is at D = 1).
Both differences shrink like 1/n: (8) with (21) is (9)'s stiff-wall limit.

Usage: python examples/stiff_wall.py [--preset fig13] [--n 6,20,50,100,200,500]   (1-2 s a wall)
Prints a Markdown table (docs/findings/impact.md, "Towards the stiff-wall limit").
"""

import argparse

from slosh_bif import get_preset
from slosh_bif.model.restitution.eq21 import kappa
from slosh_bif.model.restitution.wall import wall_law

SPEEDS = (0.3, 1.0, 3.0)


def main(argv=None):
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--preset", default="fig13")
    parser.add_argument("--n", default="6,20,50,100,200,500", help="wall exponents, comma-separated")
    args = parser.parse_args(argv)
    P = get_preset(args.preset).params
    print(
        f"wall of the {args.preset} set: lam = {P.lam:g}, chi = {P.chi:g}, pbar = {P.pbar}; "
        "kappa at unit speed"
    )
    print("| n | kappa_wall | kappa (21) | gap | " + " | ".join(f"D({v:g}) - 1" for v in SPEEDS) + " |")
    print("| --- " * (4 + len(SPEEDS)) + "|")
    for n in (int(k) for k in args.n.split(",")):
        law = wall_law(P.lam, P.chi, n, P.pbar, 0.1, 10.0, nodes=16)
        k_wall, k21 = float(law.kappa(1.0)), float(kappa(1.0, P.lam, P.chi, n, P.pbar))
        clearance = " | ".join(f"{float(law.clearance(v)) - 1:.3f}" for v in SPEEDS)
        print(f"| {n} | {k_wall:.3f} | {k21:.3f} | {k_wall - k21:.3f} | {clearance} |")


if __name__ == "__main__":
    main()
