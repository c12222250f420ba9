"""The frequency-response question: the amplitude of X at a few detunings of the Fig. 10 and
Fig. 13 sets by every method the package has ((46), the slow flow (45), (8), (9), shooting on
(9)), against reference orbits found by shooting at rtol 1e-12 from a settled simulation.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from benchmarks.timing import PERIOD, first_harmonic, timed
from slosh_bif.continuation import ContinuationOptions
from slosh_bif.model.presets import get_preset
from slosh_bif.orbits.starts import settle_and_shoot
from slosh_bif.simulation.direct import SimulationSettings, simulate
from slosh_bif.slowflow.critical import critical_forcing
from slosh_bif.slowflow.flow import SlowFlow
from slosh_bif.slowflow.steady_states import frequency_response
from slosh_bif.studies.chart.critical import critical_forcing_full

# Detunings of the frequency-response question: where (9) has a stable 2pi-orbit that a
# simulation from the preset's initial state settles on (checked on every run).
FR_SIGMAS = {"fig10": (-6.0, -1.2, 0.7, 4.0, 6.0), "fig13": (-3.0, -2.0, 0.5, 1.0)}
QUICK_FR_SIGMAS = {"fig10": (-6.0, 0.7), "fig13": (-2.0, 1.0)}

REFERENCE_SEGMENTS = 4  # arcs of multiple shooting, as in `slosh-bif shoot`


# --- the frequency-response question -------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Reference:
    """The reference answer at one sigma: a stable 2pi-orbit of (9) and how well it is known."""

    preset: str
    sigma: float
    A1: float
    self_error: float  # |A1(rtol 1e-12) - A1(rtol 1e-10)| / A1
    max_multiplier: float
    y0: np.ndarray


def reference_orbits(preset: str, sigmas) -> list:
    """The reference of each sigma (raises when (9) does not settle on a stable orbit there)."""
    pre = get_preset(preset)
    refs = []
    for sigma in sigmas:
        params = pre.params.replace(sigma=float(sigma))
        orbit, A1 = settle_and_shoot(params, pre.state0, 1e-12, sim_rtol=1e-9, segments=REFERENCE_SEGMENTS)
        if not (orbit.converged and orbit.stable):
            raise RuntimeError(
                f"{preset}, sigma = {sigma}: no stable orbit near the settled state ({orbit.message})"
            )
        _, A1_coarse = settle_and_shoot(params, orbit.y0, 1e-10, first=0, segments=REFERENCE_SEGMENTS)
        refs.append(
            Reference(
                preset,
                float(sigma),
                A1,
                abs(A1_coarse - A1) / A1,
                float(np.max(np.abs(orbit.multipliers))),
                orbit.y0,
            )
        )
    return refs


def _critical_row(ref):
    """Abar_b of (46) against Abar_c of (9) (:func:`~slosh_bif.studies.chart.critical.critical_forcing_full`:
    the least forcing at which the boundary of stable period-1 orbits with wall contact lies, over
    every family at that sigma): the same question, "down to which forcing is there a resonant
    response?", asked of both models."""
    params = get_preset(ref.preset).params.replace(sigma=ref.sigma)
    full = critical_forcing_full(params, ref.y0)
    slow = critical_forcing(params, ref.sigma)
    corrected = critical_forcing(params, ref.sigma, model="corrected")

    def rel(value):
        return abs(value - full.Abar_c) / full.Abar_c if np.isfinite(full.Abar_c) else np.nan

    return dict(
        preset=ref.preset,
        sigma=ref.sigma,
        Abar_b_slow_flow=slow.Abar_b,
        slow_flow_kind=slow.kind,
        Abar_b_smooth_model=full.Abar_c,
        smooth_model_kind=full.bounded_by,
        relative_difference=rel(slow.Abar_b),
        Abar_b_corrected=corrected.Abar_b,
        corrected_kind=corrected.kind,
        relative_difference_corrected=rel(corrected.Abar_b),
    )


def _interp_stable(fr, sigma, target):
    """A of the stable states of (46) at sigma (interpolated on the branches); the one nearest
    ``target`` (several may coexist; the nearest is the kindest reading), NaN if none."""
    found = []
    for b in fr.branches:
        p, A = b.p, b.x[:, 0]
        for i in np.flatnonzero((p[:-1] - sigma) * (p[1:] - sigma) <= 0):
            if b.stable[i] and b.stable[i + 1] and p[i + 1] != p[i]:
                found.append(A[i] + (sigma - p[i]) / (p[i + 1] - p[i]) * (A[i + 1] - A[i]))
    return min(found, key=lambda a: abs(a - target)) if found else np.nan


def _methods(preset, refs):
    """Each method of the question: (name, knob name, knob values, answer(knob) -> A1 per sigma)."""
    pre = get_preset(preset)
    sigmas = [r.sigma for r in refs]
    targets = [r.A1 for r in refs]
    lo, hi = min(sigmas) - 1.0, max(sigmas) + 1.0

    def continuation(model):
        def answer(step_max):
            options = ContinuationOptions(step=min(0.05, step_max), step_max=step_max)
            fr = frequency_response(pre.params, sigma_min=lo, sigma_max=hi, options=options, model=model)
            return [_interp_stable(fr, s, a) for s, a in zip(sigmas, targets)]

        return answer

    def slow_flow_45(periods):
        out = []
        for s in sigmas:
            flow = SlowFlow(pre.params.replace(sigma=s))
            A0, psi0 = flow.start_from_state(pre.state0)
            traj = flow.integrate(A0, psi0, (0.0, pre.params.eps * periods * PERIOD), rtol=1e-8, atol=1e-10)
            out.append(np.nan if traj.escaped else float(traj.A[-1]))
        return out

    def simulated(model):
        def answer(periods):
            out = []
            for s in sigmas:
                sim = simulate(
                    pre.params.replace(sigma=s),
                    pre.state0,
                    periods * PERIOD,
                    settings=SimulationSettings(model=model, rtol=1e-8, atol=1e-10, sample_step=0.05),
                )
                out.append(first_harmonic(sim.t, sim.y[0], 10) if sim.success else np.nan)
            return out

        return answer

    def shooting(rtol):
        # Newton needs a start in the orbit's basin, from a loose simulation; its cost counts.
        return [
            settle_and_shoot(
                pre.params.replace(sigma=s), pre.state0, rtol, sim_rtol=1e-7, segments=REFERENCE_SEGMENTS
            )[1]
            for s in sigmas
        ]

    return [
        ("eq. 46 continuation", "step_max", (2.0, 0.5, 0.1), continuation("slowflow")),
        ("corrected slow flow continuation", "step_max", (2.0, 0.5, 0.1), continuation("corrected")),
        ("slow flow (45) integrated", "periods", (30, 100, 300), slow_flow_45),
        ("impact model (8) simulated", "periods", (30, 100, 300), simulated("impact")),
        ("smooth model (9) simulated", "periods", (30, 100, 300), simulated("smooth")),
        ("shooting on (9)", "rtol", (1e-6, 1e-8, 1e-10), shooting),
    ]


def frequency_response_bench(*, quick: bool = False, repeats: int = 3, progress=None):
    """Rows ``(preset, method, knob, value, seconds, error, answers, reference)`` per method and
    knob value, the reference rows, and the critical-forcing rows (:func:`_critical_row`).
    ``error`` is the largest relative error over the sigmas where the method gave an answer; ``failures``
    counts the sigmas where it gave none (the slow
    flow escaping from S+, a simulation failing, Newton not converging)."""
    say = progress or (lambda message: None)
    sigma_sets = QUICK_FR_SIGMAS if quick else FR_SIGMAS
    rows, ref_rows, crit_rows = [], [], []
    for preset, sigmas in sigma_sets.items():
        say(f"frequency response, {preset}: reference orbits (shooting at rtol 1e-12)")
        refs = reference_orbits(preset, sigmas)
        ref_rows += [
            dict(
                preset=preset,
                sigma=r.sigma,
                A1=r.A1,
                self_error=r.self_error,
                max_multiplier=r.max_multiplier,
            )
            for r in refs
        ]
        exact = np.array([r.A1 for r in refs])
        say(
            f"critical forcing, {preset}: Abar_b of (46) against Abar_c of (9) (every family at "
            "sigma, continued in Abar)"
        )
        crit_rows += [_critical_row(r) for r in (refs[:1] if quick else refs)]
        for name, knob, values, answer in _methods(preset, refs):
            for value in values[:2] if quick else values:
                say(f"frequency response, {preset}: {name}, {knob} = {value:g}")
                seconds, A1, runs = timed(
                    lambda: answer(value), repeats=repeats if not quick else 1, min_seconds=0.0
                )
                A1 = np.asarray(A1, dtype=float)
                rel = np.abs(A1 - exact) / exact
                rows.append(
                    dict(
                        preset=preset,
                        method=name,
                        knob=knob,
                        value=value,
                        seconds=seconds,
                        runs=runs,
                        error=float(np.nanmax(rel)) if np.any(np.isfinite(rel)) else np.nan,
                        failures=int(np.sum(~np.isfinite(rel))),
                        answers=" ".join(f"{a:.6g}" for a in A1),
                        reference=" ".join(f"{a:.6g}" for a in exact),
                    )
                )
    return rows, ref_rows, crit_rows
