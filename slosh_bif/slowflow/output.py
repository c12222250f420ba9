"""Writing frequency-response curves and critical-forcing curves as CSV and PNG.

CSV rows follow branch order; ``stable`` is 1 or 0 and ``special`` is empty or one of LP, BP, END.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from slosh_bif.report.tables import write_rows
from slosh_bif.slowflow.steady_states import FrequencyResponse

__all__ = ["write_frc_csv", "plot_frc", "write_critical_csv", "plot_critical", "model_label"]


def model_label(model: str) -> str:
    """How a figure names the slow flow it shows."""
    return "eq. 46" if model == "slowflow" else "corrected: wall's kappa and clearance"


FRC_COLUMNS = ("component", "sigma", "Abar", "A", "psi", "alpha", "stable", "special")


def frc_rows(fr: FrequencyResponse):
    for component, branch in enumerate(fr.branches):
        alpha = fr.alpha(branch)
        labels = branch.special_labels()
        for i in range(len(branch)):
            sigma, Abar = (
                (branch.p[i], fr.params.Abar) if branch.param == "sigma" else (fr.params.sigma, branch.p[i])
            )
            psi = (branch.x[i, 1] + np.pi) % (2 * np.pi) - np.pi
            yield dict(
                component=component,
                sigma=sigma,
                Abar=Abar,
                A=branch.x[i, 0],
                psi=psi,
                alpha=alpha[i],
                stable=int(branch.stable[i]),
                special=labels[i],
            )


def write_frc_csv(fr: FrequencyResponse, path) -> Path:
    return write_rows(frc_rows(fr), FRC_COLUMNS, path, digits=17)


def plot_frc(fr: FrequencyResponse, path, *, title=None) -> Path:
    from slosh_bif.report.plotting import branch_legend, drawn, plot_branch, pyplot, save_figure

    fig, ax = pyplot().subplots(figsize=(8, 5.5))
    for k, branch in enumerate(fr.branches):
        plot_branch(
            ax,
            branch,
            branch.x[:, 0],
            color=f"C{k}",
            label=f"component {k}" if len(fr.branches) > 1 else None,
        )
    ax.axhline(fr.A_min, color="0.5", lw=0.8, ls=":")
    ax.annotate(
        "A_min (manifold end)",
        (ax.get_xlim()[0], fr.A_min),
        textcoords="offset points",
        xytext=(4, 4),
        fontsize=8,
        color="0.4",
    )
    branch_legend(ax, **drawn(fr.branches))
    by_abar = bool(fr.branches) and fr.branches[0].param == "Abar"
    ax.set_xlabel(r"forcing $\bar A$" if by_abar else r"detuning $\sigma$")
    ax.set_ylabel(f"amplitude A of X (slow flow, {model_label(fr.model)})")
    P = fr.params
    fixed = f"sigma = {P.sigma:g}" if by_abar else f"Abar = {P.Abar:g}"
    ax.set_title(
        title
        or f"{'Forcing' if by_abar else 'Frequency'} response on S+: {fixed}, gamma = {P.gamma:g}, "
        f"beta = {P.beta:g}, n = {P.n}, pbar = {P.pbar}"
    )
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return save_figure(fig, path, dpi=120)


def write_critical_csv(curve, path) -> Path:
    columns = ("sigma", "Abar_b", "A", "kind")
    rows = (
        dict(zip(columns, (float(s), float(a), float(x), str(k))))
        for s, a, x, k in zip(curve.sigma, curve.Abar_b, curve.A, curve.kind)
    )
    return write_rows(rows, columns, path, digits=17)


def plot_critical(curve, path, *, title=None) -> Path:
    from slosh_bif.report.plotting import pyplot, save_figure

    fig, ax = pyplot().subplots(figsize=(8, 5.5))
    end = curve.end_branch
    ax.plot(end.p, end.x[:, 0], ":", color="0.5", lw=1, label="end-point condition (A = A_min)")
    if curve.upper_end_branch is not None:
        top = curve.upper_end_branch
        ax.plot(top.p, top.x[:, 0], "-.", color="0.5", lw=1, label="end-point condition (upper end of S+)")
    for k, b in enumerate(curve.fold_branches):
        ax.plot(b.p, b.x[:, 1], "--", color="0.5", lw=1, label="fold of A(Abar)" if k == 0 else None)
    for kind, color, label in (
        ("END", "tab:blue", "Abar_b at the manifold end"),
        ("LP", "tab:red", "Abar_b at an interior fold"),
    ):
        sel = curve.kind == kind
        ax.plot(curve.sigma[sel], curve.Abar_b[sel], ".", color=color, ms=5, label=label)
    ax.plot(curve.sigma, curve.Abar_b, "-", color="k", lw=1.2, label=r"critical forcing $\bar A_b(\sigma)$")
    P = curve.params
    ax.set_xlabel(r"detuning $\sigma$")
    ax.set_ylabel(r"forcing amplitude $\bar A$")
    ax.set_ylim(0, 2.0 * max(curve.Abar_b.max(), 1e-3))
    ax.set_title(
        title
        or f"Critical forcing for steady states on S+ ({model_label(curve.model)}): gamma = "
        f"{P.gamma:g}, beta = {P.beta:g}, n = {P.n}, pbar = {P.pbar}"
    )
    ax.text(
        0.02, 0.95, "below the curve: no steady state on S+", transform=ax.transAxes, fontsize=8, va="top"
    )
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(alpha=0.3)
    return save_figure(fig, path, dpi=120)
