"""The paper's figures 3-15, regenerated from scratch with the paper's parameters.

Each ``figN(out, quick=False)`` computes what the figure shows and writes ``out/figN.png``;
``quick=True`` shortens simulations and coarsens grids (for tests). :data:`NOTES` says, per
figure, where our result differs from the printed one; the docs' gallery (docs/findings/gallery.md) repeats
it.

Figures 1 and 2 are sketches and are not reproduced. Fig. 4 (the modal masses of a cylinder, which
the paper takes from Abramson) is computed by :mod:`slosh_bif.model.tank`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from slosh_bif.flows.noise import band_limited_noise
from slosh_bif.model import manifold, restitution
from slosh_bif.model.manifold import project_on_manifold
from slosh_bif.model.params import Params
from slosh_bif.model.presets import get_preset
from slosh_bif.model.tank import cylinder_modes
from slosh_bif.report.plotting import (
    plot_manifold,
    plot_projection,
    plot_time_history,
    pyplot,
    save_figure,
)
from slosh_bif.simulation.direct import Noise, SimulationSettings, simulate
from slosh_bif.simulation.output import plot_motion_on_manifold
from slosh_bif.simulation.regimes import classify
from slosh_bif.simulation.wavelet import morlet_transform
from slosh_bif.slowflow.flow import SlowFlow, triangle_wave

__all__ = ["FIGURES", "NOTES", "make_figures"]

NOTES = {
    "fig3": "Reproduces eq. (19). I(n, p) is the integral (18) at fixed p; I(n, pbar) at fixed pbar = 2p - "
    "n.",
    "fig4": "Computed from the potential-flow series (slosh_bif.model.tank), not read off Abramson's "
    "chart; m_0 is m_F minus all modes (400 terms and the rest).",
    "fig5": "Reproduces the figure: f is a triangle wave of amplitude alpha turning at T0 = eta (mod pi).",
    "fig6": "kappa = 0.729 gives A_min = 0.0993, not the printed 0.06 (alpha_min = 0.990 agrees with the "
    "caption).",
    "fig7": "Reproduces the trend (kappa independent of A for pbar = 0); kappa from eq. (39) on S+.",
    "fig8": "SIM (36) with rho(A) from eq. (39); the branches end at A_min(kappa(A_min)).",
    "fig9": "The paper's capture lasts to tau ~ 100 (a) and ~350 (b); our runs of the printed parameters "
    "keep it to tau ~ 330-470 (see derivations/REPORT.md).",
    "fig10": "In (9) the response is 1:1 resonant with near-constant amplitude but not periodic: the "
    "2pi-orbit there is unstable (multiplier 16, sigma = 1 lies beyond the NS point 0.881 and the "
    "fold 0.924). About 3.4 impacts a period (double hits on one wall), not 2.",
    "fig11": "No impacts after the transient; beta = 0.3 adds the particle's free oscillation. Wavelets: "
    "Morlet, amplitude-normalised.",
    "fig12": "Strongly modulated as printed; with n = 6 the restitution of eq. (21) (0.27) is far from the "
    "wall's (0.63), so (8) and (9) modulate differently.",
    "fig13": "Transition to the periodic response as printed; the settled amplitude (peak |X| 0.28) is 10 % "
    "below the slow flow's 0.31.",
    "fig14": "Band-limited noise (std 4, cutoff 10, seed 0) instead of one draw per step: see "
    "slosh_bif.flows.noise for why and for the equivalent step.",
    "fig15": "sigma_bar not printed; 4 assumed. With cutoff 10 the noise modulates the envelope by about 50 "
    "% (the paper: 'no major qualitative difference').",
}


def _fig(name, out):
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    return out / f"{name}.png"


def fig3(out, *, quick=False):
    """The integral I of eqs. (18)-(19): a) over (n, p); b) over (n, pbar); c) against p for
    n = 0, 1, 5, 50; d) zoom on p in [0, 5]."""
    plt = pyplot()
    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    n = np.linspace(0, 50, 60 if quick else 201)
    p = np.linspace(0, 5, 40 if quick else 161)
    N, Pp = np.meshgrid(n, p)
    for ax, values, label in (
        (axes[0, 0], restitution.I(N, 2 * Pp - N), "p"),
        (axes[0, 1], restitution.I(N, Pp), r"$\bar p$"),
    ):
        from matplotlib.colors import LogNorm

        mesh = ax.pcolormesh(
            N, Pp, values, shading="auto", cmap="viridis", norm=LogNorm()
        )  # I spans 3 decades
        fig.colorbar(mesh, ax=ax, label="I")
        ax.set_xlabel("n")
        ax.set_ylabel(label)
        ax.set_title(f"I(n, {label})")
    for ax, p_max in ((axes[1, 0], 20.0), (axes[1, 1], 5.0)):
        p_line = np.linspace(0, p_max, 200)
        for n_value, color in ((0, "tab:pink"), (1, "tab:red"), (5, "tab:blue"), (50, "k")):
            ax.plot(
                p_line,
                restitution.I(n_value, 2 * p_line - n_value),
                "-",
                color=color,
                label=f"I(n, p), n = {n_value}",
            )
            ax.plot(
                p_line,
                restitution.I(n_value, p_line),
                "--",
                color=color,
                label=rf"I(n, $\bar p$), n = {n_value}",
            )
        ax.set_xlabel(r"p or $\bar p$")
        ax.set_ylabel("I")
        ax.set_title(f"against p in [0, {p_max:g}]")
    axes[1, 0].legend(fontsize=7, ncol=2)
    return save_figure(fig, _fig("fig3", out))


def fig4(out, *, quick=False):
    """The modal masses m_1, m_2, m_3 of the first three antisymmetric sloshing modes and the fixed
    mass m_0 of an upright cylinder, over the total liquid mass, against the depth ratio h/r."""
    ratios = np.linspace(0.05, 3.0, 40 if quick else 300)
    modes = [cylinder_modes(1.0, h) for h in ratios]
    fig, ax = pyplot().subplots(figsize=(7, 5))
    ax.plot(ratios, [m.fixed_ratio for m in modes], ":", color="k", lw=2, label=r"$m_0/m_F$")
    for k, style in ((0, "-."), (1, "--"), (2, "-")):
        ax.plot(ratios, [m.mass_ratio[k] for m in modes], style, lw=1.6, label=rf"$m_{k + 1}/m_F$")
    ax.set_xlabel("depth ratio h/r")
    ax.set_ylabel("mass ratio")
    ax.set_yscale("log")
    ax.set_title("Modal masses of a cylindrical tank (potential flow; Abramson 1966)")
    ax.legend()
    ax.grid(alpha=0.3, which="both")
    return save_figure(fig, _fig("fig4", out))


def fig5(out, *, quick=False):
    """f(T0) of the multiple-scales ansatz (29), (35) for alpha = 1, eta = pi/2."""
    T0 = np.linspace(0, 4 * np.pi, 400 if quick else 2001)
    fig, ax = pyplot().subplots(figsize=(7, 4))
    ax.plot(T0, triangle_wave(T0, 1.0, np.pi / 2)[0], "k-")
    ax.set_xlabel(r"$T_0$")
    ax.set_ylabel(r"$f(T_0)$")
    ax.set_title(r"$f(T_0) = (2\alpha/\pi)\,\arcsin(\cos(T_0 - \eta))$, $\alpha = 1$, $\eta = \pi/2$")
    ax.grid(alpha=0.3)
    return save_figure(fig, _fig("fig5", out))


def fig6(out, *, quick=False):
    """The SIM (36) for kappa = 0.729 (the caption's beta = 0.2 does not enter (36))."""
    plt = pyplot()
    rho = float(restitution.rho(0.729))
    fig, ax = plt.subplots(figsize=(6.5, 5))
    plot_manifold(ax, rho, A_max=2.0)
    A_end, alpha_end = float(manifold.a_min(rho)), float(manifold.alpha_min(rho))
    ax.annotate(
        f"A_min = {A_end:.4f} (printed 0.06)\nalpha_min = {alpha_end:.3f} (printed 0.99)",
        (A_end, alpha_end),
        xytext=(0.5, 0.4),
        textcoords="data",
        arrowprops=dict(arrowstyle="->"),
        fontsize=9,
    )
    ax.set_title(r"SIM, $\kappa$ = 0.729")
    ax.legend(loc="upper left", fontsize=8)
    return save_figure(fig, _fig("fig6", out))


_FIG78 = dict(lam=0.25, chi=1.0)
_FIG78_N = ((6, "tab:blue"), (10, "tab:red"), (50, "k"))


def _on_manifold(n, pbar, quick):
    """(A, kappa, alpha) along S+ from its end, by eq. (39)."""
    P = Params(eps=0.05, beta=0.0, gamma=0.0, sigma=0.0, Abar=0.0, n=n, pbar=pbar, **_FIG78)
    A_end = SlowFlow(P).A_min
    A = A_end + (3.0 - A_end) * np.linspace(0, 1, 40 if quick else 200) ** 2
    # Rounding may put the end point itself just off the manifold: keep the points that solve (39).
    solved = restitution.kappa_on_manifold(A, _FIG78["lam"], _FIG78["chi"], n, pbar, strict=False)
    ok = solved.exists
    return A[ok], solved.kappa[ok], solved.alpha[ok], solved.rho[ok]


def fig7(out, *, quick=False):
    """kappa against A on S+ (eq. 39) for lam = 0.25, chi = 1, n = 6, 10, 50 and pbar = -2, 0, 2."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(13, 4), sharey=True)
    for ax, pbar in zip(axes, (-2, 0, 2)):
        for n, color in _FIG78_N:
            A, kappa, _, _ = _on_manifold(n, pbar, quick)
            ax.plot(A, kappa, color=color, label=f"n = {n}")
        ax.set_title(rf"$\bar p$ = {pbar}")
        ax.set_xlabel("amplitude A")
    axes[0].set_ylabel(r"restitution coefficient $\kappa$")
    axes[0].legend()
    return save_figure(fig, _fig("fig7", out))


def fig8(out, *, quick=False):
    """The SIM (36) with rho(A) of eq. (39), same parameters as Fig. 7."""
    plt = pyplot()
    fig, axes = plt.subplots(2, 3, figsize=(13, 8))
    for col, pbar in enumerate((-2, 0, 2)):
        for n, color in _FIG78_N:
            A, _, alpha, rho = _on_manifold(n, pbar, quick)
            for ax in axes[:, col]:
                ax.plot(A, alpha, "-", color=color, label=f"n = {n}")
                ax.plot(A, manifold.alpha(A, rho, manifold.UNSTABLE), "--", color=color)
        axes[0, col].set_title(rf"$\bar p$ = {pbar} (solid: S+, dashed: unstable)")
        # The branches differ only near the fold: zoom there in the second row.
        axes[1, col].set_xlim(0, 0.4)
        axes[1, col].set_ylim(0.6, 1.4)
        axes[1, col].set_title("zoom on the fold", fontsize=9)
        axes[1, col].set_xlabel("amplitude A")
    for ax in axes[:, 0]:
        ax.set_ylabel(r"$\alpha$")
    axes[0, 0].legend()
    return save_figure(fig, _fig("fig8", out))


def fig9(out, *, quick=False):
    """Free vibrations: smooth-model time histories with the slow-flow envelope (43), and the
    impact model's motion on the SIM, for beta = 0 (a, b) and 0.3 (c, d)."""
    plt = pyplot()
    t_end = 150.0 if quick else 600.0
    fig, axes = plt.subplots(2, 2, figsize=(12, 8))
    for row, name in enumerate(["fig9a", "fig9b"]):
        preset = get_preset(name)
        P = preset.params
        smooth = simulate(P, preset.state0, t_end)
        impact = simulate(P, preset.state0, t_end, settings=SimulationSettings(model="impact"))
        proj = project_on_manifold(impact.t, impact.y)
        flow = SlowFlow(P)
        slow = flow.integrate(proj.A[0], 0.0, (P.eps * proj.t[0], P.eps * t_end), t_eval=P.eps * proj.t)
        plot_time_history(axes[row, 0], smooth.t, smooth.y, envelope=(slow.T1 / P.eps, slow.A))
        axes[row, 0].set_title(f"{name}: smooth model (9), beta = {P.beta:g}")
        axes[row, 0].legend(loc="upper right", fontsize=8)
        plot_manifold(axes[row, 1], float(flow.rho(1.0)[0]), A_max=3.2)
        plot_projection(axes[row, 1], proj, label="vibro-impact model (8)")
        axes[row, 1].plot(slow.A, slow.alpha, "k-", lw=2, alpha=0.4, label="slow flow (43)")
        axes[row, 1].set_title(f"{name}: motion on the SIM")
        axes[row, 1].legend(fontsize=8)
    return save_figure(fig, _fig("fig9", out))


def _response(name, out, *, quick, window=None, title=""):
    """Time history (in the paper's window) and motion on the SIM of a forced preset's response."""
    plt = pyplot()
    preset = get_preset(name)
    t_end = preset.t_window[1] * (0.2 if quick else 1.0)
    sim = simulate(preset.params, preset.state0, t_end, noise=Noise(std=preset.noise_std, seed=0))
    summary = classify(sim)
    fig, (ax_t, ax_m) = plt.subplots(1, 2, figsize=(13, 4.8), gridspec_kw=dict(width_ratios=[1.6, 1]))
    lo, hi = window if window is not None and not quick else (sim.t[0], sim.t[-1])
    shown = (sim.t >= lo) & (sim.t <= hi)
    plot_time_history(ax_t, sim.t[shown], sim.y[:, shown])
    ax_t.legend(loc="upper right", fontsize=8)
    ax_t.set_title(f"{title or name}: smooth model (9), regime {summary.regime}", fontsize=10)
    plot_motion_on_manifold(ax_m, sim, summary, project_on_manifold(sim.t, sim.y))
    return save_figure(fig, _fig(name, out))


def fig10(out, *, quick=False):
    """Resonant response: tau in [1100, 1200] and the motion on the SIM."""
    return _response("fig10", out, quick=quick, window=(1100, 1200), title="Fig. 10")


def fig11(out, *, quick=False):
    """Non-resonant responses for beta = 0 and 0.3: time histories and Morlet wavelet plots of X."""
    plt = pyplot()
    fig, axes = plt.subplots(2, 2, figsize=(13, 7.5))
    omegas = np.linspace(0.05, 2.0, 60 if quick else 200)
    for row, name in enumerate(["fig11a", "fig11b"]):
        preset = get_preset(name)
        t_end = preset.t_window[1] * (0.2 if quick else 1.0)
        sim = simulate(preset.params, preset.state0, t_end, settings=SimulationSettings(sample_step=0.05))
        plot_time_history(axes[row, 0], sim.t, sim.y)
        axes[row, 0].legend(loc="upper right", fontsize=8)
        axes[row, 0].set_title(
            f"{name}: beta = {preset.params.beta:g}, regime {classify(sim).regime}", fontsize=10
        )
        step = 4  # wavelet on tau steps of 0.2: Nyquist 15.7, far above the plotted band
        W = morlet_transform(sim.y[0, ::step], 0.05 * step, omegas)
        mesh = axes[row, 1].pcolormesh(sim.t[::step], omegas, W, shading="auto", cmap="jet")
        fig.colorbar(mesh, ax=axes[row, 1], label="|W| (amplitude of X)")
        axes[row, 1].set_xlabel(r"$\tau$")
        axes[row, 1].set_ylabel(r"angular frequency $\omega$")
        axes[row, 1].set_title("Morlet wavelet transform of X", fontsize=10)
    return save_figure(fig, _fig("fig11", out))


def fig12(out, *, quick=False):
    """Strongly modulated response, tau in [0, 5000], and its motion on the SIM."""
    return _response("fig12", out, quick=quick, title="Fig. 12")


def fig13(out, *, quick=False):
    """Transition from strongly modulated to periodic response (tau in [0, 3000])."""
    return _response("fig13", out, quick=quick, title="Fig. 13")


def fig14(out, *, quick=False):
    """The excitation (47), eps*(Abar cos tau + F_w): time history on [0, 200] and its spectrum."""
    plt = pyplot()
    preset = get_preset("fig14")
    P = preset.params
    noise = band_limited_noise(preset.noise_std, seed=0, duration=200.0)
    tau = np.linspace(0, 200, 20001)
    force = P.eps * (P.Abar * np.cos(tau) + noise(tau))
    fig, (ax_t, ax_f) = plt.subplots(1, 2, figsize=(13, 4.5))
    ax_t.plot(tau, force, lw=0.5, color="tab:blue")
    ax_t.set_xlabel(r"$\tau$")
    ax_t.set_ylabel("F")
    ax_t.set_title(
        rf"excitation, $\bar\sigma$ = {preset.noise_std:g}, $\varepsilon$ = {P.eps:g}, $\bar A$ = {P.Abar:g}",
        fontsize=10,
    )
    dt = tau[1] - tau[0]
    amplitude = 2 * np.abs(np.fft.rfft(force)) / tau.size
    omega = 2 * np.pi * np.fft.rfftfreq(tau.size, d=dt)
    keep = omega <= 20
    ax_f.plot(omega[keep], amplitude[keep], lw=0.7, color="tab:blue")
    ax_f.axvline(noise.cutoff, color="k", ls=":", lw=0.8, label=f"noise cutoff {noise.cutoff:g}")
    ax_f.set_xlabel(r"angular frequency $\omega$")
    ax_f.set_ylabel("|FFT| (amplitude)")
    ax_f.legend(fontsize=8)
    ax_f.set_title("spectrum: the forcing line at 1 on a flat band", fontsize=10)
    return save_figure(fig, _fig("fig14", out))


def fig15(out, *, quick=False):
    """Fig. 10's parameters with the noise of (47): time history and motion on the SIM."""
    return _response("fig15", out, quick=quick, title="Fig. 15")


FIGURES = {
    f.__name__: f
    for f in (fig3, fig4, fig5, fig6, fig7, fig8, fig9, fig10, fig11, fig12, fig13, fig14, fig15)
}


def make_figures(out, *, quick=False, only=None, progress=None):
    """Write every figure (or those named in ``only``) to ``out``; returns the paths."""
    names = list(FIGURES) if only is None else list(only)
    unknown = [n for n in names if n not in FIGURES]
    if unknown:
        raise ValueError(f"unknown figure(s) {unknown}; choose from {', '.join(FIGURES)}")
    paths = []
    for k, name in enumerate(names, 1):
        paths.append(FIGURES[name](out, quick=quick))
        if progress is not None:
            progress(f"{name} ({k} of {len(names)}): {paths[-1]}")
    return paths
