"""CSV tables and work-precision charts of :mod:`benchmarks.run` (one CSV behind each PNG)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from benchmarks.against import AGAINST_COLUMNS
from benchmarks.speed import SPEED_COLUMNS
from slosh_bif.report.plotting import pyplot, save_figure
from slosh_bif.report.tables import write_rows

__all__ = [
    "equal_error_ratio",
    "write_integration",
    "write_frequency_response",
    "write_growth",
    "integration_ratios",
]


def equal_error_ratio(rows, preset, method, baseline="scipy DOP853"):
    """Median of (baseline time) / (method time) at equal error: both work-precision curves are
    interpolated log-log at 9 errors spread over the range they share; NaN if they share none."""

    def curve(name):
        pts = sorted(
            (r["error"], r["seconds"])
            for r in rows
            if r["preset"] == preset and r["method"] == name and r["error"] > 0
        )
        return np.log([p[0] for p in pts]), np.log([p[1] for p in pts])

    e_b, t_b = curve(baseline)
    e_m, t_m = curve(method)
    if len(e_b) < 2 or len(e_m) < 2:
        return np.nan
    lo, hi = max(e_b[0], e_m[0]), min(e_b[-1], e_m[-1])
    if lo >= hi:
        return np.nan
    at = np.linspace(lo, hi, 9)
    return float(np.median(np.exp(np.interp(at, e_b, t_b) - np.interp(at, e_m, t_m))))


def _lines(ax, rows, key, x, y, *, marker="o-"):
    """One line per distinct ``key`` value, through the rows' (x, y), in first-seen order."""
    for k, name in enumerate(dict.fromkeys(r[key] for r in rows)):
        pts = [r for r in rows if r[key] == name and np.isfinite(r[x]) and np.isfinite(r[y])]
        if pts:
            ax.plot([r[x] for r in pts], [r[y] for r in pts], marker, color=f"C{k % 10}", label=name)


def integration_ratios(rows) -> list:
    """(preset, n, method, speed ratio to scipy DOP853 at equal error) for every method."""
    out = []
    for preset in dict.fromkeys(r["preset"] for r in rows):
        n = next(r["n"] for r in rows if r["preset"] == preset)
        for method in dict.fromkeys(r["method"] for r in rows if r["preset"] == preset):
            out.append(
                dict(
                    preset=preset,
                    n=n,
                    method=method,
                    speedup_vs_scipy_DOP853=equal_error_ratio(rows, preset, method),
                )
            )
    return out


def write_integration(rows, out) -> list:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    paths = [
        write_rows(
            rows,
            ["preset", "n", "method", "rtol", "seconds", "runs", "nfev", "error"],
            out / "integrators.csv",
        )
    ]
    ratios = integration_ratios(rows)
    paths.append(
        write_rows(
            ratios,
            ["preset", "n", "method", "speedup_vs_scipy_DOP853"],
            out / "integrators_ratios.csv",
            digits=4,
        )
    )
    plt = pyplot()
    presets = list(dict.fromkeys(r["preset"] for r in rows))
    fig, axes = plt.subplots(2, len(presets), figsize=(6.5 * len(presets), 9), squeeze=False)
    for j, preset in enumerate(presets):
        sub = [r for r in rows if r["preset"] == preset]
        for i, (y, label) in enumerate(
            (("seconds", "seconds per period (median)"), ("nfev", "right-hand-side evaluations"))
        ):
            ax = axes[i, j]
            _lines(ax, sub, "method", "error", y)
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("max error of the state after one forcing period")
            ax.set_ylabel(label)
            ax.set_title(f"(9), {preset} set (n = {sub[0]['n']})")
            ax.grid(alpha=0.3, which="both")
        axes[0, j].legend(fontsize=7)
        fast = next((r for r in ratios if r["preset"] == preset and "numba" in r["method"]), None)
        if fast is not None and np.isfinite(fast["speedup_vs_scipy_DOP853"]):
            axes[0, j].text(
                0.02,
                0.02,
                f"compiled DOP853: {fast['speedup_vs_scipy_DOP853']:.0f}x faster than scipy DOP853 "
                "at equal error",
                transform=axes[0, j].transAxes,
                fontsize=8,
            )
    paths.append(save_figure(fig, out / "integrators.png"))
    return paths


def write_frequency_response(rows, ref_rows, crit_rows, out) -> list:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    # Column names that scripts read; Abar_b_smooth_model is Abar_c of (9).
    crit_columns = [
        "preset",
        "sigma",
        "Abar_b_slow_flow",
        "slow_flow_kind",
        "Abar_b_smooth_model",
        "smooth_model_kind",
        "relative_difference",
        "Abar_b_corrected",
        "corrected_kind",
        "relative_difference_corrected",
    ]
    paths = [
        write_rows(crit_rows, crit_columns, out / "critical_forcing.csv"),
        write_rows(
            rows,
            [
                "preset",
                "method",
                "knob",
                "value",
                "seconds",
                "runs",
                "error",
                "failures",
                "answers",
                "reference",
            ],
            out / "frequency_response.csv",
        ),
        write_rows(
            ref_rows,
            ["preset", "sigma", "A1", "self_error", "max_multiplier"],
            out / "frequency_response_reference.csv",
        ),
    ]
    plt = pyplot()
    presets = list(dict.fromkeys(r["preset"] for r in rows))
    fig, axes = plt.subplots(1, len(presets), figsize=(6.5 * len(presets), 5), squeeze=False)
    for ax, preset in zip(axes[0], presets):
        sub = [r for r in rows if r["preset"] == preset]
        _lines(ax, sub, "method", "error", "seconds")
        for r in (r for r in sub if np.isfinite(r["error"])):  # the knob value beside each point
            ax.annotate(
                f"{r['value']:g}",
                (r["error"], r["seconds"]),
                fontsize=6,
                xytext=(3, 3),
                textcoords="offset points",
            )
        failed = [r for r in sub if r["failures"] and np.isfinite(r["error"])]
        if failed:
            ax.plot(
                [r["error"] for r in failed],
                [r["seconds"] for r in failed],
                "kx",
                ms=9,
                label="no answer at some sigma (error over the rest)",
            )
        refs = [r for r in ref_rows if r["preset"] == preset]
        floor = max(r["self_error"] for r in refs)
        ax.axvline(max(floor, 1e-12), color="0.6", ls=":", label="reference's own error")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("largest relative error of A1 over the sigmas")
        ax.set_ylabel("seconds for all sigmas (median)")
        at = ", ".join(f"{r['sigma']:g}" for r in refs)
        ax.set_title(f"amplitude of X at sigma = {at}\n{preset} set")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    paths.append(save_figure(fig, out / "frequency_response.png"))
    return paths


def write_growth(rows, out) -> list:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    paths = [write_rows(rows, ["study", "x", "method", "seconds", "detail"], out / "growth.csv")]
    plt = pyplot()
    studies = (
        ("n", "wall exponent n (Fig. 10 set)"),
        ("interval", "forcing periods simulated (Fig. 10 set)"),
        ("regime map", "grid points (60 periods each)"),
    )
    fig, axes = plt.subplots(1, 3, figsize=(17, 5))
    for ax, (study, xlabel) in zip(axes, studies):
        _lines(ax, [r for r in rows if r["study"] == study], "method", "x", "seconds")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("seconds (median)")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    axes[0].set_title("branch and simulation against n")
    axes[1].set_title("simulation against interval length")
    axes[2].set_title("regime map against grid size and workers")
    paths.append(save_figure(fig, out / "growth.png"))
    return paths


def write_against(rows, out) -> list:
    """``against.csv`` and one line per case on stdout: its time over the earlier commit's."""
    for r in rows:
        floor = (
            f"; one step: {r['fixed_seconds']:.2f} s against {r['base_fixed_seconds']:.2f} s, floor "
            f"{r['floor_ratio']:.3f}"
            if np.isfinite(r["floor_ratio"])
            else ""
        )
        print(
            f"against {r['base']}: {r['case']}: {r['seconds']:.2f} s against {r['base_seconds']:.2f} s, "
            f"ratio {r['ratio']:.3f} (target <= {r['target']:g}){floor}"
        )
    Path(out).mkdir(parents=True, exist_ok=True)
    return [write_rows(rows, AGAINST_COLUMNS, Path(out) / "against.csv")]


def write_speed(rows, out) -> list:
    """``speed.csv`` and one line per row on stdout: each ratio (or time) beside its target."""
    for r in rows:
        if np.isfinite(r["ratio"]):
            verdict = f"ratio {r['ratio']:.3f} (target <= {r['target']:g})"
        else:
            verdict = f"(target < {r['target']:g} s)" if np.isfinite(r["target"]) else ""
        print(f"speed: {r['case']}: {r['seconds']:.2f} s {verdict}")
    Path(out).mkdir(parents=True, exist_ok=True)
    return [write_rows(rows, SPEED_COLUMNS, Path(out) / "speed.csv")]
