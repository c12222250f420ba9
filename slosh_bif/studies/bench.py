"""Work-precision benchmarks: what each method costs for the accuracy it gives.

Four questions, each measured in one process (medians of repeated runs; ratios, not seconds,
are what carry over between machines):

* **The frequency-response question** (:func:`frequency_response_bench`): the amplitude of X at a
  few detunings sigma of the Fig. 10 and Fig. 13 sets (first-harmonic amplitude A1 of X, as in
  ``slosh-bif compare``), answered by the eq. (46) continuation, by integrating the slow flow
  (45) to its steady state, by simulating the impact model (8) and the smooth model (9), and by
  shooting on (9). Error: the largest relative error over the sigmas against a reference orbit
  found by shooting at rtol 1e-12 (4 arcs) from a simulation that has settled on it (see
  :func:`settle_and_shoot`), checked stable, and
  whose own error is estimated by repeating it at rtol 1e-10.
* **The integration question** (:func:`integration_bench`): the state of (9) after one forcing
  period at n = 50 (Fig. 10 set) and n = 6 (Fig. 12 set), by every integrator the package offers
  (the compiled DOP853 and its scipy fallback) and scipy's ``solve_ivp`` methods on the Python
  right-hand side (the baseline a user would otherwise pick), against a compiled DOP853 run at
  rtol 1e-13; time and right-hand-side evaluations.
* **The cost of growth** (:func:`growth_bench`): time to trace a branch and to simulate a fixed
  interval as the wall exponent n grows, simulation time against interval length, and regime-map
  time against grid size and number of worker processes.
* **Speed** (:func:`~slosh_bif.studies.speed.speed_bench`): the shooting command as a whole process
  against 1,000 scipy periods, start-up, the shooting start (the targets of the speed issue).

:func:`run` writes each question's CSV and chart (:mod:`slosh_bif.studies.bench_output`); the CLI is
``slosh-bif bench --out DIR``.
"""

from __future__ import annotations

import dataclasses
import statistics
import time
import warnings

import numpy as np
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline

from slosh_bif.continuation import ContinuationOptions, continuation
from slosh_bif.flows import integrator
from slosh_bif.model.equations import SmoothModel
from slosh_bif.model.presets import get_preset
from slosh_bif.orbits.families import SHOOTING_OPTIONS
from slosh_bif.orbits.shooting import ShootingProblem
from slosh_bif.orbits.starts import settle_and_shoot
from slosh_bif.simulation.direct import SimulationSettings, simulate
from slosh_bif.simulation.regimes import regime_map
from slosh_bif.simulation.settings import Workers
from slosh_bif.slowflow.critical import critical_forcing
from slosh_bif.slowflow.flow import AsymptoticsWarning, SlowFlow
from slosh_bif.slowflow.steady_states import frequency_response
from slosh_bif.studies import bench_output
from slosh_bif.studies.chart import critical_forcing_full
from slosh_bif.studies.speed import speed_bench

__all__ = [
    "FR_SIGMAS",
    "timed",
    "first_harmonic",
    "reference_orbits",
    "frequency_response_bench",
    "integration_bench",
    "growth_bench",
    "run",
]

# Detunings of the frequency-response question: where (9) has a stable 2pi-orbit that a
# simulation from the preset's initial state settles on (checked on every run).
FR_SIGMAS = {"fig10": (-6.0, -1.2, 0.7, 4.0, 6.0), "fig13": (-3.0, -2.0, 0.5, 1.0)}
QUICK_FR_SIGMAS = {"fig10": (-6.0, 0.7), "fig13": (-2.0, 1.0)}

REFERENCE_SEGMENTS = 4  # arcs of multiple shooting, as in `slosh-bif shoot`
PERIOD = 2 * np.pi


def timed(fn, repeats: int = 3, min_seconds: float = 0.02, budget: float = 20.0):
    """(median seconds per call, last result, rounds run) over up to ``repeats`` rounds.

    A round repeats a fast call until it has run ``min_seconds`` (sub-millisecond calls are not
    timer noise then); rounds stop early once ``budget`` seconds are spent (slow methods get fewer).
    """
    times, result, spent = [], None, 0.0
    for _ in range(max(1, repeats)):
        calls, start = 0, time.perf_counter()
        while True:
            result = fn()
            calls += 1
            elapsed = time.perf_counter() - start
            if elapsed >= min_seconds:
                break
        times.append(elapsed / calls)
        spent += elapsed
        if spent >= budget:
            break
    return statistics.median(times), result, len(times)


def first_harmonic(t, X, periods: int = 20) -> float:
    """Amplitude of the e^{i tau} component of X over the last ``periods`` forcing periods."""
    t, X = np.asarray(t, dtype=float), np.asarray(X, dtype=float)
    if t[-1] - t[0] < periods * PERIOD * (1 - 1e-9):
        raise ValueError(
            f"need at least {periods} forcing periods of samples; got {(t[-1] - t[0]) / PERIOD:.3g}"
        )
    keep = t >= t[-1] - periods * PERIOD - 4 * (t[1] - t[0])
    grid = np.linspace(t[-1] - periods * PERIOD, t[-1], 256 * periods, endpoint=False)
    # A cubic spline, not linear interpolation: the latter's h^2 error is 3e-5 at the default samples.
    return float(abs(np.mean(CubicSpline(t[keep], X[keep])(grid) * np.exp(-1j * grid))) * 2)


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
    """Abar_b of (46) against Abar_c of (9) (:func:`~slosh_bif.studies.chart.critical_forcing_full`:
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


# --- the integration question --------------------------------------------------------------------

INTEGRATION_SETS = ("fig10", "fig12")  # n = 50 and n = 6
IMPLICIT_LOOSEST = 1e-9  # Radau/BDF: seconds per period below this rtol and no better than DOP853


def _integrators(params, y0, tau):
    model = SmoothModel(params)

    def compiled(backend):
        def run(rtol):
            r = integrator.integrate(params, y0, 0.0, tau, rtol=rtol, atol=rtol * 1e-2, backend=backend)
            return r.z, r.nfev

        return run

    def scipy_method(method, jac=None):
        def run(rtol):
            sol = solve_ivp(
                model.rhs,
                (0.0, tau),
                y0,
                method=method,
                rtol=rtol,
                atol=rtol * 1e-2,
                **({"jac": jac} if jac else {}),
            )
            return sol.y[:, -1], sol.nfev

        return run

    return {
        "slosh_bif DOP853 (numba, default)": compiled("numba"),
        "slosh_bif DOP853 (scipy fallback)": compiled("scipy"),
        "scipy DOP853": scipy_method("DOP853"),
        "scipy RK45": scipy_method("RK45"),
        "scipy LSODA": scipy_method("LSODA"),
        "scipy Radau (FD Jacobian)": scipy_method("Radau"),
        "scipy Radau (analytic Jacobian)": scipy_method("Radau", model.jac),
        "scipy BDF (analytic Jacobian)": scipy_method("BDF", model.jac),
    }


def integration_bench(*, quick: bool = False, repeats: int = 3, progress=None):
    """Rows ``(preset, n, method, rtol, seconds, nfev, error)``: one forcing period of (9)."""
    say = progress or (lambda message: None)
    if not integrator.HAVE_NUMBA:
        raise RuntimeError(
            "the integration benchmark compares the compiled integrator: install the 'fast' extra (numba)"
        )
    rtols = (1e-6, 1e-9) if quick else (1e-5, 1e-7, 1e-9, 1e-11)
    rows = []
    for preset in INTEGRATION_SETS:
        pre = get_preset(preset)
        params, y0 = pre.params, pre.state0
        ref = integrator.integrate(params, y0, 0.0, PERIOD, rtol=1e-13, atol=1e-15).z
        for name, run in _integrators(params, y0, PERIOD).items():
            for rtol in rtols:
                if ("Radau" in name or "BDF" in name) and rtol < IMPLICIT_LOOSEST:
                    continue
                say(f"integration, {preset} (n = {params.n}): {name}, rtol {rtol:.0e}")
                with np.errstate(
                    over="ignore", invalid="ignore"
                ):  # trial steps deep in the wall overflow; the error control rejects them
                    run(rtol)  # compile or load the kernels, warm caches: not part of the timing
                    seconds, (z, nfev), runs = timed(lambda: run(rtol), repeats=repeats)
                rows.append(
                    dict(
                        preset=preset,
                        n=params.n,
                        method=name,
                        rtol=rtol,
                        seconds=seconds,
                        runs=runs,
                        nfev=int(nfev),
                        error=float(np.max(np.abs(z - ref))),
                    )
                )
    return rows


# --- the cost of growth ----------------------------------------------------------------------------

GROWTH_N = (6, 10, 20, 50)
BRANCH_RANGE = (4.0, 10.0)  # stable symmetric orbits at sigma = 4 for every n of GROWTH_N (Abar = 3)


def _shooting_start(params, state0, sigma):
    """A ShootingProblem and a 2pi-orbit of (9) at ``sigma``, from a settled simulation."""
    start_params = params.replace(sigma=sigma)
    orbit, _ = settle_and_shoot(start_params, state0, 1e-10, segments=REFERENCE_SEGMENTS)
    if not orbit.converged:
        raise RuntimeError(f"no start orbit at sigma = {sigma}, n = {params.n}: {orbit.message}")
    problem = ShootingProblem(start_params, segments=REFERENCE_SEGMENTS)
    return problem, problem.initial_states(orbit.y0)


def growth_bench(*, quick: bool = False, repeats: int = 3, progress=None):
    """Rows ``(study, x, method, seconds, detail)`` for the growth studies."""
    say = progress or (lambda message: None)
    pre = get_preset("fig10")
    rows = []
    rep = 1 if quick else repeats
    for n in GROWTH_N[::3] if quick else GROWTH_N:
        params = pre.params.replace(n=n)
        say(f"growth: n = {n}")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AsymptoticsWarning)
            seconds, fr, _ = timed(
                lambda: frequency_response(params, sigma_min=-6.0, sigma_max=8.0),
                repeats=rep,
                min_seconds=0.0,
            )
        rows.append(
            dict(
                study="n",
                x=n,
                method="eq. 46 branch, sigma in [-6, 8]",
                seconds=seconds,
                detail=f"{sum(len(b) for b in fr.branches)} points",
            )
        )
        problem, x0 = _shooting_start(params, pre.state0, BRANCH_RANGE[0])
        options = dataclasses.replace(
            SHOOTING_OPTIONS, p_min=BRANCH_RANGE[0], p_max=BRANCH_RANGE[1], direction="forward"
        )
        seconds, branch, _ = timed(
            lambda: continuation(problem, x0, BRANCH_RANGE[0], param="sigma", options=options),
            repeats=rep,
            min_seconds=0.0,
        )
        specials = " ".join(f"{sp.kind} {sp.p:.4g}" for sp in branch.special)
        rows.append(
            dict(
                study="n",
                x=n,
                method="shooting branch (9), sigma 4 -> 10",
                seconds=seconds,
                detail=f"{len(branch)} points; {specials}",
            )
        )
        seconds, sim, _ = timed(
            lambda: simulate(params, pre.state0, 100 * PERIOD), repeats=rep, min_seconds=0.0
        )
        rows.append(
            dict(study="n", x=n, method="smooth model (9), 100 periods", seconds=seconds, detail=sim.status)
        )
    for periods in (25, 100) if quick else (25, 50, 100, 200, 400):
        say(f"growth: interval of {periods} periods")
        for model in ("smooth", "impact"):
            seconds, sim, _ = timed(
                lambda: simulate(
                    pre.params,
                    pre.state0,
                    periods * PERIOD,
                    settings=SimulationSettings(model=model, sample_step=0.05),
                ),
                repeats=rep,
                min_seconds=0.0,
            )
            rows.append(
                dict(
                    study="interval",
                    x=periods,
                    method=f"{model} model simulated",
                    seconds=seconds,
                    detail=f"{len(sim.impact_t)} impacts",
                )
            )
    sides = (2, 3) if quick else (2, 3, 4, 6)
    for workers in (1, 2):
        for side in sides:
            say(f"growth: regime map {side} x {side}, {workers} worker(s)")
            sigmas, abars = np.linspace(-2.0, 4.0, side), np.linspace(0.5, 3.0, side)
            seconds, _, _ = timed(
                lambda: regime_map(
                    pre.params,
                    pre.state0,
                    sigmas,
                    abars,
                    tmax=60 * PERIOD,
                    workers=Workers(max_workers=workers),
                ),
                repeats=1,
                min_seconds=0.0,
            )
            rows.append(
                dict(
                    study="regime map",
                    x=side * side,
                    method=f"{workers} worker{'s' if workers > 1 else ''}",
                    seconds=seconds,
                    detail="60 periods per point",
                )
            )
    return rows


# --- all of it ---------------------------------------------------------------------------------------

QUESTIONS = ("frequency-response", "integration", "growth", "speed")


def run(out, *, only=None, quick: bool = False, repeats: int = 3, progress=None) -> list:
    """Run the chosen questions (all by default) and write their CSVs and charts to ``out``."""
    only = list(only or QUESTIONS)
    unknown = [q for q in only if q not in QUESTIONS]
    if unknown:
        raise ValueError(f"unknown benchmark {unknown[0]!r}; choose from {', '.join(QUESTIONS)}")
    if not (isinstance(repeats, int) and repeats >= 1):
        raise ValueError(f"repeats must be an integer >= 1; got {repeats!r}")
    written = []
    if "integration" in only:
        written += bench_output.write_integration(
            integration_bench(quick=quick, repeats=repeats, progress=progress), out
        )
    if "frequency-response" in only:
        written += bench_output.write_frequency_response(
            *frequency_response_bench(quick=quick, repeats=repeats, progress=progress), out
        )
    if "growth" in only:
        written += bench_output.write_growth(
            growth_bench(quick=quick, repeats=repeats, progress=progress), out
        )
    if "speed" in only:
        written += bench_output.write_speed(speed_bench(quick=quick, progress=progress), out)
    return written
