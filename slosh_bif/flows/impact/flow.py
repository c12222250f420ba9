"""The exact flow of the vibro-impact model (8), compiled: flights in closed form, every impact found
with a certificate, and the restitution law (2), (21) applied at each.

Flights. Between impacts (8) is linear with constant coefficients; on ``z = [X, X', w, w', cos tau,
sin tau]`` it is ``z' = K z`` (:func:`~slosh_bif.model.equations.impact_augmented`), whose flow
over s is ``expm(K s)``. The propagators ``P_k = expm(K h 2**-k)``, k = 0..LEVELS, are made once per
parameter set and sample step h; products of them give the state at any dyadic point of a step
exactly up to rounding. There is no integration error, no expm in the loop, and no special case at
resonance or for the Jordan block that (8) has at beta = 0 (where a modal solution breaks down).

Impacts with a certificate. On an interval of length L where ``f = +-w`` has the values f0, f1 and
slopes d0, d1 at its ends and ``|f''| <= B`` (``w'' = K[3] . z`` and ``|z(s)| <= exp(|K| s) |z(0)|``
in the max-norm), f lies below both parabolas ``f0 + d0 s + B s**2/2`` and ``f1 - d1 (L - s) +
B (L - s)**2/2``. Their lower envelope is convex on each side of the single point where they meet,
so if it is below the wall there and at s = L, f cannot reach the wall inside: the interval is free.
An interval that is not free is halved, the left half first, so the first impact is found however
fast or however grazing the approach. Once an interval ends beyond one wall only and f's slope is
certified positive over it (``f'(0) - B L > 0``), it holds exactly one crossing, which Newton on the
flow's Taylor series from the interval's start finds to rounding (the map's Jacobian is carried
there by the Taylor series of the flight's variational system). At the finest level (L = h
2**-LEVELS, 1e-16 of tau at the default step) an interval whose end lies at or beyond the wall,
moving into it, holds the impact; one whose end does not is a tangency within rounding, and one
whose end is on the wall but moving off it (a start at rest on the wall, pulled away) is not an
impact either.

Impacts. ``w'+ = -kappa(|w'-|) w'-`` with kappa of (21), ``sqrt(1 - c v**q)``. A run stops with a
status rather than going on without a model: ``"kappa-not-real"`` where (21) gives no real kappa,
``"sticking"`` where the post-impact speed falls below ``stick_speed`` or the flight is pushed back
onto the wall within a rise too small for w's rounding (impacts then accumulate at a point in
time, beyond which (8) without a sticking phase is not defined), ``"max-impacts"``. The
corrected impact model (``variant="corrected"``) puts the smooth wall's kappa_wall(v) at a wall that
stands at |w| = D(v) (:mod:`slosh_bif.flows.impact.band`).

:func:`slosh_bif.simulation.vibro_impact.simulate_impact` is the entry point; its event loop on
``scipy.linalg.expm`` is the reference this flow is tested against.
"""

from __future__ import annotations

import functools
import math
import sys

import numpy as np

from slosh_bif.flows.compiled import HAVE_NUMBA, forget_stale_compilations, jit
from slosh_bif.flows.impact import band as _band_module
from slosh_bif.flows.impact import crossings as _crossings_module
from slosh_bif.flows.impact.band import LEFT, REACHED, TOO_FAST, band, law, law_arrays
from slosh_bif.flows.impact.crossings import (
    LEVELS,
    apply,
    carry,
    max_abs,
    may_reach,
    piece,
    saltation,
    sticks,
)
from slosh_bif.flows.impact.propagators import (
    LINEAR_PARAMETERS,
    WALL_PARAMETERS,
    derivative_of_K,
    propagators,
)
from slosh_bif.model._generated import impact_kernels as _impact_kernels
from slosh_bif.model._generated.impact_kernels import impact_measured_kernel, impact_saltation_kernel
from slosh_bif.model.equations import impact_augmented
from slosh_bif.model.params import Params
from slosh_bif.model.restitution import dissipation_at_unit_speed
from slosh_bif.model.restitution.corrected import measured_wall

__all__ = ["END_REASONS", "IMPACT_VARIANTS", "LEVELS", "LINEAR_PARAMETERS", "WALL_PARAMETERS", "ImpactFlow"]

IMPACT_VARIANTS = ("paper", "corrected")

# Codes of the compiled run, and what a run that ended early met.
_FINISHED, _STICKING, _KAPPA_NOT_REAL, _MAX_IMPACTS, _FULL, _TOO_FAST = 0, 1, 2, 3, 4, 5
END_REASONS = {
    _STICKING: "the particle sticks to the wall (impacts accumulate)",
    _KAPPA_NOT_REAL: "kappa (eq. 21) is not real at an impact speed reached",
    _MAX_IMPACTS: "more than 10,000 impacts",
    _TOO_FAST: "an impact faster than the measured wall law's speeds",
}
_impact = jit(impact_saltation_kernel, inline=True)
_measured = jit(impact_measured_kernel, inline=True)


@jit
def _run(flights, restitution, wall, linear, span, limits, variations, record):
    """Samples every h from t0 to t1 (t1 last) with the impacts among them; see :class:`ImpactFlow`.
    Stops with code _FULL when more than ``capacity`` impacts would be stored. With ``jac``,
    ``phi`` (identity on entry) and ``dp`` (zero) end as d y(t1) / d y0 and d y(t1) / d param.
    A non-empty ``stacked`` is the measured wall's law (:mod:`slosh_bif.flows.impact.band`; its
    band's threshold ``shape[4]`` is the certified search's), else the wall is (21)'s at |w| = 1.

    The records: ``flights`` as in :func:`~slosh_bif.flows.impact.crossings.piece`;
    ``restitution = (kappa_c, kappa_q, dc)`` of (21); ``wall = (shape, stacked)``; ``linear``, the
    linear part's (eps, beta, gamma, sigma, Abar); ``span = (y0, t0, t1, h)``; ``limits =
    (stick_speed, max_impacts, capacity)``; ``variations = (jac, phi, dp)``; ``record`` (with
    ``jac``): keep phi and dp at every stored row too (the orbit's sensitivities along it)."""
    table, dtable, _, _, _, lengths, growth, row_norm = flights
    kappa_c, kappa_q, dc = restitution
    shape, stacked = wall
    y0, t0, t1, h = span
    stick_speed, max_impacts, capacity = limits
    jac, phi, dp = variations
    measured = stacked.shape[0] > 0
    c = shape[4] if measured else 1.0
    count = int(math.ceil((t1 - t0) / h - 1e-12))
    times = np.empty(count + 1 + capacity)
    states = np.empty((count + 1 + capacity, 4))
    kept = count + 1 + capacity if record else 1
    phis = np.empty((kept, 4, 4))
    dps = np.empty((kept, 4))
    impacts = np.empty((capacity, 4))  # t, side, w'-, w'+
    stack_z = np.empty((2 * LEVELS + 4, 6))
    stack_k = np.empty(2 * LEVELS + 4, dtype=np.int64)
    stack_s = np.empty(2 * LEVELS + 4)
    z = np.empty(6)
    zn = np.empty(6)
    za = np.empty(6)
    zb = np.empty(6)
    tmp = np.empty((4, 5))
    work = (stack_z, stack_k, stack_s, tmp, za, zb)
    reset = np.empty(18)  # the saltation matrix (16), w'+ and its derivative in the loss
    pars = np.empty(9)  # (21)'s kernel: eps, beta, gamma, sigma, Abar, loss, q; the measured wall's:
    pars[:5] = linear  # eps, beta, gamma, sigma, Abar, side, kappa, kappa', D'
    z[:4] = y0
    times[0] = t0
    states[0] = y0
    if record:
        phis[0] = phi
        dps[0] = dp
    rows, hits = 1, 0
    for j in range(count):
        ta = t0 + j * h
        tb = t1 if j == count - 1 else t0 + (j + 1) * h
        done = 0.0
        in_band = measured and abs(z[2]) >= c
        while True:
            tau = ta + done
            z[4] = math.cos(tau)
            z[5] = math.sin(tau)
            side = 0
            if in_band:
                code, s = band(flights, wall, z, tb - tau, work, variations)
                done += s
                in_band = False
                if code == REACHED:
                    break
                if code == LEFT:
                    continue
                if code == TOO_FAST:
                    return times, states, impacts, rows, hits, _TOO_FAST, phis, dps
                side = 1 if z[2] >= 0.0 else -1
            else:
                rest = (tb - tau) / h  # in steps; taken as its binary expansion
                if rest >= 1.0 - 1e-9:  # a whole step certified free, without the search's set-up
                    apply(table[0], z, zn)
                    B = row_norm * growth[0] * max_abs(z) / c
                    if not (
                        may_reach(z[2] / c, z[3] / c, zn[2] / c, zn[3] / c, h, B)
                        or may_reach(-z[2] / c, -z[3] / c, -zn[2] / c, -zn[3] / c, h, B)
                    ):
                        if jac:
                            carry(table[0], dtable[0], z, phi, dp, tmp)
                        z[:] = zn
                        break
                for k in range(LEVELS + 1):
                    unit = lengths[k] / h
                    if rest < unit * (1.0 - 1e-9):
                        if rest < lengths[LEVELS] / h:
                            break
                        continue
                    side, s = piece(flights, z, k, zn, work, variations, c)
                    z[:] = zn
                    if side != 0:
                        done += s
                        break
                    rest -= unit
                    done += s
                if side == 0:
                    break
                if measured:  # |w| reached the band: the wall itself is found there
                    in_band = True
                    continue
            if hits >= capacity:
                return times, states, impacts, rows, hits, _FULL, phis, dps
            v_minus = z[3]
            speed = abs(v_minus)
            impacts[hits, 0] = ta + done
            impacts[hits, 1] = side
            impacts[hits, 2] = v_minus
            if measured:
                kappa, dkappa, _, dclear = law(shape, stacked, speed)
                pars[5], pars[6], pars[7], pars[8] = side, kappa, dkappa, dclear
                _measured(ta + done, z, reset, pars)
                in_band = True  # the particle leaves the wall through the band
            else:
                if speed > 0.0:
                    loss = kappa_c * speed**kappa_q
                else:  # the limit of (21) at zero speed
                    loss = kappa_c if kappa_q == 0.0 else (0.0 if kappa_q > 0.0 else math.inf)
                if loss > 1.0:
                    impacts[hits, 3] = math.nan
                    return times, states, impacts, rows, hits + 1, _KAPPA_NOT_REAL, phis, dps
                pars[5], pars[6] = loss, kappa_q
                _impact(ta + done, z, reset, pars)
                z[2] = side  # exactly on the wall, so the next flight starts inside
            z[3] = reset[16]
            impacts[hits, 3] = z[3]
            if jac:
                saltation(reset, phi, dp)
                if dc != 0.0:  # a wall parameter moves c, and the loss c speed**q with it
                    dp[3] += reset[17] * speed**kappa_q * dc
            hits += 1
            times[rows] = ta + done
            states[rows] = z[:4]
            if record:
                phis[rows] = phi
                dps[rows] = dp
            rows += 1
            if sticks(flights[2], z, side, stick_speed):
                return times, states, impacts, rows, hits, _STICKING, phis, dps
            if hits >= max_impacts:
                return times, states, impacts, rows, hits, _MAX_IMPACTS, phis, dps
        times[rows] = tb
        states[rows] = z[:4]
        if record:
            phis[rows] = phi
            dps[rows] = dp
        rows += 1
    return times, states, impacts, rows, hits, _FINISHED, phis, dps


@functools.lru_cache(maxsize=32)
def _restitution_constants(lam, chi, n, pbar, param):
    """(c, q, dc / d param) of kappa = sqrt(1 - c v**q) (21): c is linear in lam and goes as
    chi**-a; kept across the many flows of a continuation (its wall stays)."""
    c = float(dissipation_at_unit_speed(lam, chi, n, pbar))
    exponent = pbar / (2 * (n + 1)) + 0.5
    dc = {"lam": float(dissipation_at_unit_speed(1.0, chi, n, pbar)), "chi": -exponent * c / chi}
    return c, pbar / (n + 1), dc.get(param, 0.0)


class ImpactFlow:
    """The compiled exact flow of (8) for one parameter set, sampled every ``step``.

    ``run`` samples a trajectory (the arrays of :class:`~slosh_bif.simulation.vibro_impact.ImpactTrajectory`);
    ``strobe`` maps a state over a time T with its Jacobian (the flights' propagators and the
    impacts' saltation matrices) and its derivative with respect to ``param``: one of the
    parameters in the linear part of (8) (eps, beta, gamma, sigma, Abar), through the flights'
    propagators, or of the wall's (lam, chi), through the restitution law at each impact.

    ``variant``: ``"paper"``, (8) as the paper states it (first-order coefficients, kappa of (21),
    the wall at |w| = 1), or ``"corrected"``, the corrected impact model: (9) with its wall replaced
    by the wall's own measured law (flights on (9)'s exact linear part, kappa_wall(v) at the
    clearance D(v): :mod:`slosh_bif.flows.impact.band`; no derivatives in the wall's lam, chi).
    ``exact_flights`` (for :meth:`run` only) swaps the flights: (9)'s exact linear part for
    ``"paper"``, (8)'s first-order coefficients for ``"corrected"``.
    """

    def __init__(
        self,
        params: Params,
        step: float = 0.05,
        param: str | None = None,
        variant: str = "paper",
        *,
        exact_flights: bool | None = None,
    ):
        if not (np.isfinite(step) and 0 < step <= 0.5):
            raise ValueError(f"sample_step must be in (0, 0.5]; got {step!r}")
        if variant not in IMPACT_VARIANTS:
            raise ValueError(f"variant must be one of {', '.join(IMPACT_VARIANTS)}; got {variant!r}")
        allowed = LINEAR_PARAMETERS + (WALL_PARAMETERS if variant == "paper" else ())
        if param is not None and param not in allowed:
            raise ValueError(
                f"param must be one of {', '.join(allowed)} with variant {variant!r}; got {param!r}"
            )
        if not isinstance(params, Params):
            raise TypeError(f"params must be a slosh_bif.Params; got {type(params).__name__}")
        # the flights of the other variant, to tell the two differences apart (runs only: the
        # saltation matrices are derived for each variant's own flights)
        exact = variant == "corrected" if exact_flights is None else bool(exact_flights)
        self.params, self.exact_flights = params, exact
        P = params
        K = impact_augmented(P.eps, P.beta, P.gamma, P.sigma, P.Abar, exact=exact)
        self.K = K
        self.step = float(step)
        self.lengths = self.step * 0.5 ** np.arange(LEVELS + 2)
        # with a parameter of the flights, the propagators' derivatives in it too (a wall
        # parameter, or none: the flights do not depend on it, zeros)
        Kp = derivative_of_K(params, param, exact) if param in LINEAR_PARAMETERS else None
        self.table, self.dtable = propagators(K, self.lengths, Kp)
        self.Kp = np.zeros_like(K) if Kp is None else Kp
        norm = float(np.abs(K).sum(axis=1).max())
        self.growth = np.exp(norm * self.lengths)
        self.row_norm = float(np.abs(K[3]).sum())  # |w''| <= row_norm |z|
        # terms of the Taylor series of expm(K s) z for s <= step: the rest below 1e-17 |z|
        size, term, self.taylor = norm * self.step, 1.0, 0
        while term > 1e-17 and self.taylor < 60:
            self.taylor += 1
            term *= size / self.taylor
        self.variant = variant
        if variant == "corrected":
            self.wall = measured_wall(P.lam, P.chi, P.n, P.pbar)
            self.shape, self.stacked = law_arrays(self.wall)
        else:
            self.wall, self.shape, self.stacked = None, np.zeros(5), np.zeros((0, 4))
        # where a flight grazes the wall: |w| = 1 for (8), and for the corrected impact model the
        # measured wall's clearance at its least speed (the clamp of its law: D(v_min))
        self.grazing_level = 1.0 if self.wall is None else float(self.wall.clearance(self.wall.v_min))
        self.linear = np.array([P.eps, P.beta, P.gamma, P.sigma, P.Abar])
        self.kappa_c, self.kappa_q, self.dc = _restitution_constants(P.lam, P.chi, P.n, P.pbar, param)
        # the flights' constants as one record, as the compiled kernels take them
        self.flights = (
            self.table,
            self.dtable,
            self.K,
            self.Kp,
            self.taylor,
            self.lengths,
            self.growth,
            self.row_norm,
        )

    @property
    def slowest_smooth_impact(self) -> float:
        """The least impact speed above which the map is smooth in it: 0 for (8) (its kappa is
        smooth down to grazing), the measured law's least speed for the corrected impact model
        (below it the law is clamped)."""
        return 0.0 if self.wall is None else float(self.wall.v_min)

    def _call(self, y0, t0, t1, stick_speed, max_impacts, capacity, jac, record=False):
        """The compiled run from room for ``capacity`` impacts up, rerun with four times the room
        while it fills (the same inputs give the same run); its arrays cut to what was stored
        (the last two: phi and dp at every row, with ``record``; else None)."""
        while True:
            phi, dp = np.eye(4), np.zeros(4)
            times, states, impacts, rows, hits, code, phis, dps = _run(
                self.flights,
                (self.kappa_c, self.kappa_q, self.dc),
                (self.shape, self.stacked),
                self.linear,
                (np.asarray(y0, dtype=float), float(t0), float(t1), self.step),
                (float(stick_speed), max_impacts, capacity),
                (jac, phi, dp),
                record,
            )
            if code != _FULL:
                kept = (phis[:rows], dps[:rows]) if record else (None, None)
                return times[:rows], states[:rows].T, impacts[:hits], int(code), phi, dp, *kept
            capacity = min(max_impacts, 4 * capacity)

    def run(self, y0, t0: float, t1: float, *, stick_speed: float, max_impacts: int):
        """``(t, y, impacts, code)``: sample times (with the impact instants), states ``(4, N)``
        (post-impact at an impact), impacts ``(K, 4)`` rows ``t, side, w'-, w'+`` and the end code
        (0 finished, 1 sticking, 2 kappa not real, 3 ``max_impacts`` reached, 5 an impact faster
        than the measured law's speeds)."""
        count = int(math.ceil((t1 - t0) / self.step - 1e-12))
        return self._call(y0, t0, t1, stick_speed, max_impacts, min(max_impacts, 2 * count + 64), False)[:4]

    def sensitivities(self, y0, t0: float, period: float, *, max_impacts: int = 10_000):
        """``(t, y, phis, dps, impacts, code)``: the run of :meth:`run` from y0 over ``period``
        (samples every ``step`` and at the impacts, post-impact there) with, at every sample, the
        state's derivatives with respect to y0 (``phis``, (N, 4, 4)) and to ``param`` (``dps``,
        (N, 4)): what a quantity sampled along an orbit needs for its own derivatives."""
        if self.exact_flights != (self.variant == "corrected"):
            raise ValueError("a flow with the other variant's flights runs, but has no saltation matrices")
        count = int(math.ceil(period / self.step - 1e-12))
        t, y, impacts, code, _, _, phis, dps = self._call(
            y0, t0, t0 + period, 1e-9, max_impacts, min(max_impacts, 2 * count + 64), True, record=True
        )
        return t, y, phis, dps, impacts, code

    def strobe(self, y0, t0: float, period: float, *, stick_speed: float = 1e-9, max_impacts: int = 10_000):
        """``(y, phi, dp, impacts, code)``: the state at ``t0 + period``, its derivatives with respect
        to y0 (4 x 4) and to ``param`` (zero without one), the impacts and the end code of :meth:`run`."""
        if self.exact_flights != (self.variant == "corrected"):  # the other variant's flights
            raise ValueError("a flow with the other variant's flights runs, but has no saltation matrices")
        _, states, impacts, code, phi, dp, _, _ = self._call(
            y0, t0, t0 + period, stick_speed, max_impacts, min(max_impacts, 64), True
        )
        return states[:, -1].copy(), phi, dp, impacts, code


if HAVE_NUMBA:  # the run inlines or calls the search, the band and the generated impact kernels
    forget_stale_compilations(
        _run,
        (_crossings_module, _band_module, _impact_kernels, sys.modules[__name__]),
        ("flow", "crossings", "band"),
        "impact.sources",
    )
