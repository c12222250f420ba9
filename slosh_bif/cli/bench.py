"""``slosh-bif bench``: a thin entry to the benchmarks, which live beside the package in the source
checkout's ``benchmarks/`` folder (as scipy keeps its own)."""

from __future__ import annotations

import sys
from pathlib import Path

from slosh_bif.cli.common import out_path, progress

__all__ = ["add_commands"]

MAX_REPEATS = 100  # timing rounds per benchmark point: the median of 100 is as good as it gets


def _benchmarks():
    """``benchmarks.run`` of the checkout this package runs from; a one-line error without one."""
    import slosh_bif

    root = Path(slosh_bif.__file__).resolve().parents[1]
    if not (root / "benchmarks" / "run.py").is_file():
        raise ValueError(
            f"the benchmarks live in a source checkout's benchmarks/ folder, and there is none beside "
            f"this installation ({root}): install the package from a clone (pip install -e .)"
        )
    if str(root) not in sys.path:
        sys.path.insert(0, str(root))
    import benchmarks.run

    return benchmarks.run


def _bench(args) -> int:
    run = _benchmarks().run

    if not 1 <= args.repeats <= MAX_REPEATS:
        raise ValueError(f"--repeats takes an integer in [1, {MAX_REPEATS}]; got {args.repeats}")
    paths = run(args.out, only=args.only, quick=args.quick, repeats=args.repeats, progress=progress)
    for path in paths:
        print(path)
        if path.name == "integrators_ratios.csv":  # the headline numbers
            print(path.read_text().strip())
    return 0


def add_commands(sub) -> None:
    bench = sub.add_parser(
        "bench",
        help="work-precision charts: frequency-response question, integrators, cost of growth (a few "
        "minutes)",
    )
    bench.add_argument("--out", type=out_path, required=True, help="output folder (created if missing)")
    bench.add_argument(
        "--only",
        nargs="+",
        default=None,
        choices=("frequency-response", "integration", "growth", "speed"),
        help="only these benchmarks",
    )
    bench.add_argument(
        "--repeats", type=int, default=3, help="timing rounds per point; the median is reported (default 3)"
    )
    bench.add_argument(
        "--quick", action="store_true", help="fewer points and one round (a smoke test, not a measurement)"
    )
    bench.set_defaults(run=_bench)
