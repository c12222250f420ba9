"""``python -m benchmarks --out DIR``, from the root of a source checkout: the work-precision
charts and speed ratios of :func:`benchmarks.run.run`, each written as a CSV and a chart. The
benchmarks are the project's, not the installed package's: the package does not know they exist."""

from __future__ import annotations

import argparse
import sys

from benchmarks.run import BASE, QUESTIONS, run
from slosh_bif.cli.common import out_path, progress

MAX_REPEATS = 100  # timing rounds per benchmark point: the median of 100 is as good as it gets


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m benchmarks",
        description="work-precision charts: the frequency-response question, the integrators, the cost "
        "of growth, the speed ratios (a few minutes; the speed targets about half an hour)",
    )
    parser.add_argument("--out", type=out_path, required=True, help="output folder (created if missing)")
    parser.add_argument("--only", nargs="+", default=None, choices=QUESTIONS, help="only these benchmarks")
    parser.add_argument(
        "--repeats", type=int, default=3, help="timing rounds per point; the median is reported (default 3)"
    )
    parser.add_argument(
        "--quick", action="store_true", help="fewer points and one round (a smoke test, not a measurement)"
    )
    parser.add_argument(
        "--base",
        default=BASE,
        metavar="COMMIT",
        help=f"the commit 'against' measures this tree against (default {BASE})",
    )
    args = parser.parse_args(argv)
    if not 1 <= args.repeats <= MAX_REPEATS:
        parser.error(f"--repeats takes an integer in [1, {MAX_REPEATS}]; got {args.repeats}")
    chosen = dict(only=args.only, quick=args.quick, repeats=args.repeats, progress=progress, base=args.base)
    for path in run(args.out, **chosen):
        print(path)
        if path.name == "integrators_ratios.csv":  # the headline numbers
            print(path.read_text().strip())
    return 0


if __name__ == "__main__":
    sys.exit(main())
