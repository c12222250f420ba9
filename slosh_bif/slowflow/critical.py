"""The critical forcing Abar_b: the smallest Abar with a steady state on S+, eq. (46).

Along the steady states at fixed sigma, Abar is a function of A (eq. 46 is explicit in Abar^2),
so the smallest Abar sits either at an interior fold of A(Abar) (dR/dA = 0 with R the residual
of (46)) or at an end of S+ (A_min, or an upper end where one exists). :func:`critical_forcing`
finds it at one sigma by minimising that function over the window of S+ (a continuation in Abar
stalled or started outside short windows on some restitution laws).

:func:`critical_curve` follows Abar_b(sigma) by two-parameter continuation, in sigma, of

* the fold condition ``R = 0, dR/dA = 0`` in ``(A, Abar)`` (:class:`FoldProblem`), and
* the end-point condition ``R(A_min) = 0`` in ``Abar`` (:class:`EndProblem`),

and keeps, at each sigma, the least of them; only folds that are minima of Abar(A)
(``d2R/dA2 / dR/dAbar < 0``) count.
"""

from __future__ import annotations

import dataclasses

import numpy as np

import slosh_bif.continuation as cont
from slosh_bif.model.params import Params
from slosh_bif.model.restitution import END_KINDS
from slosh_bif.slowflow.flow import SlowFlow
from slosh_bif.slowflow.steady_states import (
    EDGE_MARGIN,
    SteadyStateProblem,
    _amplitude_bound,
    abar_on_curve,
)

__all__ = [
    "CriticalPoint",
    "CriticalCurve",
    "abar_branch",
    "critical_forcing",
    "critical_curve",
    "FoldProblem",
    "EndProblem",
    "interp_min",
    "abar_at_upper_end",
]


class _Residual46:
    """R(A; sigma, Abar) of (46) and its gradient, with second derivatives by central differences.

    The problems below divide R by pi^4 A^2 (so R/(pi^4 A^2) = Abar(A)^2 - Abar^2 is of order one;
    R itself is ~ 1e2 and an absolute tolerance of 1e-11 would sit at its rounding level).
    """

    def __init__(self, params: Params, model: str = "slowflow"):
        self.flow = SlowFlow(params, model)
        self.A_edge = self.flow.A_min * (1 + EDGE_MARGIN)

    def R(self, A, sigma, Abar):
        return float(self.flow.steady_residual(A, sigma, Abar))

    def grad(self, A, sigma, Abar):
        """[R_A, R_sigma, R_Abar]."""
        return np.asarray(self.flow.steady_residual_grad(A, sigma, Abar), dtype=float)

    def hess_row(self, A, sigma, Abar):
        """[R_AA, R_Asigma, R_AAbar] by central differences of the analytic R_A."""
        out = []
        for i, v in enumerate((A, sigma, Abar)):
            h = 1e-6 * max(1.0, abs(v))
            if i == 0:  # keep the stencil on the manifold, clear of the square root at A_min
                h = min(h, 0.5 * (A - self.flow.A_min))
            up, down = [A, sigma, Abar], [A, sigma, Abar]
            up[i], down[i] = v + h, v - h
            out.append((self.grad(*up)[0] - self.grad(*down)[0]) / (2 * h))
        return np.array(out)

    def abar_at(self, A, sigma):
        """The (unique, non-negative) Abar of the steady state of amplitude A at sigma."""
        E, Phi = self.flow.steady_balances(A, sigma=sigma, Abar=1.0)
        return float(np.hypot(E, Phi) / (np.pi**2 * A))


# A fold curve that runs into the manifold's end merges there with the end-point curve; its
# second derivatives blow up like (A - A_min)^(-3/2), so it is followed only this far.
FOLD_EDGE_MARGIN = 1e-5


class FoldProblem:
    """Folds of A(Abar): x = (A, Abar) with R = R_A = 0 (scaled by pi^4 A^2), continued in sigma."""

    names = ("A", "Abar")
    branch_kind = "folds of (46)"

    def __init__(self, params: Params, model: str = "slowflow"):
        self.r = _Residual46(params, model)
        self.A_edge = self.r.flow.A_min * (1 + FOLD_EDGE_MARGIN)
        self.A_edge_high = self.r.flow.A_max * (1 - FOLD_EDGE_MARGIN)  # inf where S+ has no upper end

    def _parts(self, x, p):
        A, Abar = x
        s = np.pi**4 * A**2
        return A, s, self.r.R(A, p, Abar), self.r.grad(A, p, Abar)

    def residual(self, x, p):
        _, s, R, g = self._parts(x, p)
        return np.array([R, g[0]]) / s

    def jacobian(self, x, p):
        A, s, R, g = self._parts(x, p)
        h = self.r.hess_row(A, p, x[1])
        # d(f/s)/dA = (f_A - 2 f / A) / s for s = pi^4 A^2.
        return np.array([[g[0] - 2 * R / A, g[2]], [h[0] - 2 * g[0] / A, h[2]]]) / s

    def dparam(self, x, p):
        A, s, _, g = self._parts(x, p)
        return np.array([g[1], self.r.hess_row(A, p, x[1])[1]]) / s

    def in_domain(self, x, p):
        return bool(self.A_edge <= x[0] <= self.A_edge_high and x[1] > 0)

    def is_minimum(self, x, p):
        """Whether Abar(A) has a minimum (not a maximum) at this fold: -R_AA/R_Abar > 0."""
        A, Abar = x
        return bool(-self.r.hess_row(A, p, Abar)[0] / self.r.grad(A, p, Abar)[2] > 0)


class EndProblem:
    """The end-point condition R(A_end; sigma, Abar) = 0: x = (Abar,), continued in sigma.

    Evaluated exactly at an end of S+, the lower A_min (``end="lower"``) or, where a fold of (39)
    or kappa = 0 ends S+ above, its upper end A_max (``end="upper"``): R and its derivatives in
    sigma and Abar are regular there (only R_A, through d alpha/dA or d kappa/dA, is infinite,
    and it is not used).
    """

    names = ("Abar",)
    branch_kind = "manifold ends of (46)"

    def __init__(self, params: Params, model: str = "slowflow", end: str = "lower"):
        self.r = _Residual46(params, model)
        law = self.r.flow.law
        if end not in ("lower", "upper") or (end == "upper" and law.upper is None):
            raise ValueError(
                f"end must be 'lower' or, where S+ has one, 'upper'; got {end!r} (S+: {law.describe()})"
            )
        self.A = law.A_min if end == "lower" else law.upper.A
        self.scale = np.pi**4 * self.A**2
        P = params
        if (
            end == "lower" and law.lower.kind == END_KINDS[0]
        ):  # alpha = alpha_min: the functions written for the end
            at_end, residual_end = law.end_values(law.lower), self.r.flow.generated("steady_residual_end")
            self._parts = lambda p, Abar: residual_end(*at_end, P.beta, P.gamma, p, Abar)
        else:  # a fold of (39) or kappa = 0 ends S+: alpha is regular there
            self._parts = self._parts_at_fold

    def _parts_at_fold(self, p, Abar):
        """R, R_sigma, R_Abar at an end where S+ folds: R_A is infinite there (an inf or NaN that
        is not used, so numpy's warning about it is silenced)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            grad = self.r.grad(self.A, p, Abar)
        return np.array([self.r.R(self.A, p, Abar), *grad[1:]])

    def abar_at(self, sigma):
        """The Abar of the steady state on the end at ``sigma``: R = a Abar^2 + b (even in Abar)."""
        R1, _, dR1 = self._parts(sigma, 1.0)
        a = 0.5 * dR1
        return float(np.sqrt(max(-(R1 - a) / a, 0.0)))

    def residual(self, x, p):
        return np.array([self._parts(p, x[0])[0]]) / self.scale

    def jacobian(self, x, p):
        return np.array([[self._parts(p, x[0])[2]]]) / self.scale

    def dparam(self, x, p):
        return np.array([self._parts(p, x[0])[1]]) / self.scale

    def in_domain(self, x, p):
        return bool(x[0] > 0)


@dataclasses.dataclass(frozen=True)
class CriticalPoint:
    """Abar_b at one sigma: the value, the amplitude A there, and whether it is a fold or the end."""

    sigma: float
    Abar_b: float
    A: float
    kind: str  # "LP" (interior fold) or "END" (manifold end)


DEFAULT_OPTIONS = cont.ContinuationOptions(step=0.02, step_max=0.2)


def abar_branch(
    params: Params, sigma: float, *, options: cont.ContinuationOptions | None = None, model: str = "slowflow"
):
    """Steady states on S+ at fixed ``sigma``, continued in Abar: one branch from A_min to large A
    (or to the upper end of S+)."""
    P = params.replace(sigma=float(sigma))
    problem = SteadyStateProblem(P, "Abar", model)
    flow = problem.flow
    A0 = max(1.0, 3 * flow.A_min)
    if not A0 < flow.A_max * (1 - 2 * EDGE_MARGIN):  # a short window of S+ (an upper end): its middle
        A0 = float(np.sqrt(flow.A_min * flow.A_max))
    Abar0 = _Residual46(P, model).abar_at(A0, P.sigma)
    psi0 = float(flow.steady_phase(A0, Abar=Abar0))
    opts = dataclasses.replace(options or DEFAULT_OPTIONS, p_min=0.0, p_max=max(10.0, 10 * Abar0))
    return cont.continuation(problem, [A0, psi0], Abar0, param="Abar", options=opts)


def critical_forcing(params: Params, sigma: float, *, model: str = "slowflow") -> CriticalPoint:
    """The smallest Abar with a steady state on S+ at ``sigma``.

    At fixed sigma, (46) gives Abar explicitly as a function of A on S+ (:func:`abar_on_curve`),
    so Abar_b is its least value over the window of S+: at an end of S+ (``END``, evaluated at
    the end itself) or at an interior minimum, a fold of the Abar branch (``LP``, located by
    bounded Brent to 1e-13 in A). With gamma > 0, Abar >= gamma A, so amplitudes beyond
    (the least Abar so far) / gamma need no search. ``model``: the paper's slow flow or the
    corrected one.
    """
    P = params.replace(sigma=float(sigma))
    flow = SlowFlow(P, model)
    lo, hi = flow.A_min, flow.A_max
    guess = float(abar_on_curve(flow, min(max(1.0, 3 * lo), np.sqrt(lo * hi) if np.isfinite(hi) else np.inf)))
    top = min(hi, _amplitude_bound(P.replace(Abar=max(guess, 1e-12))))
    A = np.geomspace(lo, top, 4001)
    A[-1] = top
    # The ends by their own closed forms: at the lower end alpha has a square root in A (NaN at
    # A_min itself by rounding); at an upper end (a fold of (39), kappa = 0) alpha is regular, but
    # kappa(A) is found only inside, so the end's kappa gives rho there.
    abar = np.concatenate(
        [
            [EndProblem(P, model).abar_at(P.sigma)],
            abar_on_curve(flow, A[1:-1]),
            [abar_at_upper_end(flow, top)],
        ]
    )
    finite = np.isfinite(abar)
    if not np.any(finite):
        raise RuntimeError(
            f"(46) has no steady state on S+ at sigma = {sigma} for A in [{lo:.10g}, {top:.10g}]"
        )
    i = int(np.nanargmin(np.where(finite, abar, np.nan)))
    if i == 0:
        return CriticalPoint(sigma=float(sigma), Abar_b=float(abar[0]), A=float(lo), kind=cont.Kind.END.value)
    if i == len(A) - 1:
        if top == hi:
            return CriticalPoint(
                sigma=float(sigma), Abar_b=float(abar[-1]), A=float(hi), kind=cont.Kind.END.value
            )
        raise RuntimeError(
            f"Abar of (46) at sigma = {sigma} still falls at A = {top:.6g}, the largest amplitude searched"
        )
    from scipy import optimize  # here: importing the slow flow does not import scipy.optimize

    found = optimize.minimize_scalar(
        lambda a: float(abar_on_curve(flow, a)),
        bounds=(A[i - 1], A[i + 1]),
        method="bounded",
        options={"xatol": 1e-13 * A[i]},
    )
    return CriticalPoint(
        sigma=float(sigma), Abar_b=float(found.fun), A=float(found.x), kind=cont.Kind.FOLD.value
    )


def abar_at_upper_end(flow: SlowFlow, A):
    """Abar of the steady state at A, the largest amplitude searched: the upper end of S+ itself
    (its kappa from the end, not from (39)) when A is that end."""
    if A < flow.A_max:
        return float(abar_on_curve(flow, A))
    E, Phi = flow.generated("steady_balances")(
        A, *flow.law.end_values(flow.law.upper), *flow._slow_with(None, 1.0)
    )
    return float(np.hypot(E, Phi) / (np.pi**2 * A))


@dataclasses.dataclass(frozen=True)
class CriticalCurve:
    """Abar_b(sigma): arrays in increasing sigma, with the curve (fold or end) each point comes from."""

    params: Params
    sigma: np.ndarray
    Abar_b: np.ndarray
    A: np.ndarray
    kind: np.ndarray  # "LP" or "END" per point
    end_branch: object
    fold_branches: tuple
    model: str = "slowflow"
    upper_end_branch: object = None  # the curve on the upper end of S+, where one ends it


def _trace(problem, x0, sigma0, lo, hi, options):
    opts = dataclasses.replace(options, p_min=lo, p_max=hi)
    return cont.continuation(problem, x0, sigma0, param="sigma", options=opts)


def critical_curve(
    params: Params,
    sigma_min: float,
    sigma_max: float,
    *,
    seeds: int = 7,
    options: cont.ContinuationOptions | None = None,
    progress=None,
    model: str = "slowflow",
) -> CriticalCurve:
    """Abar_b(sigma) over [sigma_min, sigma_max] by continuation of the fold and end-point conditions.

    Folds are seeded by :func:`critical_forcing` at ``seeds`` values of sigma; each fold curve is
    then traced by continuation (a seed on an already traced curve is skipped). ``progress``, if
    given, is called with a short message after each stage.
    """
    report = progress or (lambda message: None)
    if not sigma_min < sigma_max:
        raise ValueError(f"need sigma_min < sigma_max; got {sigma_min} and {sigma_max}")
    opts = options or DEFAULT_OPTIONS
    ends = []
    for which in ("lower", "upper") if SlowFlow(params, model).law.upper is not None else ("lower",):
        end_problem = EndProblem(params, model, which)
        ends.append(
            _trace(
                end_problem, [end_problem.abar_at(sigma_min)], float(sigma_min), sigma_min, sigma_max, opts
            )
        )
        report(f"{which} end-point curve: {len(ends[-1])} points")
    fold_problem = FoldProblem(params, model)
    folds = []
    for k, sigma in enumerate(np.linspace(sigma_min, sigma_max, seeds)):
        for lp in abar_branch(params, sigma, options=opts, model=model).special_of("LP"):
            x = np.array([lp.x[0], lp.p])
            if not any(_on_branch(b, x, sigma) for b in folds):
                folds.append(_trace(fold_problem, x, float(sigma), sigma_min, sigma_max, opts))
                report(f"fold curve {len(folds)}: {len(folds[-1])} points ({folds[-1].message})")
        report(f"seed {k + 1}/{seeds} at sigma = {sigma:.4g} done")
    return dataclasses.replace(_envelope(params, tuple(ends), tuple(folds), fold_problem), model=model)


def _on_branch(branch, x, sigma, tol=1e-6):
    near = np.abs(branch.p - sigma) < 0.5 * branch.options["step_max"] + 1e-12
    if not np.any(near):
        return False
    return bool(
        np.min(np.linalg.norm(branch.x[near] - x, axis=1)) < max(tol, 0.5 * branch.options["step_max"])
    )


def _envelope(params, ends, folds, fold_problem) -> CriticalCurve:
    """Least of the end curves and the minimum-type fold curves, point by point in sigma."""
    flow = fold_problem.r.flow
    candidates = [
        (end.p, end.x[:, 0], np.full(len(end), A), "END") for end, A in zip(ends, (flow.A_min, flow.A_max))
    ]
    for b in folds:
        minimum = np.array([fold_problem.is_minimum(x, p) for x, p in zip(b.x, b.p)])
        candidates.append((b.p[minimum], b.x[minimum, 1], b.x[minimum, 0], "LP"))
    rows = []
    for k, (s, abar, A, kind) in enumerate(candidates):
        for i in range(len(s)):
            others = [interp_min(s2, abar2, s[i]) for j, (s2, abar2, _, _) in enumerate(candidates) if j != k]
            if all(abar[i] <= o + 1e-12 for o in others if o is not None):
                rows.append((s[i], abar[i], A[i], kind))
    rows.sort()
    # The same point can come from two curves (where they meet) or twice from one (a bound): keep one.
    rows = [
        r
        for i, r in enumerate(rows)
        if i == 0 or abs(r[0] - rows[i - 1][0]) > 1e-12 or abs(r[1] - rows[i - 1][1]) > 1e-12
    ]
    sigma, Abar_b, A, kind = (np.array(c) for c in zip(*rows)) if rows else (np.array([]),) * 4
    return CriticalCurve(
        params,
        sigma.astype(float),
        Abar_b.astype(float),
        A.astype(float),
        kind,
        ends[0],
        folds,
        upper_end_branch=ends[1] if len(ends) > 1 else None,
    )


def interp_min(s, v, at):
    """The least value of a (possibly multi-valued) curve (s, v) at s = at, by linear interpolation
    (segments with a non-finite end are skipped); None where no segment spans ``at``."""
    values = [
        v[i] + (v[i + 1] - v[i]) * (at - s[i]) / (s[i + 1] - s[i])
        for i in range(len(s) - 1)
        if min(s[i], s[i + 1]) <= at <= max(s[i], s[i + 1])
        and s[i] != s[i + 1]
        and np.isfinite(v[i])
        and np.isfinite(v[i + 1])
    ]
    return min(values) if values else None
