"""Frequency-response curves: steady states of the forced slow flow (45) on S+, eqs. (45), (46).

The unknowns are ``(A, psi)`` and the residual is the slow flow (45) itself, so the continuation
Jacobian *is* the slow-flow Jacobian and stability comes from its eigenvalues. The continued
parameter is ``sigma`` (or ``Abar``). Eq. (46) follows from (45) by eliminating psi, so every
point of a branch satisfies it; for fixed A it is quadratic in sigma,

    sigma = (1 - beta^2) + (8 alpha (1 - alpha)(1 - beta^2) -+ sqrt(pi^4 A^2 Abar^2 - E^2)) / (pi^2 A^2),
    E = gamma pi^2 A^2 + 8 rho alpha^2 (1 - beta^2),

which gives start points (and an independent check of every point). A component of the curve
exists over each interval of A where ``pi^2 A Abar > E``: a closed curve when the interval lies
inside (A_min, inf), an arc ending twice at the manifold's end when it starts at A_min. A branch
that reaches A = A_min ends there (``END``, "manifold end"): it does not wander onto the
unstable manifold branch.
"""

from __future__ import annotations

import dataclasses

import numpy as np

import slosh_bif.continuation as cont
from slosh_bif.continuation.branch import Branch
from slosh_bif.model.params import Params
from slosh_bif.model.restitution import END_KINDS
from slosh_bif.newton import NewtonSettings, newton_loop
from slosh_bif.slowflow.flow import SlowFlow

__all__ = [
    "SteadyStateProblem",
    "FrequencyResponse",
    "frequency_response",
    "forcing_response",
    "sigma_on_curve",
    "abar_on_curve",
]

PARAMS = ("sigma", "Abar")
# Points closer to the manifold's end than this (relative) are ill-conditioned: alpha has a
# square root there, and rounding in A**2 - A_min**2 would show up as 1e-8 in alpha.
EDGE_MARGIN = 1e-8


class SteadyStateProblem:
    """Equilibria ``(A, psi)`` of (45) with ``param`` ("sigma" or "Abar") free; a continuation problem."""

    names = ("A", "psi")
    branch_kind = "steady states of (45)"
    edge_name = "manifold end A = A_min"
    stability_from_jacobian = True  # the residual is the slow flow: its Jacobian decides stability

    def __init__(self, params: Params, param: str = "sigma", model: str = "slowflow"):
        if param not in PARAMS:
            raise ValueError(f"continued parameter must be one of {', '.join(PARAMS)}; got {param!r}")
        self.params = params
        self.param = param
        self.flow = SlowFlow(params, model)
        self._rhs, self._jac, self._dparams = (
            self.flow.generated(name) for name in ("slow_rhs", "slow_jac", "slow_dparams")
        )
        self.A_edge = self.flow.A_min * (1 + EDGE_MARGIN)
        self.A_edge_high = self.flow.A_max * (1 - EDGE_MARGIN)
        self._column = PARAMS.index(param)
        # The engine only evaluates inside the domain (A >= A_edge), so the generated functions are
        # called directly, without SlowFlow's per-call input checks; rho is a constant at pbar = 0
        # in the paper's model (the corrected model's clearance is never constant).
        self._rho0 = (self.flow.rho(1.0)[0].item(), 0.0) if self.flow.newtonian else None

    def _values(self, A):
        """The law's arguments of the generated functions after (A, psi)."""
        return self._rho0[:1] if self._rho0 is not None else tuple(float(v) for v in self.flow.law.values(A))

    def _slopes(self, A):
        return self._rho0 if self._rho0 is not None else tuple(float(v) for v in self.flow.law.slopes(A))

    def _slow(self, p):
        P = self.params
        return (P.beta, P.gamma, p, P.Abar) if self.param == "sigma" else (P.beta, P.gamma, P.sigma, p)

    def residual(self, x, p):
        return self._rhs(x[0], x[1], *self._values(x[0]), *self._slow(p))

    def jacobian(self, x, p):
        # On an end of S+ itself (an END point) d alpha/dA is infinite: the Jacobian, and so the
        # stability of the END row, is the limit from just inside.
        A = min(max(x[0], self.A_edge), self.A_edge_high)
        return self._jac(A, x[1], *self._slopes(A), *self._slow(p))

    def dparam(self, x, p):
        return self._dparams(x[0], x[1], *self._values(x[0]), *self._slow(p))[:, self._column]

    def in_domain(self, x, p):
        return bool(self.A_edge <= x[0] <= self.A_edge_high)

    def edge_distance(self, x, p):
        """Relative distance of A from the nearer end of S+."""
        upper = (
            (self.flow.A_max - x[0]) / self.flow.A_max if np.isfinite(self.flow.A_max) else np.inf
        )  # S+ may be unbounded above
        return min((x[0] - self.flow.A_min) / self.flow.A_min, upper)

    def edge_point(self, x, p):
        """The steady state exactly on the end of S+ nearest (x, p): A = A_min (or A_max), with psi
        and the parameter by Newton on (45) there. Neither the residual nor its derivatives in psi
        and the parameter involve d alpha/dA, which is infinite at the manifold's end (36), where
        the flow is evaluated with alpha = alpha_min exactly (no square root of a rounding error)."""
        law = self.flow.law
        end = law.lower if law.upper is None or abs(x[0] - law.A_min) <= abs(x[0] - law.A_max) else law.upper
        self.edge_name = end.describe()
        A = end.A
        at_end = self._rho0[:1] if self._rho0 is not None else law.end_values(end)
        with_slopes = tuple(x for value in at_end for x in (value, 0.0))  # only d/dpsi is used: no d/dA
        at_36 = end.kind == END_KINDS[0]  # alpha = alpha_min there: the functions written for it
        rhs_end, end_jac = self.flow.generated("slow_rhs_end"), self.flow.generated("slow_end_jac")

        def residual(z):
            slow = self._slow(z[1])
            return rhs_end(z[0], *at_end, *slow) if at_36 else self._rhs(A, z[0], *at_end, *slow)

        def jacobian(z):
            slow = self._slow(z[1])
            if at_36:
                D = end_jac(z[0], *at_end, *slow)
                return np.column_stack([D[:, 0], D[:, 1 + self._column]])
            return np.column_stack(
                [
                    self._jac(A, z[0], *with_slopes, *slow)[:, 1],
                    self._dparams(A, z[0], *at_end, *slow)[:, self._column],
                ]
            )

        run = newton_loop(residual, jacobian, np.array([x[1], p], dtype=float), NewtonSettings(tol=1e-14))
        return (np.array([A, run.x[0]]), run.x[1]) if run.converged else None


def sigma_on_curve(flow: SlowFlow, A, *, rounding: float = 0.0):
    """Both roots sigma(A) of (46) at amplitude(s) A (NaN where pi^2 A Abar < E; with ``rounding``,
    a discriminant below zero by at most that fraction of (pi^2 A Abar)^2 counts as zero: the
    curve's turn, where the two roots meet)."""
    A = np.asarray(A, dtype=float)
    E, Phi0 = flow.steady_balances(A, sigma=0.0)  # Phi is Phi0 - pi^2 A^2 sigma
    force = (np.pi**2 * A * flow.params.Abar) ** 2
    disc = force - E**2
    disc = np.where(disc >= -rounding * force, np.maximum(disc, 0.0), np.nan)
    root = np.sqrt(disc)
    scale = np.pi**2 * A**2
    return (Phi0 - root) / scale, (Phi0 + root) / scale


def abar_on_curve(flow: SlowFlow, A, sigma=None):
    """The forcing Abar of the steady state of amplitude A (at the flow's sigma, or ``sigma``):
    (46) is explicit in Abar^2 for fixed A, Abar = |(E, Phi)| / (pi^2 A)."""
    E, Phi = flow.steady_balances(A, sigma=sigma, Abar=1.0)
    return np.hypot(E, Phi) / (np.pi**2 * np.asarray(A, dtype=float))


def _feasible_intervals(flow: SlowFlow, A_max):
    """Intervals of A in [A_edge, A_max] where steady states exist (a log grid, for start points only)."""
    A = np.geomspace(flow.A_min * (1 + 2 * EDGE_MARGIN), min(A_max, flow.A_max * (1 - 2 * EDGE_MARGIN)), 4000)
    ok = np.isfinite(sigma_on_curve(flow, A)[0])
    edges = np.flatnonzero(np.diff(ok.astype(int)))
    starts = [0] if ok[0] else []
    starts += [i + 1 for i in edges if not ok[i]]
    stops = [i for i in edges if ok[i]] + ([len(A) - 1] if ok[-1] else [])
    return [(A[a], A[b]) for a, b in zip(starts, stops) if b > a]


def _amplitude_bound(params: Params):
    # Beyond this the energy balance pi^2 A Abar = E cannot hold: E >= gamma pi^2 A^2.
    return 10.0 * (params.Abar / params.gamma + 1.0) if params.gamma > 0 else 1e3


@dataclasses.dataclass(frozen=True)
class FrequencyResponse:
    """All components of a frequency-response curve, each a :class:`~slosh_bif.continuation.branch.Branch`."""

    params: Params
    branches: tuple
    A_min: float
    model: str = "slowflow"

    def alpha(self, branch: Branch):
        """alpha_S+ along a branch (its A column)."""
        return SlowFlow(self.params, self.model).alpha(branch.x[:, 0])


def frequency_response(
    params: Params,
    *,
    sigma_min=None,
    sigma_max=None,
    options: cont.ContinuationOptions | None = None,
    model: str = "slowflow",
) -> FrequencyResponse:
    """Trace every component of the frequency-response curve A(sigma) of (45)/(46) on S+.

    ``sigma_min``/``sigma_max`` default to the range where steady states exist, plus a margin.
    Continuation options' ``p_min``/``p_max`` are set from them. ``model``: the paper's slow flow
    or the corrected one (:class:`~slosh_bif.slowflow.flow.SlowFlow`).
    """
    if not params.Abar > 0:
        raise ValueError(
            f"a frequency-response curve needs forcing: parameter Abar must be > 0; got {params.Abar}"
        )
    problem = SteadyStateProblem(params, "sigma", model)
    flow = problem.flow
    intervals = _feasible_intervals(flow, _amplitude_bound(params))
    if not intervals:
        raise ValueError(
            f"no steady state on the stable manifold branch for any sigma at Abar = {params.Abar} "
            "(below the critical forcing)"
        )
    if sigma_min is None or sigma_max is None:
        A_all = np.concatenate([np.geomspace(lo, hi, 200) for lo, hi in intervals])
        s_all = np.concatenate(sigma_on_curve(flow, A_all))
        s_all = s_all[np.isfinite(s_all)]
        margin = 0.1 * (s_all.max() - s_all.min()) + 0.1
        sigma_min = s_all.min() - margin if sigma_min is None else sigma_min
        sigma_max = s_all.max() + margin if sigma_max is None else sigma_max
    if not (np.isfinite(sigma_min) and np.isfinite(sigma_max) and sigma_min < sigma_max):
        raise ValueError(f"need finite sigma_min < sigma_max; got {sigma_min} and {sigma_max}")
    opts = dataclasses.replace(
        options or cont.ContinuationOptions(), p_min=float(sigma_min), p_max=float(sigma_max)
    )
    branches = []
    for lo, hi in intervals:
        # Start points: samples of the component (both roots of (46)) inside the range, the middle
        # one first; each further piece of the component inside the range gets its own branch.
        A_s = np.geomspace(lo, hi, 203)[1:-1]
        candidates = []
        for root in sigma_on_curve(flow, A_s):
            candidates += [
                (A, sg) for A, sg in zip(A_s, root) if np.isfinite(sg) and sigma_min < sg < sigma_max
            ]
        candidates.sort(key=lambda c: abs(c[0] - np.sqrt(lo * hi)))
        while candidates:
            A0, sigma0 = candidates.pop(0)
            psi0 = float(flow.steady_phase(A0, sigma=sigma0))
            branch = cont.continuation(problem, [A0, psi0], float(sigma0), param="sigma", options=opts)
            branches.append(branch)
            candidates = [
                (A, sg)
                for A, sg in candidates
                if np.min(np.hypot(branch.x[:, 0] - A, branch.p - sg)) >= 2 * opts.step_max
            ]
    return FrequencyResponse(params=params, branches=tuple(branches), A_min=flow.A_min, model=model)


def forcing_response(
    params: Params,
    *,
    abar_min: float = 0.0,
    abar_max: float | None = None,
    options: cont.ContinuationOptions | None = None,
    model: str = "slowflow",
) -> FrequencyResponse:
    """Steady states of (45)/(46) on S+ at the parameter set's sigma, continued in Abar over
    [abar_min, abar_max] (default: up to ten times the forcing of the largest-amplitude start).

    For fixed A, Abar is explicit (:func:`abar_on_curve`), so the curve is one arc from the
    manifold's end to large A; each piece of it inside the Abar range is one branch.
    """
    problem = SteadyStateProblem(params, "Abar", model)
    flow = problem.flow
    A_top = min(
        _amplitude_bound(params.replace(Abar=max(params.Abar, abar_max or 0.0, 1.0))),
        flow.A_max * (1 - 2 * EDGE_MARGIN),
    )
    A = np.geomspace(flow.A_min * (1 + 2 * EDGE_MARGIN), A_top, 4000)
    abar = abar_on_curve(flow, A)
    if abar_max is None:
        abar_max = float(max(10.0, 10 * abar[np.argmin(np.abs(A - max(1.0, 3 * flow.A_min)))]))
    if not (np.isfinite(abar_min) and np.isfinite(abar_max) and 0 <= abar_min < abar_max):
        raise ValueError(f"need finite 0 <= abar_min < abar_max; got {abar_min} and {abar_max}")
    opts = dataclasses.replace(
        options or cont.ContinuationOptions(step=0.02, step_max=0.2),
        p_min=float(abar_min),
        p_max=float(abar_max),
    )
    inside = (abar > abar_min) & (abar < abar_max)
    if not np.any(inside):
        raise ValueError(
            f"no steady state on S+ with Abar in [{abar_min}, {abar_max}] at sigma = "
            f"{params.sigma} (Abar ranges over [{abar.min():.6g}, {abar.max():.6g}] for A up to "
            f"{A[-1]:.3g})"
        )
    branches = []
    starts = np.flatnonzero(inside & ~np.r_[False, inside[:-1]])  # each piece's first point
    for i0 in starts:
        i1 = i0 + int(np.argmax(~inside[i0:])) if not np.all(inside[i0:]) else len(A)
        k = (i0 + i1 - 1) // 2  # the middle of the piece
        psi0 = float(flow.steady_phase(A[k], Abar=abar[k]))
        branches.append(cont.continuation(problem, [A[k], psi0], float(abar[k]), param="Abar", options=opts))
    return FrequencyResponse(params=params, branches=tuple(branches), A_min=flow.A_min, model=model)
