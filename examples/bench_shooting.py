"""Speed target of the shooting issue, and the integrators charted speed against accuracy.

1. The whole symmetric branch of 2pi-orbits of (9) for the Fig. 10 set (n = 50, Abar = 3) over
   sigma in [-6, 8], every special point located (multiple shooting, 4 arcs, compiled DOP853),
   against 1,000 one-period integrations of (9) by scipy's solve_ivp DOP853 at rtol = 1e-10,
   atol = 1e-12, measured in the same run (the bar is the ratio, not seconds).
2. Work-precision of one period of (9) at n = 50 (Fig. 10 set) and n = 6 (Fig. 12 set): error of
   the end state against a tight reference (compiled DOP853 at rtol 1e-13), against time, for the
   compiled DOP853 and scipy's DOP853, RK45, Radau and LSODA (the implicit ones with and without
   the analytic Jacobian). Writes examples/charts/integrators.png and .csv.

Run:  python examples/bench_shooting.py [--repeats 3] [--out examples/charts]
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from slosh_bif import SmoothModel, get_preset, integrator
from slosh_bif.continuation import continuation
from slosh_bif.orbits import SHOOTING_OPTIONS
from slosh_bif.shooting import ShootingProblem, orbit_at

FIG10_ORBIT_GUESS = np.array([-2.29697839, 0.4870925, 0.62950163, -1.6026986])  # a simulated state


def one_period_scipy(params, y0):
    model = SmoothModel(params)
    return solve_ivp(model.rhs, (0.0, 2 * np.pi), y0, method="DOP853", rtol=1e-10, atol=1e-12)


def speed_target(repeats):
    P = get_preset("fig10").params
    y0 = get_preset("fig10").state0
    one_period_scipy(P, y0)
    baseline = []
    for _ in range(repeats):
        t = time.perf_counter()
        for _ in range(100):
            one_period_scipy(P, y0)
        baseline.append((time.perf_counter() - t) * 10)  # scaled to 1,000 integrations
    problem = ShootingProblem(P, segments=4)
    orbit_at(problem, problem.initial_states(FIG10_ORBIT_GUESS), 1.0)  # compile/load outside the timing
    branch_times, branch = [], None
    for _ in range(repeats):
        problem = ShootingProblem(P, segments=4)
        t = time.perf_counter()
        start = orbit_at(problem, problem.initial_states(FIG10_ORBIT_GUESS), 1.0, tol=1e-9)
        branch = continuation(problem, problem.initial_states(start.y0), 1.0, param="sigma", options=dataclasses.replace(SHOOTING_OPTIONS, p_min=-6.0, p_max=8.0))
        branch_times.append(time.perf_counter() - t)
    base, mine = np.median(baseline), np.median(branch_times)
    print(f"1,000 one-period DOP853 integrations (scipy, rtol 1e-10): median {base:.2f} s (of {repeats})")
    print(f"whole symmetric branch, sigma in [-6, 8]: median {mine:.2f} s, {len(branch)} points, {problem.evaluations} arc integrations,")
    print("  special points: " + ", ".join(f"{s.kind} {s.p:.5f}" for s in branch.special))
    print(f"ratio branch / baseline = {mine / base:.3f} (target < 1)")
    return base, mine


def work_precision(out: Path, repeats):
    rows = []
    for preset in ("fig10", "fig12"):
        P = get_preset(preset).params
        y0 = get_preset(preset).state0
        model = SmoothModel(P)
        ref = integrator.integrate(P, y0, 0.0, 2 * np.pi, rtol=1e-13, atol=1e-15).z
        methods = {
            "compiled DOP853": lambda r: integrator.integrate(P, y0, 0.0, 2 * np.pi, rtol=r, atol=r * 1e-2).z,
            "scipy DOP853": lambda r: solve_ivp(model.rhs, (0, 2 * np.pi), y0, method="DOP853", rtol=r, atol=r * 1e-2).y[:, -1],
            "scipy RK45": lambda r: solve_ivp(model.rhs, (0, 2 * np.pi), y0, method="RK45", rtol=r, atol=r * 1e-2).y[:, -1],
            "scipy LSODA": lambda r: solve_ivp(model.rhs, (0, 2 * np.pi), y0, method="LSODA", rtol=r, atol=r * 1e-2).y[:, -1],
            "scipy Radau (FD Jacobian)": lambda r: solve_ivp(model.rhs, (0, 2 * np.pi), y0, method="Radau", rtol=r, atol=r * 1e-2).y[:, -1],
            "scipy Radau (analytic Jacobian)": lambda r: solve_ivp(model.rhs, (0, 2 * np.pi), y0, method="Radau", rtol=r, atol=r * 1e-2, jac=model.jac).y[:, -1],
        }
        for name, run in methods.items():
            for rtol in (1e-5, 1e-7, 1e-9, 1e-11):
                if name.startswith("scipy Radau") and rtol < 1e-9:
                    continue  # minutes per point, and no better than the explicit methods
                times = []
                for _ in range(repeats):
                    t = time.perf_counter()
                    z = run(rtol)
                    times.append(time.perf_counter() - t)
                rows.append({"preset": preset, "n": P.n, "method": name, "rtol": rtol, "seconds": float(np.median(times)), "error": float(np.max(np.abs(z - ref)))})
                print(f"{preset} n={P.n:2d} {name:32s} rtol {rtol:.0e}: {rows[-1]['seconds'] * 1e3:9.2f} ms  error {rows[-1]['error']:.2e}")
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "integrators.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    for ax, preset in zip(axes, ("fig10", "fig12")):
        sub = [r for r in rows if r["preset"] == preset]
        for k, name in enumerate(dict.fromkeys(r["method"] for r in sub)):
            pts = [r for r in sub if r["method"] == name]
            ax.loglog([r["error"] for r in pts], [r["seconds"] for r in pts], "o-", color=f"C{k}", label=name)
        ax.set_xlabel("max error of the state after one period")
        ax.set_ylabel("seconds (median)")
        ax.set_title(f"one period of (9), {preset} set (n = {sub[0]['n']})")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "integrators.png", dpi=130)
    print(f"wrote {out / 'integrators.png'} and {out / 'integrators.csv'}")
    # speed ratio at equal error: interpolate scipy DOP853 time at the compiled method's errors
    for preset in ("fig10", "fig12"):
        fast = sorted((r["error"], r["seconds"]) for r in rows if r["preset"] == preset and r["method"] == "compiled DOP853")
        slow = sorted((r["error"], r["seconds"]) for r in rows if r["preset"] == preset and r["method"] == "scipy DOP853")
        ratios = [np.exp(np.interp(np.log(e), np.log([s[0] for s in slow]), np.log([s[1] for s in slow]))) / t for e, t in fast if slow[0][0] <= e <= slow[-1][0]]
        if ratios:
            print(f"{preset}: scipy DOP853 / compiled DOP853 time at equal error: median {np.median(ratios):.0f}x")


def main():
    np.seterr(all="ignore")  # scipy's trial steps deep in the wall overflow; the error control rejects them
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--out", type=Path, default=Path("examples/charts"))
    args = parser.parse_args()
    if not integrator.HAVE_NUMBA:
        print("numba is not installed: the compiled path is unavailable (pip install -e '.[fast]')")
    speed_target(args.repeats)
    work_precision(args.out, args.repeats)


if __name__ == "__main__":
    main()
