"""Event-driven simulation of the vibro-impact model (8) with the restitution law (2), (21).

:func:`simulate_impact` runs the compiled exact flow of :mod:`slosh_bif.flows.impact.flow` (impacts
found with a certificate) by default, and with ``backend="scipy"`` the event loop below, its
independent reference:

Between impacts (8) is linear, ``y' = M y + F cos(tau)``. Appending ``(cos tau, sin tau)`` to the
state makes it autonomous and linear, ``z' = K z``, so the flow over any interval ``s`` is the
matrix exponential ``expm(K s)``: exact, with no integration error and no special case at
resonance. The trajectory is stepped on a fixed grid of ``sample_step``; in each step an impact
is found either as a sign change of ``|w| - 1`` or, for a grazing passage, as an interior extremum
of w beyond the wall (located where ``w' = 0``). The impact instant is then refined by Brent's
method on the exact flow, and the restitution law is applied there.

A step shorter than half the shortest natural period cannot hide two extrema of w, so no impact
is missed; the default 0.05 is far below that for the paper's parameters.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

from slosh_bif.flows.impact.band import inside_measured_wall
from slosh_bif.flows.impact.crossings import STICK_RISE
from slosh_bif.flows.impact.flow import IMPACT_VARIANTS, ImpactFlow
from slosh_bif.flows.smooth.integrator import resolve_backend
from slosh_bif.model.equations import ImpactModel
from slosh_bif.model.params import Params

__all__ = ["ImpactTrajectory", "simulate_impact"]

# Statuses of a finished run.
FINISHED = "finished"
STICKING = "sticking"  # post-impact speed too small to leave the wall: the impact model has a Zeno point
KAPPA_NOT_REAL = "kappa-not-real"  # eq. (21) gives no real kappa at this impact speed
MAX_IMPACTS = "max-impacts"
BEYOND_LAW = "beyond-measured-speeds"  # an impact faster than the measured wall law's range


@dataclasses.dataclass(frozen=True)
class ImpactTrajectory:
    """Result of :func:`simulate_impact`.

    Attributes
    ----------
    t : (N,) sample times; y : (4, N) states ``[X, X', w, w']`` at them (post-impact at an
    impact instant); impact_t : (K,) impact times; impact_side : (K,) +1 or -1 (the wall hit);
    impact_v_minus, impact_v_plus : (K,) w' just before and after; status, message : how the
    run ended (``"finished"`` or the reason it stopped early).
    """

    t: np.ndarray
    y: np.ndarray
    impact_t: np.ndarray
    impact_side: np.ndarray
    impact_v_minus: np.ndarray
    impact_v_plus: np.ndarray
    status: str
    message: str

    @property
    def success(self) -> bool:
        return self.status == FINISHED


class _ExactFlow:
    """Exact flow of (8) between impacts on the augmented state ``z = [y, cos tau, sin tau]``."""

    def __init__(self, model: ImpactModel):
        from scipy import linalg  # the reference path only (the compiled flow needs no scipy)

        self.K = model.augmented()
        self._expm = linalg.expm

    def propagator(self, s):
        return self._expm(self.K * s)

    def component(self, z, s, index):
        return (self.propagator(s) @ z)[index]


def _augment(tau, y):
    return np.concatenate([y, [np.cos(tau), np.sin(tau)]])


def _find_impact(flow, z, h, side):
    """Earliest s in [0, h] where w reaches the wall ``side`` (+1/-1), or None; 0 only for a start
    on the wall moving into it, or at rest there and pushed into it."""
    from scipy import optimize

    def beyond(s):
        return side * flow.component(z, s, 2) - 1.0

    def speed(s):
        return flow.component(z, s, 3)

    on_wall = beyond(0.0) >= 0.0
    if on_wall and (side * z[3] > 0.0 or (z[3] == 0.0 and side * float(flow.K[3] @ z) > 0.0)):
        return 0.0
    if beyond(h) >= 0.0:
        start = 0.0
        if on_wall:
            # Left this wall (a rebound, or at rest and pulled off it) and back on it within the
            # step: the particle turned around in between, and the new impact lies after the turn.
            leaving = 0.0 if z[3] != 0.0 else 1e-9 * h
            if speed(leaving) * speed(h) >= 0.0:
                return None
            start = optimize.brentq(speed, leaving, h, xtol=1e-15, rtol=1e-15)
        return optimize.brentq(beyond, start, h, xtol=1e-15, rtol=1e-15)
    # Grazing: w may exceed the wall inside the step and come back; look at the extremum of w.
    if side * z[3] > 0 > side * speed(h):
        s_peak = optimize.brentq(speed, 0.0, h, xtol=1e-15, rtol=1e-15)
        if beyond(s_peak) >= 0.0:
            return optimize.brentq(beyond, 0.0, s_peak, xtol=1e-15, rtol=1e-15)
    return None


def simulate_impact(
    params: Params,
    state0,
    t_span,
    *,
    sample_step: float = 0.05,
    max_impacts: int = 1_000_000,
    stick_speed: float = 1e-9,
    backend: str = "auto",
    variant: str = "paper",
    continued: bool = False,
) -> ImpactTrajectory:
    """Simulate the vibro-impact model (8) from ``state0`` over ``t_span = (t0, t1)``.

    Parameters
    ----------
    params : Params
    state0 : (4,) array
        ``[X, X', w, w']`` with ``|w| <= 1``.
    t_span : (t0, t1)
    sample_step : float
        Output grid and event-search step, in (0, 0.5].
    max_impacts : int
        Stop (status ``"max-impacts"``) after this many impacts.
    stick_speed : float
        A post-impact speed below this ends the run (status ``"sticking"``), as does a flight
        pushed back onto the wall within a rise below
        :data:`~slosh_bif.flows.impact.crossings.STICK_RISE` (too small for w's rounding): impacts
        would accumulate at a point in time (a Zeno point), beyond which (8) is not defined.
    backend : ``"auto"``/``"numba"`` the compiled flow, ``"scipy"`` the expm event loop.
    variant : ``"paper"``, (8) as the paper states it, or ``"corrected"``: (9) with its wall replaced
        by the wall's own restitution at its clearance |w| = D(v) (compiled flow only).
    continued : bool
        ``state0`` is where an earlier run of the same flow ended (a longer run in pieces): it may
        lie in the corrected model's contact band, beyond D(v) at its present speed, and is not
        checked against the wall.
    """
    model = ImpactModel(params)
    y0 = np.asarray(state0, dtype=float)
    if y0.shape != (4,) or not np.all(np.isfinite(y0)):
        raise ValueError(f"state0 must be 4 finite numbers [X, X', w, w']; got {state0!r}")
    if variant not in IMPACT_VARIANTS:
        raise ValueError(f"variant must be one of {', '.join(IMPACT_VARIANTS)}; got {variant!r}")
    if variant == "paper" and abs(y0[2]) > 1.0 and not continued:
        raise ValueError(f"state0 must start between the walls, |w| <= 1; got w = {float(y0[2])!r}")
    t0, t1 = (float(t) for t in t_span)
    if not (np.isfinite(t0) and np.isfinite(t1) and t1 > t0):
        raise ValueError(f"t_span must be finite with t1 > t0; got {t_span!r}")
    if not (0 < sample_step <= 0.5):
        raise ValueError(f"sample_step must be in (0, 0.5]; got {sample_step!r}")

    if not (isinstance(max_impacts, (int, np.integer)) and max_impacts >= 1):
        raise ValueError(f"max_impacts must be a positive integer; got {max_impacts!r}")
    if variant == "corrected":
        if resolve_backend(backend) != "numba":
            raise ValueError("the corrected impact model runs on the compiled flow only (backend 'numba')")
        flow = _compiled_flow(params, float(sample_step), variant)
        inside = inside_measured_wall(flow.wall, y0)
        if inside < 0 and not continued:
            raise ValueError(
                f"state0 must start inside the measured wall, |w| < D(v) = {abs(y0[2]) + inside:.6g}; "
                f"got w = {float(y0[2])!r}"
            )
    if resolve_backend(backend) == "numba":
        t, y, hits, code = _compiled_flow(params, float(sample_step), variant).run(
            y0, t0, t1, stick_speed=stick_speed, max_impacts=int(max_impacts)
        )
        return _trajectory(t, y, hits, code, t1, max_impacts)

    flow = _ExactFlow(model)
    step_propagator = flow.propagator(sample_step)
    times, states = [t0], [y0.copy()]
    impacts = []  # (t, side, v_minus, v_plus)
    status, message = FINISHED, f"reached tau = {t1}"
    tau, y = t0, y0.copy()
    while tau < t1:
        h = min(sample_step, t1 - tau)
        z = _augment(tau, y)
        hits = [(s, side) for side in (1, -1) if (s := _find_impact(flow, z, h, side)) is not None]
        if not hits:
            z_next = (step_propagator if h == sample_step else flow.propagator(h)) @ z
            tau, y = tau + h, z_next[:4]
            times.append(tau)
            states.append(y.copy())
            continue
        s, side = min(hits)
        y = (flow.propagator(s) @ z)[:4]
        y[2] = float(side)  # exactly on the wall, so the next step starts inside
        v_minus = y[3]
        try:
            y = model.impact(y) if v_minus != 0.0 else y  # at rest on the wall, pressed into it: sticks
        except ValueError as err:
            status, message = KAPPA_NOT_REAL, f"at tau = {tau + s:.10g}: {err}"
            break
        tau += s
        impacts.append((tau, side, v_minus, y[3]))
        times.append(tau)
        states.append(y.copy())
        push = side * float(flow.K[3] @ _augment(tau, y))  # w'' towards the wall just left
        if abs(y[3]) < stick_speed or (push > 0.0 and y[3] ** 2 < 2.0 * push * STICK_RISE):
            status, message = STICKING, _sticking(y[3], tau)
            break
        if len(impacts) >= max_impacts:
            status, message = (
                MAX_IMPACTS,
                f"stopped after max_impacts = {max_impacts} impacts at tau = {tau:.10g}",
            )
            break
    arr = np.array(impacts, dtype=float).reshape(-1, 4)
    return ImpactTrajectory(
        t=np.array(times),
        y=np.array(states).T,
        impact_t=arr[:, 0],
        impact_side=arr[:, 1].astype(int),
        impact_v_minus=arr[:, 2],
        impact_v_plus=arr[:, 3],
        status=status,
        message=message,
    )


@functools.lru_cache(maxsize=8)
def _compiled_flow(params: Params, step: float, variant: str = "paper") -> ImpactFlow:
    """The propagator table of a parameter set, kept for the pieces of one long run."""
    return ImpactFlow(params, step, variant=variant)


def _sticking(speed, tau) -> str:
    return (
        f"post-impact speed {abs(speed):.3g} at tau = {tau:.10g}: the particle sticks to the wall "
        f"(below stick_speed, or pushed back onto it within a rise below {STICK_RISE:g})"
    )


def _trajectory(t, y, hits, code, t1, max_impacts) -> ImpactTrajectory:
    """The compiled run's arrays and end code as an :class:`ImpactTrajectory`."""
    if code == 0:
        status, message = FINISHED, f"reached tau = {t1}"
    elif code == 1:
        status, message = STICKING, _sticking(y[3, -1], t[-1])
    elif code == 2:
        status = KAPPA_NOT_REAL
        message = (
            f"at tau = {hits[-1, 0]:.10g}: kappa (eq. 21) is not real at impact speed {abs(hits[-1, 2]):.6g}"
        )
        hits = hits[:-1]
    elif code == 5:
        status, message = (
            BEYOND_LAW,
            f"an impact after tau = {t[-1]:.10g} is faster than the measured law's speeds",
        )
    else:
        status, message = (
            MAX_IMPACTS,
            f"stopped after max_impacts = {max_impacts} impacts at tau = {t[-1]:.10g}",
        )
    return ImpactTrajectory(
        t=t,
        y=y,
        impact_t=hits[:, 0],
        impact_side=hits[:, 1].astype(int),
        impact_v_minus=hits[:, 2],
        impact_v_plus=hits[:, 3],
        status=status,
        message=message,
    )
