"""What the commands share: the parameter and range options, progress on stderr, list parsing."""

from __future__ import annotations

import sys
from pathlib import Path

from slosh_bif.model.presets import PRESETS, get_preset

__all__ = ["add_params_options", "add_range_options", "params_of", "sigma_range", "progress", "throttled", "floats"]


def add_params_options(parser):
    parser.add_argument("--preset", required=True, choices=sorted(PRESETS), help="parameter set of a figure of the paper")
    parser.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="override one parameter (repeatable), e.g. --set Abar=2 --set n=10",
    )


def add_range_options(parser):
    parser.add_argument("--sigma-min", type=float, default=None, help="lower end of the sigma range (default -6)")
    parser.add_argument("--sigma-max", type=float, default=None, help="upper end of the sigma range (default 8)")
    parser.add_argument("--out", type=Path, required=True, help="output folder (created if missing)")


def params_of(args):
    return get_preset(args.preset).params.with_overrides(args.overrides)


def sigma_range(args, default=(-6.0, 8.0)):
    lo = default[0] if args.sigma_min is None else args.sigma_min
    hi = default[1] if args.sigma_max is None else args.sigma_max
    if not lo < hi:
        raise ValueError(f"--sigma-min must be below --sigma-max; got {lo} and {hi}")
    return lo, hi


def progress(message):
    print(f"  {message}", file=sys.stderr, flush=True)


def throttled(report, every=1.0, *, passes=lambda message: "point" not in message):
    """A progress callback that passes on at most one message a second (and every message for
    which ``passes`` is true: by default each that is not about a single point, e.g. a new branch)."""
    import time

    last = [-1e9]

    def callback(message):
        now = time.monotonic()
        if now - last[0] >= every or passes(message):
            last[0] = now
            report(message)

    return callback


def floats(text):
    return [float(v) for v in text.split(",")]
