"""The speed targets of the shooting issues, measured as ratios in one run
(``python -m benchmarks --only speed``).

* **Shooting branch, whole process**: ``slosh-bif shoot --preset fig10 --no-switch --sigma-min -6
  --sigma-max 8`` run as a user runs it (a fresh interpreter: imports, cached compilation, the
  settling simulation, the branch with every special point, the output files; the median of three
  runs), against 1,000 reference periods
  (:func:`~benchmarks.speed_reference.one_period_reference`: scipy's ``solve_ivp`` DOP853 at rtol
  1e-10 over one period of the Fig. 10 set at sigma = 3 from its attractor); target at most 0.18.
  The n = 6 set's branch from its symmetric orbit at sigma = -6 (``--set n=6 --set sigma=-6
  --guess`` that orbit), against the n = 6 reference: at most 0.095. Every reference is the mean
  of two measured right before and right after its case (:func:`_beside`). Both branches also
  against the earlier reference (1,000 periods chained from the preset's state; target 0.3),
  which gives smaller ratios.
* **Whole studies** (not in ``--quick``): the Fig. 10 chart with switching (at most 22 times
  1,000 reference periods) and ``shoot --start scan`` (every family, at most 11 times).
* **Start-up**: a ``shoot`` run from launch to its first Newton step (target < 0.5 s with numba's
  cache warm: :mod:`slosh_bif.flows.loops` imports numba at the first integration),
  ``slosh-bif info`` (target < 0.5 s), the shooting start alone in this process; and (not in
  ``--quick``) where the Fig. 10 branch's whole process spends its time, stage by stage.
* **Load independence**: ``slosh-bif simulate --preset fig9a --model impact --backend scipy --tmax
  150`` (the expm event loop: many small matrix exponentials) with one CPU-burning process beside it, as a
  ratio to its time
  without, measured back to back in one run; target at most 1.5 (BLAS threads that fight the
  neighbour for the cores made it 26x).
* **The impact model**: 100 forcing periods of (8) by its compiled exact flow against 100 of (9)
  at n = 50 (the Fig. 10 set, in this process; target at most 0.1), and ``shoot --model impact``
  against the (9) branch above, as whole processes (no target: both carry the same fixed costs
  of imports, settling and plot, about 2 s) and as the continuation alone (``branch_compute.py``;
  target at most a third).
* **Peak memory** of the whole-process branch (the child's maximum resident set size), and of
  regime maps of 20 x 20 and 100 x 100 cells (Fig. 13 set, short runs: a memory case, not a regime
  study): the parent's and the largest worker's resident sets, which must not grow with the cells.

The direct simulation's ratio against scipy is the integration question's
(``integrators_ratios.csv``).
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time

import numpy as np

from benchmarks.branch_compute import branch_seconds
from benchmarks.speed_reference import (
    chained_reference,
    first_newton,
    one_period_reference,
    run_child,
    stage_profile,
)
from slosh_bif.model.presets import get_preset
from slosh_bif.orbits.starts import orbit_from_simulation
from slosh_bif.simulation.direct import SimulationSettings, simulate

__all__ = ["speed_bench", "run_cli", "SPEED_COLUMNS"]

SPEED_COLUMNS = ("case", "seconds", "reference_seconds", "ratio", "target", "peak_rss_mb", "note")
SHOOT = ["shoot", "--preset", "fig10", "--no-switch", "--sigma-min", "-6", "--sigma-max", "8"]


def _n6_guess():
    """``--set n=6 --set sigma=-6 --guess X,Xd,w,wd``: the symmetric orbit there, found once."""
    params = get_preset("fig10").params.replace(n=6, sigma=-6.0)
    y0 = orbit_from_simulation(params, get_preset("fig10").state_for(params)).y0
    return ["--set", "n=6", "--set", "sigma=-6", "--guess", ",".join(f"{v:.17g}" for v in y0)]


# case -> (its extra arguments, the n of its reference, the target ratio to 1,000 reference periods)
CASES = {
    "fig10 (n = 50)": (list, 50, 0.18),
    "fig10, n = 6, from the symmetric orbit at sigma = -6": (_n6_guess, 6, 0.095),
}
BRANCH_RUNS = 3  # whole-process runs of each branch case (one with quick); its row has their median
WHOLE_STUDIES = (  # (case, arguments, target ratio to 1,000 reference periods at n = 50)
    (
        "chart fig10 with switching",
        ["chart", "--preset", "fig10", "--sigma-min", "-6", "--sigma-max", "8", "--abar-min", "0.2"]
        + ["--abar-max", "6"],
        22.0,
    ),
    ("shoot fig10 --start scan (every family)", ["shoot", "--preset", "fig10", "--start", "scan"], 11.0),
)


def _row(case, seconds, reference, target, note, peak=np.nan):
    return dict(
        case=case,
        seconds=seconds,
        reference_seconds=reference,
        ratio=seconds / reference,
        target=target,
        peak_rss_mb=peak,
        note=note,
    )


_CHILD = (  # the peak at exit: the console entry runs the exit functions, then leaves at once
    "import atexit, resource, runpy, sys\n"
    "atexit.register(lambda: print('peak_rss_kb', resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, "
    "resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, file=sys.stderr))\n"
    "sys.argv = ['slosh-bif', *sys.argv[1:]]\n"
    "runpy.run_module('slosh_bif.cli', run_name='__main__')\n"
)
REGIMES = ["regimes", "--preset", "fig13", "--tmax", "60", "--workers", "2"]
REGIME_GRIDS = (20, 100)


def run_cli(arguments, timeout=900.0, workers=False):
    """Wall time and the child's own peak resident set (MB; ru_maxrss is in kB on Linux) of
    ``slosh-bif ARGUMENTS`` in a fresh interpreter; ``workers``: also its largest worker's."""
    seconds, done = run_child(_CHILD, arguments, timeout)
    lines = done.stderr.strip().splitlines()
    peaks = (
        [float(v) / 1024 for v in lines[-1].split()[1:]]
        if lines and lines[-1].startswith("peak_rss_kb")
        else [np.nan, np.nan]
    )
    if done.returncode not in (0, 3):
        reason = next((line for line in reversed(lines) if not line.startswith("peak_rss_kb")), "")
        raise RuntimeError(f"slosh-bif {' '.join(arguments)} failed ({done.returncode}): {reason}")
    return (seconds, *peaks) if workers else (seconds, peaks[0])


def _beside(n, work):
    """(``work()``, 1,000 reference periods at this n: the mean of the reference measured right
    before and right after the work, and a note of both). The machine's speed drifts over a
    bench of twenty minutes (a whole study's processes slowed by half, the reference measured
    at the start did not), and a ratio cancels it only against a reference taken beside it."""
    before = 1000 * one_period_reference(n)
    value = work()
    after = 1000 * one_period_reference(n)
    return value, 0.5 * (before + after), f"reference {before:.1f} ms a period before, {after:.1f} after"


def _simulated(preset, model, repeats=3):
    """Best of ``repeats`` wall times of 100 forcing periods of one model, in this process."""
    simulate(
        preset.params, preset.state0, 2 * np.pi, settings=SimulationSettings(model=model)
    )  # compiled before timing
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        simulate(preset.params, preset.state0, 200 * np.pi, settings=SimulationSettings(model=model))
        best = min(best, time.perf_counter() - start)
    return best


def speed_bench(*, quick: bool = False, progress=None) -> list:
    """Rows of :data:`SPEED_COLUMNS`: each whole-process branch against 1,000 scipy periods of its
    own parameter set, the start-up of ``slosh-bif info`` and the in-process shooting start."""
    say = progress or (lambda message: None)
    rows = []
    periods = 100 if quick else 1000
    with tempfile.TemporaryDirectory() as tmp:
        run_cli(["compile"], timeout=1800.0)  # numba's cache filled once, as an installed user has it
        for case, (extra, n, target) in CASES.items():
            say(f"speed: slosh-bif shoot, {case}")
            extra = extra()
            # a median of runs, as the reference is a median: one run of a second on a shared
            # machine moves by a tenth between runs
            runs, reference, taken = _beside(
                n,
                lambda: [
                    run_cli([*SHOOT, *extra, "--out", os.path.join(tmp, "shoot")])
                    for _ in range(1 if quick else BRANCH_RUNS)
                ],
            )
            seconds, peak = float(np.median([r[0] for r in runs])), max(r[1] for r in runs)
            rows.append(
                _row(
                    f"shoot --no-switch, {case}",
                    seconds,
                    reference,
                    target,
                    f"whole process (median of {len(runs)} runs) against 1,000 reference periods "
                    "(scipy DOP853 at rtol 1e-10, one "
                    f"period of the Fig. 10 set at sigma = 3, n = {n}, from its attractor; {taken})",
                    peak,
                )
            )
            say(f"speed: {periods} chained scipy periods (the earlier reference), {case}")
            params = get_preset("fig10").params.with_overrides(extra[1:4:2])
            chained = chained_reference(params, get_preset("fig10").state_for(params), periods)
            rows.append(
                _row(
                    f"shoot --no-switch, {case}, earlier reference",
                    seconds,
                    chained * 1000 / periods,
                    0.3,
                    "the same run against 1,000 chained periods from the preset's state (the earlier "
                    "reference)" + (" (100 measured, scaled)" if quick else ""),
                )
            )
        if not quick:
            for case, arguments, target in WHOLE_STUDIES:
                say(f"speed: slosh-bif {' '.join(arguments)}")
                (seconds, peak), reference, taken = _beside(
                    50, lambda: run_cli([*arguments, "--out", os.path.join(tmp, "study")], timeout=7200.0)
                )
                rows.append(
                    _row(
                        case,
                        seconds,
                        reference,
                        target,
                        f"whole process, times 1,000 periods ({taken})",
                        peak,
                    )
                )
        say("speed: start-up to the first Newton step")
        start_up = min(first_newton([*SHOOT, *extra, "--out", tmp]) for _ in range(3))  # the n = 6 case's
        rows.append(
            _row(
                "shoot start-up: launch to the first Newton step (n = 6 set, --guess)",
                start_up,
                np.nan,
                0.5,
                "seconds, interpreter start included, numba's cache warm; target in seconds",
            )
        )
        if not quick:
            say("speed: the profile of the Fig. 10 branch")
            for stage, seconds in stage_profile([*SHOOT, "--out", os.path.join(tmp, "profile")]).items():
                rows.append(_row(f"profile of shoot fig10: {stage}", seconds, np.nan, np.nan, "seconds"))
        say("speed: the impact model beside a CPU-burning process")
        # the expm event loop (--backend scipy): many tiny matrix exponentials, what BLAS threads slowed
        impact = [
            "simulate",
            "--preset",
            "fig9a",
            "--model",
            "impact",
            "--backend",
            "scipy",
            "--tmax",
            "150",
            "--out",
            os.path.join(tmp, "impact"),
        ]
        alone = min(run_cli(impact)[0] for _ in range(1 if quick else 2))
        burner = subprocess.Popen([sys.executable, "-c", "while True: pass"])
        try:
            loaded = min(run_cli(impact)[0] for _ in range(1 if quick else 2))
        finally:
            burner.kill()
            burner.wait()
        rows.append(
            dict(
                case="simulate fig9a --model impact --backend scipy, beside a CPU-burning process",
                seconds=loaded,
                reference_seconds=alone,
                ratio=loaded / alone,
                target=1.5,
                peak_rss_mb=np.nan,
                note="whole process, against the same command with the machine otherwise idle",
            )
        )
        say("speed: the impact model's branch beside (9)'s")
        impact_branch, _ = run_cli(
            [*SHOOT, "--model", "impact", "--set", "sigma=5", "--out", os.path.join(tmp, "shoot8")]
        )
        smooth_branch = next(r["seconds"] for r in rows if r["case"].endswith("fig10 (n = 50)"))
        rows.append(
            _row(
                "shoot --model impact --set sigma=5, fig10 (8)",
                impact_branch,
                smooth_branch,
                np.nan,
                "whole process against the (9) branch above; (8)'s symmetric branch from sigma = "
                "5 on the half-period map, through its four grazings; both carry the same ~2 s of "
                "imports, settling and plot (the branch's own target is the next row's)",
            )
        )
        say("speed: the two branches' continuation alone, in this process")
        alone = branch_seconds(repeats=1 if quick else 3)
        rows.append(
            _row(
                "(8)'s symmetric branch over [-6, 8] against (9)'s, continuation alone",
                alone["impact"],
                alone["smooth"],
                1 / 3,
                "in process, best wall seconds of alternating runs: the continuation without the "
                "interpreter, imports, measures and plot that both whole processes add",
            )
        )
        say("speed: start-up")
        startup = min(run_cli(["info", "--preset", "fig10"])[0] for _ in range(1 if quick else 3))
        rows.append(
            dict(
                case="slosh-bif info (start-up, cached)",
                seconds=startup,
                reference_seconds=np.nan,
                ratio=np.nan,
                target=0.5,
                peak_rss_mb=np.nan,
                note="seconds; target in seconds",
            )
        )
        for cells in REGIME_GRIDS[:1] if quick else REGIME_GRIDS:
            say(f"speed: regimes {cells} x {cells} (memory)")
            seconds, parent, worker = run_cli(
                [
                    *REGIMES,
                    "--sigma-points",
                    str(cells),
                    "--abar-points",
                    str(cells),
                    "--out",
                    os.path.join(tmp, f"regimes{cells}"),
                ],
                timeout=3600.0,
                workers=True,
            )
            rows.append(
                dict(
                    case=f"regimes {cells} x {cells}, fig13, tmax 60 (memory)",
                    seconds=seconds,
                    reference_seconds=np.nan,
                    ratio=np.nan,
                    target=np.nan,
                    peak_rss_mb=parent,
                    note=f"peak resident set of the parent; largest worker {worker:.0f} MB",
                )
            )
    pre = get_preset("fig10")
    say("speed: 100 periods of (8) and of (9)")
    seconds = {model: _simulated(pre, model) for model in ("impact", "smooth")}
    rows.append(
        _row(
            "simulate (8), fig10, 100 periods",
            seconds["impact"],
            seconds["smooth"],
            0.1,
            "in process, best of 3, against (9) at n = 50 compiled; impact times to 1e-10",
        )
    )
    start = time.perf_counter()
    orbit_from_simulation(pre.params, pre.state0)
    rows.append(
        dict(
            case="shooting start (settle 150 periods, Newton)",
            seconds=time.perf_counter() - start,
            reference_seconds=np.nan,
            ratio=np.nan,
            target=np.nan,
            peak_rss_mb=np.nan,
            note="in process, compiled",
        )
    )
    return rows
