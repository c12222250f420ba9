"""The speed targets of the shooting issue, measured as ratios in one run (``slosh-bif bench --only speed``).

* **Shooting branch, whole process**: ``slosh-bif shoot --preset fig10 --no-switch --sigma-min -6
  --sigma-max 8`` run as a user runs it (a fresh interpreter: imports, cached compilation, the
  settling simulation, the branch with every special point, the output files), against 1,000
  one-period integrations of (9) by scipy's ``solve_ivp`` DOP853 at rtol 1e-10, atol 1e-12 on the
  same machine in the same run; the target is a ratio of at most 0.3. The same with
  ``--set n=6 --set sigma=-6`` (a symmetric start at sigma = -6 for the n = 6 set).
* **Start-up**: ``slosh-bif info --preset fig10`` in a fresh interpreter (target < 0.5 s), and
  the shooting start alone in this process (the settling simulation and Newton).
* **Load independence**: ``slosh-bif simulate --preset fig9a --model impact --backend scipy --tmax
  150`` (the expm event loop: many small matrix exponentials) with one CPU-burning process beside it, as a
  ratio to its time
  without, measured back to back in one run; target at most 1.5 (BLAS threads that fight the
  neighbour for the cores made it 26x).
* **The impact model**: 100 forcing periods of (8) by its compiled exact flow against 100 of (9)
  at n = 50 (the Fig. 10 set, in this process; target at most 0.1), and ``shoot --model impact``
  against the (9) branch above (target at most a third).
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
from scipy.integrate import solve_ivp

from slosh_bif.model.equations import SmoothModel
from slosh_bif.model.presets import get_preset
from slosh_bif.orbits.starts import orbit_from_simulation
from slosh_bif.simulation.direct import SimulationSettings, simulate

__all__ = ["speed_bench", "run_cli", "SPEED_COLUMNS"]

SPEED_COLUMNS = ("case", "seconds", "reference_seconds", "ratio", "target", "peak_rss_mb", "note")
SHOOT = ["shoot", "--preset", "fig10", "--no-switch", "--sigma-min", "-6", "--sigma-max", "8"]
CASES = {"fig10 (n = 50)": [], "fig10, n = 6, from sigma = -6": ["--set", "n=6", "--set", "sigma=-6"]}


_CHILD = (
    "import resource, runpy, sys\n"
    "sys.argv = ['slosh-bif', *sys.argv[1:]]\n"
    "try:\n    runpy.run_module('slosh_bif.cli', run_name='__main__')\n"
    "finally:\n    print('peak_rss_kb', resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, "
    "resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, file=sys.stderr)\n"
)
REGIMES = ["regimes", "--preset", "fig13", "--tmax", "60", "--workers", "2"]
REGIME_GRIDS = (20, 100)


def run_cli(arguments, timeout=900.0, workers=False):
    """Wall time and the child's own peak resident set (MB; ru_maxrss is in kB on Linux) of
    ``slosh-bif ARGUMENTS`` in a fresh interpreter; ``workers``: also its largest worker's."""
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-c", _CHILD, *arguments],
        capture_output=True,
        text=True,
        timeout=timeout,
        env={**os.environ, "PYTHONWARNINGS": "ignore"},
    )
    seconds = time.perf_counter() - start
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


def _scipy_periods(params, y0, count=1000):
    model = SmoothModel(params)
    start = time.perf_counter()
    y = np.asarray(y0, dtype=float)
    with np.errstate(all="ignore"):  # rejected trial steps into the wall overflow harmlessly
        for _ in range(count):
            y = solve_ivp(model.rhs, (0.0, 2 * np.pi), y, method="DOP853", rtol=1e-10, atol=1e-12).y[:, -1]
    return time.perf_counter() - start


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
        run_cli(["info", "--preset", "fig10"])  # compile and cache once, as an installed user has
        for case, extra in CASES.items():
            say(f"speed: slosh-bif shoot, {case}")
            seconds, peak = run_cli([*SHOOT, *extra, "--out", os.path.join(tmp, "shoot")])
            params = get_preset("fig10").params.with_overrides(extra[1::2])
            say(f"speed: {periods} scipy DOP853 periods, {case}")
            reference = _scipy_periods(params, get_preset("fig10").state_for(params), periods) * (
                1000 / periods
            )
            rows.append(
                dict(
                    case=f"shoot --no-switch, {case}",
                    seconds=seconds,
                    reference_seconds=reference,
                    ratio=seconds / reference,
                    target=0.3,
                    peak_rss_mb=peak,
                    note="whole process against 1,000 one-period scipy DOP853 integrations (rtol 1e-10)"
                    + (" (100 measured, scaled)" if quick else ""),
                )
            )
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
            dict(
                case="shoot --model impact --set sigma=5, fig10 (8)",
                seconds=impact_branch,
                reference_seconds=smooth_branch,
                ratio=impact_branch / smooth_branch,
                target=1 / 3,
                peak_rss_mb=np.nan,
                note="whole process against the (9) branch above; (8)'s symmetric branch from sigma = "
                "5, on the half-period map, ends at its grazing, sigma = 0.514",
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
        dict(
            case="simulate (8), fig10, 100 periods",
            seconds=seconds["impact"],
            reference_seconds=seconds["smooth"],
            ratio=seconds["impact"] / seconds["smooth"],
            target=0.1,
            peak_rss_mb=np.nan,
            note="in process, best of 3, against (9) at n = 50 compiled; impact times to 1e-10",
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
