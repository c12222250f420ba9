"""What the commands share: parameter, range and continuation options (one meaning each in
every command), progress on stderr, list parsing, deprecated spellings."""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import math
import sys
from pathlib import Path

from slosh_bif.cli.terminal import REPORTER
from slosh_bif.model.params import FIELDS
from slosh_bif.model.presets import CLASSIFY_TMAX, PRESETS, get_preset

__all__ = [
    "Deprecated",
    "abar_range",
    "add_abar_range_options",
    "add_continuation_options",
    "add_params_options",
    "add_range_options",
    "add_sigma_points_option",
    "continuation_options",
    "floats",
    "out_path",
    "params_of",
    "preset_of",
    "progress",
    "sigma_range",
    "state0_of",
    "throttled",
]


class Deprecated(argparse.Action):
    """An old spelling of an option: stores into the new option's ``dest`` and says so once."""

    def __init__(self, option_strings, dest, new=None, **kwargs):
        self.new = new
        super().__init__(option_strings, dest, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None):
        print(f"slosh-bif: note: {option_string} is deprecated; use {self.new}", file=sys.stderr)
        setattr(namespace, self.dest, values)


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread like Ctrl-C's KeyboardInterrupt, so that one path stops
    workers, keeps what is done and exits (143 instead of 130)."""

    signal_name = "SIGTERM"


# values along one axis of a map (regimes, basins): 2000 x 2000 cells is days of work on 2 cores
MAX_GRID = 2000
MAX_WORKERS = 256  # local worker processes: beyond that, a cluster (--scheduler) is the way
MAX_SIGMA_POINTS = 100_000  # sigma values a comparison samples: far past any branch's resolution


def out_path(text: str) -> Path:
    """--out as a Path; an empty one (Path("") is the current folder) is a slip, refused."""
    if not text.strip():
        raise argparse.ArgumentTypeError("needs a folder or file name; got an empty string")
    return Path(text)


def check_workers(args) -> None:
    """--workers: None (one per core) or an integer in [1, MAX_WORKERS]; checked before any work."""
    if args.workers is not None and not 1 <= args.workers <= MAX_WORKERS:
        raise ValueError(f"--workers takes an integer in [1, {MAX_WORKERS}]; got {args.workers}")


def check_sigma_points(args) -> None:
    """--sigma-points of a comparison: an integer in [2, MAX_SIGMA_POINTS]."""
    if not 2 <= args.sigma_points <= MAX_SIGMA_POINTS:
        raise ValueError(
            f"--sigma-points must be an integer >= 2 and <= {MAX_SIGMA_POINTS}; got {args.sigma_points}"
        )


def stopped(status: str) -> KeyboardInterrupt:
    """The exception a command raises after writing a partial result whose ``status`` says why."""
    return Terminated(status) if "SIGTERM" in status else KeyboardInterrupt(status)


def add_params_options(parser):
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--preset", choices=sorted(PRESETS), help="parameter set of a figure of the paper")
    source.add_argument(
        "--params",
        type=Path,
        metavar="FILE",
        help="parameter file (TOML or JSON: a [params] table, or a [tank] table converted from a real "
        "tank; see `slosh-bif tank`)",
    )
    parser.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help=f"override one parameter (repeatable), e.g. --set Abar=2 --set n=10; names: {', '.join(FIELDS)}",
    )


def add_range_options(parser):
    parser.add_argument(
        "--sigma-min", type=float, default=None, help="lower end of the sigma range (default -6)"
    )
    parser.add_argument(
        "--sigma-max", type=float, default=None, help="upper end of the sigma range (default 8)"
    )
    parser.add_argument("--out", type=out_path, required=True, help="output folder (created if missing)")


def add_model_option(parser):
    """``--model slowflow|corrected``: which slow flow (eq. 46 as derived, or with the wall's own
    restitution and clearance, :mod:`slosh_bif.model.restitution.corrected`)."""
    parser.add_argument(
        "--model",
        choices=("slowflow", "corrected"),
        default="slowflow",
        help="slow flow: eq. (46) as derived (default, the paper's) or 'corrected' (kappa and clearance "
        "of the wall of (9), measured per impact speed)",
    )


def add_impact_model_option(parser) -> None:
    """``--impact-model paper|corrected``: which impact model ``--impact`` adds."""
    help_ = "with --impact: (8) as stated (default) or the corrected impact model ((9) with its wall's law)"
    parser.add_argument("--impact-model", choices=("paper", "corrected"), default="paper", help=help_)


def check_impact_model(args) -> None:
    """A one-line error for ``--impact-model`` without ``--impact``."""
    if args.impact_model != "paper" and not args.impact:
        raise ValueError("--impact-model chooses the impact model of --impact; give --impact too")


def add_abar_range_options(parser, *, default=(None, None)):
    lo, hi = default
    parser.add_argument(
        "--abar-min",
        type=float,
        default=lo,
        help="lowest forcing amplitude Abar" + (f" (default {lo:g})" if lo is not None else ""),
    )
    parser.add_argument(
        "--abar-max",
        type=float,
        default=hi,
        help="highest forcing amplitude Abar" + (f" (default {hi:g})" if hi is not None else ""),
    )


def add_sigma_points_option(parser, *, default: int, old: str = "--grid"):
    parser.add_argument(
        "--sigma-points", type=int, default=default, help=f"sigma values compared (default {default})"
    )
    if old:
        parser.add_argument(
            old,
            dest="sigma_points",
            type=int,
            action=Deprecated,
            new="--sigma-points",
            help=argparse.SUPPRESS,
        )


def add_backend_option(parser):
    """--backend on the commands that integrate (9) or (8): compiled or the scipy reference."""
    parser.add_argument(
        "--backend",
        choices=("auto", "numba", "scipy"),
        default="auto",
        help="compiled (auto, numba) or the scipy reference: for (9) the same DOP853 in scipy's "
        "solve_ivp; for (8) "
        "the exact flow's expm event loop (default auto)",
    )


def add_tmax_option(parser):
    """--tmax on every command that classifies a regime: one meaning and one default."""
    parser.add_argument(
        "--tmax",
        type=float,
        default=CLASSIFY_TMAX,
        help=f"end time tau of each simulation (default {CLASSIFY_TMAX:g}); where a regime is "
        "classified, from its second half",
    )


def add_continuation_options(parser, *, rtol: str):
    """--ds, --ds-max, --max-steps and --rtol: the continuation controls, the same on every
    continuation command (defaults: the method's own; ``rtol`` says what it is there)."""
    parser.add_argument("--ds", type=float, default=None, help="first arclength step (default: the method's)")
    parser.add_argument(
        "--ds-max", type=float, default=None, help="largest arclength step (default: the method's)"
    )
    parser.add_argument(
        "--max-steps",
        type=int,
        default=None,
        help="accepted steps per direction at most (default: the method's)",
    )
    parser.add_argument("--rtol", type=float, default=None, help=rtol)
    parser.add_argument(
        "--max-seconds",
        type=float,
        default=None,
        help="a wall-clock safety net per branch direction (default: none); a branch it cuts ends with "
        "status 'time limit', and where depends on the machine's load",
    )


def continuation_options(args, base):
    """``base`` (a ContinuationOptions) with --ds, --ds-max, --max-steps applied, checked first."""
    for flag, value in (("--ds", args.ds), ("--ds-max", args.ds_max)):
        if value is not None and not 0 < value < float("inf"):
            raise ValueError(f"{flag} must be a positive finite arclength step; got {value}")
    if args.max_steps is not None and args.max_steps < 1:
        raise ValueError(f"--max-steps must be an integer >= 1; got {args.max_steps}")
    if args.max_seconds is not None and not args.max_seconds > 0:
        raise ValueError(f"--max-seconds must be > 0; got {args.max_seconds}")
    step_max = args.ds_max if args.ds_max is not None else max(base.step_max, args.ds or 0.0)
    step = min(args.ds if args.ds is not None else base.step, step_max)
    return dataclasses.replace(
        base,
        step=step,
        step_max=step_max,
        step_min=min(base.step_min, step),
        max_steps=args.max_steps or base.max_steps,
        max_seconds=args.max_seconds or base.max_seconds,
    )


def preset_of(args):
    """The parameter set named by ``--preset`` or read from ``--params FILE`` (read once)."""
    if getattr(args, "params", None) is None:
        return get_preset(args.preset)
    if not hasattr(args, "_preset_read"):
        from slosh_bif.model.parameter_file import read_parameter_file

        try:
            args._preset_read = read_parameter_file(args.params)
        except ValueError as err:
            raise ValueError(f"--params: {err}") from None
    return args._preset_read


def params_of(args):
    return preset_of(args).params.with_overrides(args.overrides)


def state0_of(args, params):
    """The preset's initial condition in the scaling of ``params`` (eps may be overridden)."""
    return preset_of(args).state_for(params)


def sigma_range(args, default=(-6.0, 8.0)):
    lo = default[0] if args.sigma_min is None else args.sigma_min
    hi = default[1] if args.sigma_max is None else args.sigma_max
    if not (lo < hi and math.isfinite(lo) and math.isfinite(hi)):
        raise ValueError(f"--sigma-min must be below --sigma-max, both finite; got {lo} and {hi}")
    return lo, hi


def abar_range(args, default):
    """(--abar-min, --abar-max) or their defaults, checked; a default upper end of None (the
    method's own) stays None."""
    lo = default[0] if args.abar_min is None else args.abar_min
    hi = default[1] if args.abar_max is None else args.abar_max
    if not (math.isfinite(lo) and lo >= 0 and (hi is None or (math.isfinite(hi) and lo < hi))):
        raise ValueError(f"need 0 <= --abar-min < --abar-max, both finite; got {lo} and {hi}")
    return lo, hi


def progress(message):
    """A message to keep on screen (stderr; none with -q)."""
    REPORTER.note(message)


def passing(message):
    """A passing state: the status line on a terminal (a plain line elsewhere, all of them with -v)."""
    REPORTER.update(message)


def throttled(report, every=1.0, *, passes=lambda message: "point" not in message):
    """A progress callback that passes on at most one message a second (and every message for
    which ``passes`` is true: by default each that is not about a single point, e.g. a new branch)."""
    import time

    last = [-1e9]

    def callback(message):
        now = time.monotonic()
        if passes(message):
            report(message)
        elif (
            REPORTER.verbose or now - last[0] >= every
        ):  # what is shown, not what is computed, depends on the clock
            last[0] = now
            (passing if report is progress else report)(message)

    return callback


def cell_progress(report, what: str):
    """A ``progress(count, total)`` callback for a sweep, at most once a second and always the last:
    "k of n <what>, r/s, about t left" (the rate from this run's cells only, not a resume's)."""
    import time

    start, first, shown = time.monotonic(), [None], throttled(report, passes=lambda message: False)

    def callback(count, total):
        if first[0] is None:
            first[0] = count - 1
        elapsed, new = time.monotonic() - start, count - first[0]
        rate = new / elapsed if elapsed > 0 else float("nan")
        left = f", about {(total - count) / rate:.0f} s left" if rate > 0 and count < total else ""
        (report if count >= total else shown)(f"{count} of {total} {what}, {rate:.2g}/s{left}")

    return callback


def add_scheduler_option(parser) -> None:
    parser.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="run the work (cells, curves) on an existing dask.distributed cluster at ADDRESS (e.g. "
        "tcp://host:8786; needs the [dask] extra) instead of local processes",
    )


@contextlib.contextmanager
def sweep_executor(args):
    """The executor a sweep runs its cells on: the dask cluster's for ``--scheduler`` (its client
    closed when the block ends, however it ends), or None for the sweep's own local processes.
    A one-line error when dask is not installed or the scheduler does not answer."""
    address = getattr(args, "scheduler", None)
    if address is None:
        yield None
        return
    try:
        from distributed import Client
    except ImportError:
        raise ValueError("--scheduler needs dask.distributed: pip install 'slosh_bif[dask]'") from None
    _probe_scheduler(address)
    try:
        client = Client(address, timeout=5)
    except (OSError, TimeoutError) as err:
        raise ValueError(f"--scheduler {address}: no dask scheduler answers there ({err})") from None
    try:
        from slosh_bif.simulation.sweep import ClusterExecutor

        yield ClusterExecutor(client)
    finally:
        client.close()


PROBE_SECONDS = 5.0  # how long a TCP scheduler address may take to greet


def _probe_scheduler(address: str) -> None:
    """A one-line error unless the tcp:// (or bare host:port) ``address`` greets like a dask
    scheduler: on connection a scheduler writes its handshake first, a frame whose 8-byte
    little-endian length is small. Any other service is refused before dask reads its bytes as
    a length (an HTTP server's reply read so asked for 3 EiB). Other schemes are left to dask."""
    import socket
    import struct

    scheme, _, rest = address.rpartition("://")
    if scheme not in ("", "tcp"):
        return
    host, _, port = rest.rpartition(":")
    if not (host and port.isdigit()):
        raise ValueError(f"--scheduler {address}: expected tcp://HOST:PORT")
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=PROBE_SECONDS) as sock:
            greeting = b""
            while len(greeting) < 8:
                chunk = sock.recv(8 - len(greeting))
                if not chunk:
                    break
                greeting += chunk
    except (OSError, TimeoutError) as err:
        raise ValueError(f"--scheduler {address}: no dask scheduler answers there ({err})") from None
    if len(greeting) < 8 or not 0 < struct.unpack("<Q", greeting)[0] < 1 << 20:
        raise ValueError(
            f"--scheduler {address}: the service there is not a dask scheduler (it did not greet "
            "with a dask handshake)"
        )


def floats(text):
    return [float(v) for v in text.split(",")]
