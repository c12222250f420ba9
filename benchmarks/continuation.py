"""Benchmark: pseudo-arclength continuation of (45)/(46) against a natural-parameter sweep.

For the Fig. 10 and Fig. 13 sets over sigma in [SIGMA_MIN, SIGMA_MAX]: the time per branch and per
point of `frequency_response`, and of a natural-parameter sweep that solves (46) for A with
scipy.optimize.newton (analytic derivative) at each sigma of a uniform grid (as many points as the
continuation used), starting from the previous solution. The sweep cannot pass a fold: it jumps to another
branch or fails, so it reports no fold.
Medians of REPEATS runs, measured in one process. Writes bench_continuation.csv and .png.

Usage: python -m benchmarks.continuation [OUT_DIR]
"""

import csv
import statistics
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy import optimize  # noqa: E402

from slosh_bif import get_preset  # noqa: E402
from slosh_bif.slowflow.flow import SlowFlow  # noqa: E402
from slosh_bif.slowflow.steady_states import frequency_response  # noqa: E402

SIGMA_MIN, SIGMA_MAX = -15.0, 8.0  # wide enough to hold the Fig. 13 fold (sigma = -13.13)
REPEATS = 5


def natural_sweep(params, sigmas, A0):
    """scipy's Newton on (46) in A at each sigma, from the previous solution (NaN where it fails)."""
    flow = SlowFlow(params)
    A, out = A0, []
    for sigma in sigmas:
        try:
            A = optimize.newton(
                lambda a: flow.steady_residual(max(a, flow.A_min), sigma=sigma),
                A,
                fprime=lambda a: flow.steady_residual_grad(max(a, flow.A_min), sigma=sigma)[0],
                tol=1e-12,
                maxiter=50,
            )
        except (RuntimeError, ValueError):
            A = np.nan
        out.append(A)
        if not np.isfinite(A):
            A = flow.A_min * 1.5  # restart somewhere on the manifold
    return np.array(out)


def timed(fn):
    times, result = [], None
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), result


def main(out=Path("results")):
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for name in ("fig10", "fig13"):
        params = get_preset(name).params
        t_cont, fr = timed(lambda: frequency_response(params, sigma_min=SIGMA_MIN, sigma_max=SIGMA_MAX))
        n_points = sum(len(b) for b in fr.branches)
        folds = sum(len(b.special_of("LP")) for b in fr.branches)
        sigmas = np.linspace(SIGMA_MIN, SIGMA_MAX, n_points)
        A0 = fr.branches[0].x[np.argmin(fr.branches[0].p), 0]
        with np.errstate(
            divide="ignore", invalid="ignore"
        ):  # the sweep probes A_min, where alpha has a square root
            t_sweep, A_sweep = timed(lambda: natural_sweep(params, sigmas, A0))
        jumps = int(np.sum(np.abs(np.diff(A_sweep)) > 0.2 * np.nanmax(A_sweep)))
        rows.append(
            dict(
                preset=name,
                points=n_points,
                continuation_s=t_cont,
                continuation_ms_per_point=1e3 * t_cont / n_points,
                folds_found=folds,
                sweep_s=t_sweep,
                sweep_ms_per_point=1e3 * t_sweep / n_points,
                sweep_folds_found=0,
                sweep_jumps_or_failures=jumps + int(np.sum(~np.isfinite(A_sweep))),
                per_point_speedup=t_sweep / t_cont,
            )
        )
    with open(out / "bench_continuation.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    for r in rows:
        print(
            f"{r['preset']}: continuation {r['continuation_s'] * 1e3:.1f} ms for {r['points']} "
            f"points ({r['continuation_ms_per_point']:.3f} ms/point, "
            f"{r['folds_found']} fold(s) located); natural sweep {r['sweep_s'] * 1e3:.1f} ms "
            f"({r['sweep_ms_per_point']:.3f} ms/point, no fold, "
            f"{r['sweep_jumps_or_failures']} jump(s)/failure(s)); continuation/sweep time per "
            f"point = {1 / r['per_point_speedup']:.2f}"
        )
    fig, ax = plt.subplots(figsize=(6, 4))
    x = np.arange(len(rows))
    ax.bar(
        x - 0.2, [r["continuation_ms_per_point"] for r in rows], 0.4, label="pseudo-arclength continuation"
    )
    ax.bar(
        x + 0.2, [r["sweep_ms_per_point"] for r in rows], 0.4, label="natural-parameter sweep (misses folds)"
    )
    ax.set_xticks(x, [r["preset"] for r in rows])
    ax.set_ylabel("ms per point (median of 5)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "bench_continuation.png", dpi=120)
    print(f"wrote {out / 'bench_continuation.csv'} and {out / 'bench_continuation.png'}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results"))
