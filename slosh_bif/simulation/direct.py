"""Direct simulation of the smooth model (9) and the vibro-impact model (8), with the noise of (47).

:func:`simulate` is the entry point: (9) through the compiled DOP853 of
:mod:`slosh_bif.flows.smooth.integrator` (optionally with the band-limited noise of
:mod:`slosh_bif.flows.noise`), or (8) through the exact event-driven flow of
:mod:`slosh_bif.simulation.vibro_impact`; both return a :class:`Simulation` with the impacts.
:func:`integrate_smooth` keeps scipy's ``solve_ivp`` with the generated analytic Jacobian for the
implicit methods (Radau, BDF, LSODA), which the integrator chart compares: the wall term
``chi w**(2n+1)`` makes (9) stiff during impacts at large n.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from slosh_bif.flows.noise import MAX_NOISE_STD, band_limited_noise
from slosh_bif.flows.smooth import integrator
from slosh_bif.model.equations import SmoothModel
from slosh_bif.model.params import Params
from slosh_bif.simulation.settings import SIMULATION, Noise, SimulationSettings

__all__ = [
    "MODELS",
    "MAX_SAMPLES",
    "Noise",
    "Simulation",
    "SimulationSettings",
    "Trajectory",
    "integrate_smooth",
    "simulate",
    "wall_contacts",
    "wall_passages",
]

_METHODS = ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")
_IMPLICIT = ("Radau", "BDF", "LSODA")


@dataclasses.dataclass(frozen=True)
class Trajectory:
    """A solution of the smooth model: times ``t`` (N,), states ``y`` (4, N), and how it ended."""

    t: np.ndarray
    y: np.ndarray
    success: bool
    message: str
    nfev: int


def integrate_smooth(
    params: Params,
    state0,
    t_span,
    *,
    method: str = "DOP853",
    rtol: float = 1e-9,
    atol: float = 1e-11,
    t_eval=None,
    max_step: float = np.inf,
) -> Trajectory:
    """Integrate model (9) from ``state0 = [X, X', w, w']`` over ``t_span``.

    Returns a :class:`Trajectory`; ``success`` is False (with scipy's message) when the
    integrator gave up.
    """
    if method not in _METHODS:
        raise ValueError(f"method must be one of {', '.join(_METHODS)}; got {method!r}")
    for name, value in (("rtol", rtol), ("atol", atol)):
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be positive and finite; got {value!r}")
    y0 = np.asarray(state0, dtype=float)
    if y0.shape != (4,) or not np.all(np.isfinite(y0)):
        raise ValueError(f"state0 must be 4 finite numbers [X, X', w, w']; got {state0!r}")
    model = SmoothModel(params)
    extra = {"jac": model.jac} if method in _IMPLICIT else {}
    from scipy.integrate import solve_ivp  # here: the compiled path needs none of scipy.integrate

    with np.errstate(over="ignore", invalid="ignore"):  # trial steps far inside the wall may overflow
        sol = solve_ivp(
            model.rhs,
            t_span,
            y0,
            method=method,
            rtol=rtol,
            atol=atol,
            t_eval=t_eval,
            max_step=max_step,
            **extra,
        )
    return Trajectory(t=sol.t, y=sol.y, success=bool(sol.success), message=sol.message, nfev=int(sol.nfev))


# --- direct simulation of either model, with the noise of (47) ------------------------------------

MODELS = ("smooth", "impact", "impact-corrected")
_VARIANTS = {"impact": "paper", "impact-corrected": "corrected"}  # ImpactFlow's variant of each model
# Samples a simulation keeps in memory at most (t and four states each: 2e7 is 0.8 GB); the default
# sampling reaches it at tau = 4e5.
MAX_SAMPLES = 20_000_000


@dataclasses.dataclass(frozen=True)
class Simulation:
    """A simulated response of model (9) (``"smooth"``) or (8) (``"impact"``).

    t : (N,) sample times; y : (4, N) states ``[X, X', w, w']``; impact_t, impact_side,
    impact_v_minus, impact_v_plus : (K,) the impacts (exact for the impact model; for the smooth
    model the passages of |w| through 1 into the wall, located on the samples by linear
    interpolation, with w' at entry and exit); status, message : how the run ended
    (``"finished"`` or why it stopped); noise : the realised :class:`~slosh_bif.flows.noise.BandLimitedNoise`
    or None; seconds : wall-clock time of the integration.
    """

    model: str
    params: Params
    t: np.ndarray
    y: np.ndarray
    impact_t: np.ndarray
    impact_side: np.ndarray
    impact_v_minus: np.ndarray
    impact_v_plus: np.ndarray
    status: str
    message: str
    noise: object = None
    seconds: float = 0.0

    @property
    def success(self) -> bool:
        return self.status == "finished"


def wall_passages(t, y):
    """Impacts of a sampled smooth trajectory: entries of |w| into the wall (|w| > 1).

    Returns (times, side, w' at entry, w' at exit), each (K,); a contact still open at the end
    has exit velocity NaN. Linear interpolation on the samples: a contact shorter than the sample
    step can be missed, so sample finer than the contact time (about 0.1 at n = 50, speed 2).
    """
    w, wd = y[2], y[3]
    inside = np.abs(w) > 1.0
    enter = np.flatnonzero(~inside[:-1] & inside[1:]) + 1
    leave = np.flatnonzero(inside[:-1] & ~inside[1:]) + 1

    def crossing(i):  # between samples i-1 and i
        a, b = np.abs(w[i - 1]) - 1.0, np.abs(w[i]) - 1.0
        s = a / (a - b)
        return t[i - 1] + s * (t[i] - t[i - 1]), wd[i - 1] + s * (wd[i] - wd[i - 1])

    times, vin = crossing(enter) if enter.size else (np.empty(0), np.empty(0))
    vout = np.full(enter.size, np.nan)
    for k, i in enumerate(enter):
        later = leave[leave > i]
        if later.size:
            vout[k] = crossing(later[:1])[1][0]
    return times, np.sign(w[enter]).astype(int), vin, vout


_MAX_REFINED = 20_000  # samples per refined interval: n = 10^5 at impact speed 2 and step 0.02 stays resolved


def wall_contacts(params: Params, t, y, *, rtol=1e-9, atol=1e-11, backend="auto", noise=None):
    """Impacts of a smooth trajectory, found from the state rather than from the samples alone.

    At large n the wall of (9) is stiff: a contact lasts about (log n)/(n |w'|), far less than a
    sample step at n >= 1000, so the particle can touch the wall and come back between two samples
    with no sample in |w| > 1. Such an interval shows in the state: w' turns from towards the wall
    to away from it, and the particle was near enough to reach |w| = 1 at the sampled speed. Each
    such interval, and every interval where the samples cross |w| = 1 (whose linear interpolation
    misjudges the entry speed when the contact is short), is integrated again on a grid finer than
    the contact (4 n |w'| samples per unit time); :func:`wall_passages` then reads every entry into
    |w| > 1 from the joined samples.
    Returns what :func:`wall_passages` returns.
    """
    w, wd = y[2], y[3]
    dt = np.diff(t)
    reach = np.maximum(np.abs(w[:-1]), np.abs(w[1:])) + 2.0 * np.maximum(np.abs(wd[:-1]), np.abs(wd[1:])) * dt
    turned = (w[:-1] * wd[:-1] > 0) & (w[1:] * wd[1:] < 0) & (w[:-1] * w[1:] > 0)
    crossed = (np.abs(w[:-1]) > 1.0) != (
        np.abs(w[1:]) > 1.0
    )  # seen: refined for the crossing's time and speed
    times, states = [t], [y]
    for i in np.flatnonzero(crossed | (turned & (reach > 1.0))):
        speed = max(abs(wd[i]), abs(wd[i + 1]), 1e-3)
        count = int(min(_MAX_REFINED, max(32, np.ceil(4.0 * params.n * speed * dt[i]))))
        grid = np.linspace(t[i], t[i + 1], count + 1)
        fine = integrator.integrate_grid(
            params, y[:, i], grid, rtol=rtol, atol=atol, backend=backend, noise=noise
        )
        if np.abs(fine[:, 2]).max() > 1.0:
            times.append(grid[1:-1])
            states.append(fine[1:-1].T)
    if len(times) == 1:
        return wall_passages(t, y)
    order = np.argsort(np.concatenate(times), kind="stable")
    return wall_passages(np.concatenate(times)[order], np.concatenate(states, axis=1)[:, order])


def _simulate_impact_in_chunks(
    params, y0, t0, tmax, sample_step, progress, start, backend, variant, continued
):
    """(8) over [t0, tmax] in up to 20 pieces of at least 200 time units, so that progress can be
    reported; each piece starts from the previous one's end state (the flow is exact, so the pieces
    join seamlessly)."""
    from slosh_bif.simulation.vibro_impact import simulate_impact  # numba's (8): not loaded for (9)

    edges = np.linspace(t0, tmax, max(2, min(21, int((tmax - t0) / 200) + 1)))
    parts = []
    y = y0
    for k, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
        run = simulate_impact(
            params,
            y,
            (a, b),
            sample_step=sample_step,
            backend=backend,
            variant=variant,
            continued=continued or k > 0,
        )
        parts.append(run)
        if progress is not None:
            progress((k + 1) / (len(edges) - 1))
        if not run.success:
            break
        y = run.y[:, -1]
    last = parts[-1]

    def joined(field):
        return np.concatenate([getattr(run, field) for run in parts])

    t = np.concatenate([parts[0].t] + [run.t[1:] for run in parts[1:]])
    states = np.concatenate([parts[0].y] + [run.y[:, 1:] for run in parts[1:]], axis=1)
    message = last.message if not last.success else f"reached tau = {tmax:g}"
    return Simulation(
        "impact",
        params,
        t,
        states,
        joined("impact_t"),
        joined("impact_side"),
        joined("impact_v_minus"),
        joined("impact_v_plus"),
        last.status,
        message,
        None,
        time.perf_counter() - start,
    )


def diverged_beyond(params: Params) -> float:
    """|X| or |X'| past which a run counts as diverged: no bounded response of (8) or (9) comes near
    it (the linear resonance alone gives |X| ~ Abar / gamma, and the wall caps the particle)."""
    return 1e4 * (1.0 + params.Abar) * (1.0 + 1.0 / max(params.gamma, 1e-3))


def simulate(
    params: Params,
    state0,
    tmax: float,
    *,
    t0: float = 0.0,
    settings: SimulationSettings = SIMULATION,
    noise: Noise | None = None,
    progress=None,
    continued: bool = False,
) -> Simulation:
    """Simulate from ``state0`` at ``t0`` to ``tmax`` and sample every ``sample_step``.

    ``settings.model="smooth"`` integrates (9) with the compiled DOP853 of
    :mod:`slosh_bif.flows.smooth.integrator` (scipy's when numba is missing); ``"impact"`` runs the exact
    flow of (8) (:func:`slosh_bif.simulation.vibro_impact.simulate_impact`: compiled, or the expm
    event loop with ``backend="scipy"``). ``noise`` with ``std > 0`` adds the band-limited noise of
    (47) (smooth model only, see :mod:`slosh_bif.flows.noise`) and then needs a seed.
    ``progress(fraction)`` is called as the run advances. Integration failure is not raised: the
    result's ``status`` and ``message`` say where and why it stopped. ``continued``: ``state0`` is
    where a run of the same model ended (the corrected impact model's start is then not checked
    against its wall: it may lie in the contact band).
    """
    if not isinstance(settings, SimulationSettings):
        raise TypeError(f"settings must be a SimulationSettings; got {type(settings).__name__}")
    model, sample_step, rtol, atol, backend = (
        settings.model,
        settings.sample_step,
        settings.rtol,
        settings.atol,
        settings.backend,
    )
    noise_std, seed, noise_cutoff = (
        (0.0, None, 10.0) if noise is None else (noise.std, noise.seed, noise.cutoff)
    )
    if model not in MODELS:
        raise ValueError(f"model must be one of {', '.join(MODELS)}; got {model!r}")
    if not isinstance(params, Params):
        raise TypeError(f"params must be a slosh_bif.Params; got {type(params).__name__}")
    params.require_positive_stiffness()
    if not (np.isfinite(t0) and np.isfinite(tmax) and tmax > t0):
        raise ValueError(f"tmax must be finite and greater than t0 = {t0}; got {tmax!r}")
    if not (np.isfinite(sample_step) and 0 < sample_step <= 0.5):
        raise ValueError(f"sample_step must be in (0, 0.5]; got {sample_step!r}")
    if not (np.isfinite(noise_std) and 0 <= noise_std <= MAX_NOISE_STD):
        raise ValueError(
            f"noise std (sigma_bar of eq. 47) must be in [0, {MAX_NOISE_STD:g}]; got {noise_std!r}"
        )
    samples = (tmax - t0) / (min(sample_step, 0.05) if model in _VARIANTS else sample_step)
    if samples > MAX_SAMPLES:  # the samples are kept in memory (5 doubles each): refuse before integrating
        raise ValueError(
            f"tmax - t0 = {tmax - t0:g} at sample_step {sample_step:g} would keep {samples:.3g} "
            f"samples ({40 * samples / 1e9:.3g} GB), more than "
            f"the {MAX_SAMPLES:.0e} allowed: shorten the run (tau up to t0 + "
            f"{MAX_SAMPLES * sample_step:g}) or sample more sparsely"
        )
    y0 = np.asarray(state0, dtype=float)
    if y0.shape != (4,) or not np.all(np.isfinite(y0)):
        raise ValueError(f"state0 must be 4 finite numbers [X, X', w, w']; got {state0!r}")
    forcing = None
    if noise_std > 0:
        if model != "smooth":
            raise ValueError("noise (eq. 47) is supported for the smooth model only; use model='smooth'")
        if seed is None:
            raise ValueError("noise needs a seed (any non-negative integer) so that the run is reproducible")
        forcing = band_limited_noise(noise_std, seed=seed, duration=tmax - t0, t0=t0, cutoff=noise_cutoff)

    start = time.perf_counter()
    if model in _VARIANTS:
        return _simulate_impact_in_chunks(
            params,
            y0,
            t0,
            tmax,
            min(sample_step, 0.05),
            progress,
            start,
            backend,
            _VARIANTS[model],
            continued,
        )

    count = int(np.ceil((tmax - t0) / sample_step))
    taus = np.linspace(t0, tmax, count + 1)
    chunks = np.array_split(np.arange(count + 1), max(1, min(50, count // 500)))
    states = [y0[None, :]]
    status, message = "finished", f"reached tau = {tmax:g}"
    for k, chunk in enumerate(chunks):
        grid = taus[max(chunk[0] - 1, 0) : chunk[-1] + 1]
        if grid.size < 2:
            continue
        try:
            part = integrator.integrate_grid(
                params, states[-1][-1], grid, rtol=rtol, atol=atol, backend=backend, noise=forcing
            )
        except RuntimeError as err:
            status, message = "failed", str(err)
            break
        states.append(part[1:])
        if progress is not None:
            progress((k + 1) / len(chunks))
        if np.max(np.abs(part[:, :2])) > diverged_beyond(params):
            status, message = (
                "diverged",
                f"|X| or |X'| passed {diverged_beyond(params):g} by tau = {grid[-1]:.6g}",
            )
            break
    y = np.concatenate(states).T
    t = taus[: y.shape[1]]
    hit_t, side, v_in, v_out = wall_contacts(
        params, t, y, rtol=rtol, atol=atol, backend=backend, noise=forcing
    )
    return Simulation(
        "smooth",
        params,
        t,
        y,
        hit_t,
        side,
        v_in,
        v_out,
        status,
        message,
        forcing,
        time.perf_counter() - start,
    )
