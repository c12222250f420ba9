"""The ``slosh-bif`` command line.

Subcommands:

* ``info``     - a preset's parameters and the derived restitution quantities (eqs. 21, 31, 36, 40);
* ``tank``     - a real tank, its structure and the ground motion as the model's parameters (a file for
  --params);
* ``frc``      - the frequency-response curve of the slow flow (45)/(46) by continuation in sigma;
* ``critical`` - the critical forcing Abar_b(sigma) by continuation of the fold and end conditions;
* ``shoot``    - periodic orbits of the smooth model (9) by shooting, continued in sigma, with
  folds, branch points, period doublings and Neimark-Sacker points, and the branches born there;
* ``compare``  - the slow-flow curve (46) against the shooting branches over the same sigma range;
* ``trust``    - ``compare`` over a grid of eps, beta and n: where the slow flow can be trusted;
* ``simulate`` - a time response of the smooth model (9) or the vibro-impact model (8), optionally
  with the noise of (47), classified into a response regime;
* ``regimes``  - a map of response regimes over (sigma, Abar), computed in parallel;
* ``chart``    - the curves in (sigma, Abar) where the orbits of (9) fold or period-double, and
  the full model's critical forcing read off them;
* ``figures``  - the paper's Figs. 3-15, regenerated from scratch as PNG files;
* ``derive``   - regenerate the generated code from the sympy derivations (``--check``: verify it).
"""

from __future__ import annotations

import argparse
import os
import re
import sys

# One BLAS thread for the command and every process it starts (workers inherit the environment).
# BLAS libraries read these when they load, and scipy's own OpenBLAS loads late, on first use of
# scipy.linalg: a threadpool limit entered in main() would not reach it. The matrices here are
# 4x4 to 32x32, where threads only cost, and on a busy machine they cost 40x (impact model, expm).
for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS"):
    os.environ[_name] = "1"

from slosh_bif.cli import (  # noqa: E402 - after the environment is set
    answer,
    chart,
    compare,
    identify,
    info,
    orbits,
    simulation,
    slowflow,
    studies,
    study,
    tank,
)

__all__ = ["build_parser", "main", "run", "warning_origin"]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="slosh-bif",
        description="Continuation and bifurcation analysis of the equivalent mechanical model of strongly "
        "nonlinear liquid sloshing (Farid & Gendelman).",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for family in (
        info,
        tank,
        slowflow,
        orbits,
        chart,
        compare,
        study,
        studies,
        answer,
        simulation,
        identify,
    ):
        family.add_commands(sub)
    for each in sub.choices.values():
        talk = each.add_mutually_exclusive_group()
        talk.add_argument(
            "-q", "--quiet", action="store_true", help="no progress messages (results and errors still print)"
        )
        talk.add_argument(
            "-v",
            "--verbose",
            action="store_true",
            help="every progress message, and every special point on stdout",
        )
    return parser


_NUMBER = re.compile(r"^-(\d|\.\d|inf|nan)", re.IGNORECASE)


def values_may_start_with_minus(tokens: list[str]) -> list[str]:
    """A token such as -1e6, -inf or -1,0,0,0 is a value, not an option: argparse takes only plain
    negative numbers (-3, -0.5) as values. Such tokens are handed to argparse with a leading space
    (only a token that starts with '-' can be an option; the converters strip the space), which
    keeps pairs such as ``--range1 -3 3`` working. No option of ours looks like a number."""
    return [" " + token if _NUMBER.match(token) else token for token in tokens]


def _check_out(out, *, is_file: bool = False) -> None:
    """A one-line error, before any work, when the output folder (or, for ``is_file``, the output
    file's folder) cannot be made or written."""
    if out is None:
        return
    if is_file and out.is_dir():
        raise ValueError(f"--out {out} is a folder; give a file name")
    if not is_file and out.exists() and not out.is_dir():
        raise ValueError(f"--out {out} is a file; give a folder (created if missing)")
    existing = next(
        p
        for p in ((out.parent,) if is_file else (out,))
        + tuple(out.parent.parents if is_file else out.parents)
        if p.exists()
    )
    if not existing.is_dir():
        raise ValueError(f"--out {out}: {existing} is a file, not a folder")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise ValueError(f"--out {out}: cannot create or write in {existing} (permission denied)")


def warning_origin(category, filename: str, lineno: int) -> str:
    """Where a warning comes from, for those that do not say it themselves (numpy's "invalid value
    encountered in det"): its class and the package's line that raised it."""
    if issubclass(category, UserWarning) and "slosh_bif" in str(filename):
        return ""  # the package's own warnings name their subject
    where = str(filename)
    cut = where.rfind("slosh_bif" + os.sep)
    return f" ({category.__name__} at {where[cut:] if cut >= 0 else os.path.basename(where)}:{lineno})"


def _quiet_stdout() -> None:
    """Point stdout at /dev/null, so that the interpreter's final flush into a closed pipe prints nothing."""
    try:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    except (OSError, ValueError):
        pass


def _chained_interrupt(err: BaseException):
    """The KeyboardInterrupt in ``err``'s chain of causes and contexts, or None."""
    seen = set()
    while err is not None and id(err) not in seen:
        if isinstance(err, KeyboardInterrupt):
            return err
        seen.add(id(err))
        err = err.__cause__ or err.__context__
    return None


def _interrupted(command: str, stop: KeyboardInterrupt) -> int:
    name = getattr(stop, "signal_name", "SIGINT")
    print(
        f"slosh-bif {command}: {stop if str(stop) else 'interrupted (' + name + ')'}; the files "
        "written are complete, the rest was not written",
        file=sys.stderr,
    )
    return 143 if name == "SIGTERM" else 130


def main(argv=None) -> int:
    import warnings

    from threadpoolctl import threadpool_limits

    from slosh_bif.cli.exits import stop_signals
    from slosh_bif.cli.terminal import REPORTER

    parser = build_parser()
    args = parser.parse_args(values_may_start_with_minus(sys.argv[1:] if argv is None else list(argv)))
    REPORTER.configure(quiet=args.quiet, verbose=args.verbose)

    shown = set()

    def show(
        message, category, filename="", lineno=0, *_args, **_kwargs
    ):  # one line, no source excerpt, each message once
        if str(message) not in shown:
            shown.add(str(message))
            REPORTER.close()  # a warning on its own line, not inside the status line
            print(
                f"slosh-bif {args.command}: warning: {message}{warning_origin(category, filename, lineno)}",
                file=sys.stderr,
            )

    with stop_signals(), warnings.catch_warnings():
        warnings.showwarning = show
        warnings.simplefilter("always")  # every warning reaches show(), which prints each message once
        try:
            _check_out(getattr(args, "out", None), is_file=getattr(args, "out_is_file", False))
            with threadpool_limits(
                limits=1, user_api="blas"
            ):  # the BLAS already loaded when main() is called in-process
                status = args.run(args)
            sys.stdout.flush()  # a closed pipe shows here, inside the handlers, not at the interpreter's exit
            return status
        except KeyboardInterrupt as stop:  # Ctrl-C or SIGTERM: workers are stopped where they run
            return _interrupted(args.command, stop)
        except SystemError as err:
            # A signal that arrives inside compiled (numba) code, or while numba loads cached
            # code, surfaces as "returned a result with an exception set", the KeyboardInterrupt
            # chained to it (as its context or its cause).
            stop = _chained_interrupt(err)
            if stop is None:
                raise
            return _interrupted(args.command, stop)
        except ValueError as err:
            print(f"slosh-bif {args.command}: error: {err}", file=sys.stderr)
            return 2
        except RuntimeError as err:  # a method that could not answer says why (no traceback)
            print(f"slosh-bif {args.command}: failed: {err}", file=sys.stderr)
            return 1
        except BrokenPipeError:  # the reader went away (`slosh-bif info | head -2`): stop quietly
            _quiet_stdout()
            return 0
        except OSError as err:  # e.g. the disk filled up while writing
            print(f"slosh-bif {args.command}: failed to read or write a file: {err}", file=sys.stderr)
            return 1
        finally:
            REPORTER.close()


def run() -> None:
    """The ``slosh-bif`` console entry: :func:`main`, then the process leaves at once.

    Once every file is written and closed, the interpreter's teardown (freeing every module of
    numba, scipy and matplotlib one by one, about 0.4 s) changes nothing a user sees, so the exit
    functions run and the process ends without it. Where a thread or a child process is still
    alive, or a profiler or tracer watches (cProfile, coverage: they write at the interpreter's
    exit), the ordinary exit is taken, for at most
    :data:`~slosh_bif.cli.exits.EXIT_WAIT` seconds.
    """
    import atexit
    import threading

    from slosh_bif.cli.exits import EXIT_WAIT, leave_within

    status = main()
    sys.stdout.flush()
    sys.stderr.flush()
    children = sys.modules.get("multiprocessing")
    watched = sys.getprofile() is not None or sys.gettrace() is not None
    if watched or threading.active_count() > 1 or (children is not None and children.active_children()):
        leave_within(EXIT_WAIT, status, "the exit")
        sys.exit(status)
    atexit._run_exitfuncs()  # what an ordinary exit runs first (loggers, temporary folders)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)
