"""Speed against an earlier commit, measured side by side in one run
(``python -m benchmarks --only against``; ``--base COMMIT``, default 8ec52f9, the commit the speed
round 4 issue measures against).

The earlier commit's tree is unpacked beside the working tree (``git archive``: the bench needs the
repository's history) and each case is run as a whole process by both trees in turn, the order
alternating from one round to the next (the machine's speed drifts over a bench of minutes); each
side's median over the rounds is kept and the ratio printed. Both trees run in the same virtual
environment, with their caches filled first (``slosh-bif compile`` in each: numba's cache here, the
earlier tree's loops built ahead of time where it has them; and each tree's bytecode, as an
installed package has it). No absolute target: the ratio is
what carries over between machines.

Cases: the Fig. 10 symmetric branch (n = 50) and the n = 6 branch from its symmetric orbit (each
also stopped after one continuation step, its fixed part, on both sides: that part over the base's
whole command is the case's floor, the lowest ratio a faster continuation could give), the
Fig. 10 chart with switching and the family scan (not in ``--quick``: about 7 and 12 minutes a
run on one 2-core machine). The scan is not the same work on both sides from the commit on which a
family stopped switching at the mirror twins of points it has dealt with (the speed page): 8ec52f9
traces nine distinct branches in two families and four duplicates, later trees six distinct ones
in one family, so its ratio says what the command costs, not what the same branches cost.
"""

from __future__ import annotations

import io
import os
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np

from benchmarks.speed import SHOOT, _n6_guess

__all__ = ["against_bench", "AGAINST_COLUMNS", "BASE"]

BASE = "8ec52f9"
ROOT = Path(__file__).resolve().parents[1]
AGAINST_COLUMNS = (
    "case",
    "base",
    "base_seconds",
    "seconds",
    "ratio",
    "target",
    "rounds",
    "base_fixed_seconds",
    "fixed_seconds",
    "floor_ratio",
    "note",
)
CHART = ["chart", "--preset", "fig10", "--sigma-min", "-6", "--sigma-max", "8", "--abar-min", "0.2"]
CHART += ["--abar-max", "6"]


class Case(NamedTuple):
    arguments: object  # the command's arguments, or a function giving them
    rounds: int
    quick: bool  # run by --quick
    target: float  # the ratio the issue asks for
    fixed: bool  # its fixed part measured too (a branch)


CASES = {
    "Fig. 10 branch (n = 50)": Case(SHOOT, 5, True, 0.5, True),
    "n = 6 branch from its symmetric orbit at sigma = -6": Case(
        lambda: [*SHOOT, *_n6_guess()], 5, True, 0.5, True
    ),
    "Fig. 10 chart with switching": Case(CHART, 1, False, 0.5, False),
    "family scan (shoot --start scan)": Case(
        ["shoot", "--preset", "fig10", "--start", "scan"], 1, False, 0.5, False
    ),
}
# A branch's fixed part: the same command stopped after one continuation step (the interpreter, the
# imports, the compiled loops' loading, the start orbit, the files and the figure), which no
# speed-up of the continuation removes. Its time over the base's whole command is the lowest ratio
# the case could reach by making everything after that step free: its floor.
ONE_STEP = ["--max-steps", "1"]
# a tree's command line, as its console entry runs it (the interpreter's teardown skipped)
_ENTRY = "import sys; sys.argv[0] = 'slosh-bif'; from slosh_bif.cli import run; run()"


def unpack(commit: str, where: Path) -> Path:
    """The tree of ``commit`` written under ``where``; a one-line error when git cannot give it."""
    done = subprocess.run(
        ["git", "-C", str(ROOT), "archive", "--format=tar", commit], capture_output=True, timeout=120
    )
    if done.returncode != 0:
        reason = done.stderr.decode(errors="replace").strip().splitlines()[-1:] or ["no git"]
        raise ValueError(f"--base {commit}: git cannot give that commit's tree here ({reason[0]})")
    tree = Path(where) / f"slosh_bif-{commit}"
    with tarfile.open(fileobj=io.BytesIO(done.stdout)) as archive:
        archive.extractall(tree, filter="data")
    return tree


def _env(tree: Path) -> dict:
    return {**os.environ, "PYTHONPATH": str(tree), "PYTHONWARNINGS": "ignore"}


def timed_run(tree: Path, arguments, out: Path, timeout: float = 7200.0) -> float:
    """Wall seconds of ``slosh-bif ARGUMENTS --out OUT`` run by the package of ``tree``."""
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-c", _ENTRY, *arguments, "--out", str(out), "-q"],
        capture_output=True,
        text=True,
        env=_env(tree),
        cwd=tree,
        timeout=timeout,
    )
    seconds = time.perf_counter() - start
    if done.returncode not in (0, 3):
        reason = done.stderr.strip()[-300:]
        raise RuntimeError(f"{tree.name}: slosh-bif {' '.join(arguments)} failed: {reason}")
    return seconds


def _prepare(tree: Path) -> None:
    """Both caches an installed package has: numba's (``slosh-bif compile``) and the bytecode of
    the tree's modules, written here for either tree (the earlier tree's ``compile`` did not)."""
    subprocess.run(
        [sys.executable, "-c", _ENTRY, "compile"], capture_output=True, env=_env(tree), cwd=tree, timeout=1800
    )
    subprocess.run(
        [sys.executable, "-m", "compileall", "-q", str(tree / "slosh_bif")], capture_output=True, timeout=600
    )


def against_bench(*, base: str = BASE, quick: bool = False, progress=None) -> list:
    """Rows of :data:`AGAINST_COLUMNS`, one a case: this tree's median time over that of ``base``."""
    say = progress or (lambda message: None)
    rows = []
    with tempfile.TemporaryDirectory(prefix="slosh-bif-against-") as tmp:
        trees = {"base": unpack(base, Path(tmp)), "this": ROOT}
        for tree in trees.values():
            _prepare(tree)
        for case, (arguments, rounds, in_quick, target, fixed) in CASES.items():
            if quick and not in_quick:
                continue
            arguments = arguments() if callable(arguments) else list(arguments)
            rounds = 1 if quick else rounds
            for side, tree in trees.items():  # a warm run each: caches and the page cache
                if rounds > 1:
                    timed_run(tree, arguments, Path(tmp) / f"warm-{side}")
            runs = {"whole": arguments, "fixed": [*arguments, *ONE_STEP]} if fixed else {"whole": arguments}
            seconds = {(part, side): [] for part in runs for side in trees}
            for r in range(rounds):
                order = ("base", "this") if r % 2 == 0 else ("this", "base")
                for part, argv in runs.items():
                    for side in order:
                        what = case if part == "whole" else f"{case}, one step"
                        say(f"against {base}: {what}, round {r + 1} of {rounds}, {side}")
                        seconds[part, side].append(
                            timed_run(trees[side], argv, Path(tmp) / f"{part}-{side}-{r}")
                        )
            median = {key: statistics.median(values) for key, values in seconds.items()}
            mine, theirs = median["whole", "this"], median["whole", "base"]
            rows.append(
                {
                    "case": case,
                    "base": base,
                    "base_seconds": theirs,
                    "seconds": mine,
                    "ratio": mine / theirs if theirs > 0 else np.nan,
                    "target": target,
                    "rounds": rounds,
                    "base_fixed_seconds": median.get(("fixed", "base"), np.nan),
                    "fixed_seconds": median.get(("fixed", "this"), np.nan),
                    "floor_ratio": median.get(("fixed", "this"), np.nan) / theirs if theirs > 0 else np.nan,
                    "note": "whole processes, medians, alternating order"
                    + ("; fixed part: the same command stopped after one continuation step" if fixed else ""),
                }
            )
    return rows
