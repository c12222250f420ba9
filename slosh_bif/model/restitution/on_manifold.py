"""The restitution law on the stable manifold branch S+: kappa(A) and rho(A) of (39), (40), and
where S+ ends.

On S+ the impact speed (38) depends on the amplitude A through alpha(A, rho), so for a
velocity-dependent wall (pbar != 0) kappa, and with it rho (31) and the manifold (36), depend on
A through the implicit eq. (39), G(kappa, A) = kappa^2 - 1 + delta(v(kappa, A)) = 0. For pbar = 0
kappa is the Newtonian constant of (40). This one object answers, once per parameter set, what
the slow flow, the critical forcing, the regime classifier and the slow-flow start of shooting
all ask: rho(A) and d rho/dA, alpha_S+(A), and the window [A_min, A_max] of A where S+ exists.

Notes
-----
S+ carries the root of (39) reached continuously from the elastic limit (the largest root in
(0, 1]). It can end, as A decreases or increases, in three ways, each located to machine
precision from its own equations:

* ``manifold end (36)``: A = A_min(rho(kappa)), where S+ meets the unstable branch of (36) (the
  only end for pbar = 0, and the lower end for small dissipation);
* ``fold of (39)``: G = dG/dkappa = 0, the root merges with a smaller one and vanishes (Newton
  on the pair, with the generated gradient);
* ``kappa reaches 0``: G(0, A) = 0, the wall becomes perfectly plastic (bracketing in A).

For pbar > 0 the impact speed grows with A and the dissipation with it, so S+ also ends at a
finite largest amplitude; for pbar < 0 the dissipation grows as the speed falls, so the lower
end may be a fold of (39) above A_min(rho).
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from slosh_bif.model import manifold
from slosh_bif.model._generated import slow_flow as gen
from slosh_bif.model.restitution import eq21 as restitution
from slosh_bif.model.restitution.checks import check_params

__all__ = ["ManifoldLaw", "ManifoldEnd", "END_KINDS"]

END_KINDS = ("manifold end (36)", "fold of (39)", "kappa reaches 0")
_SCAN = np.geomspace(1e-4, 1e4, 801)  # amplitudes scanned for the window (refined at its ends)


def scipy_optimize():
    """scipy.optimize, imported on first use: at module level it cost every command ~0.2 s of
    start-up (``slosh-bif info`` needs no root finding)."""
    from scipy import optimize

    return optimize


@dataclasses.dataclass(frozen=True)
class ManifoldEnd:
    """One end of S+: amplitude A, kappa there, and which of :data:`END_KINDS` it is."""

    A: float
    kappa: float
    kind: str

    def describe(self) -> str:
        return f"end of S+ at A = {self.A:.10g} ({self.kind}, kappa = {self.kappa:.6g})"


def _drho_dkappa(k):
    return -4.0 / (np.pi * (1.0 + k) ** 2)


class _Eq39:
    """Eq. (39) for one wall (lam, chi, n, pbar), pbar != 0, and the ends of S+ it sets."""

    def __init__(self, lam, chi, n, pbar):
        self.lam, self.chi, self.n, self.pbar = lam, chi, n, pbar
        self.where = f"lam={lam}, chi={chi}, n={n}, pbar={pbar}"
        self._delta1 = float(restitution.dissipation_at_unit_speed(lam, chi, n, pbar))
        self._expo = pbar / (n + 1)
        self.lower, self.upper = self._window()

    def _G(self, k, A):
        with np.errstate(invalid="ignore"):
            return float(gen.manifold_kappa_residual(k, A, self._delta1, self._expo))

    def _G_grad(self, k, A):
        with np.errstate(invalid="ignore", divide="ignore"):
            return (float(v) for v in gen.manifold_kappa_residual_grad(k, A, self._delta1, self._expo))

    def _largest_root(self, A):
        return float(
            restitution.kappa_on_manifold(
                np.array([A]), self.lam, self.chi, self.n, self.pbar, strict=False
            ).kappa[0]
        )

    def _root_near_manifold_end(self, A, k_end):
        """The root just above the manifold end, where it sits within rounding of the smallest
        kappa on the manifold at A (the scan's cells are too coarse there): bracket it between
        that smallest kappa, nudged until (39) is defined, and the end's kappa."""
        k_low = restitution.kappa_low(A)
        for d in 10.0 ** np.arange(-15, -5):
            g = self._G(k_low + d, A)
            if np.isfinite(g):
                break
        hi = k_end if self._G(k_end, A) > 0 else 1.0
        if np.isfinite(g) and g > 0 and self._G(hi, A) > 0 and abs(k_end - k_low) < 1e-6:
            # Within ~1e-8 of the end the root is closer to the edge than the first offset at
            # which (39) is defined: it lies in (k_low, k_low + d), and k_low + d is it to d.
            return float(k_low + d)
        if not (np.isfinite(g) and g < 0 < self._G(hi, A)):
            return np.nan
        return float(
            scipy_optimize().brentq(
                lambda k: self._G(k, A), k_low + d, hi, xtol=1e-16, rtol=4 * np.finfo(float).eps
            )
        )

    def _window(self):
        """The ends of the longest run of amplitudes on which the root of (39) exists and moves
        continuously, each located from its own equations."""
        roots = np.array([self._largest_root(A) for A in _SCAN])
        ok = np.isfinite(roots)
        # A jump of the largest root between neighbours is a fold passed over: the run ends there.
        jump = np.abs(np.diff(roots)) > 0.2
        runs, start = [], None
        for i in range(len(_SCAN)):
            if ok[i] and start is None:
                start = i
            if start is not None and (i == len(_SCAN) - 1 or not ok[i + 1] or jump[i]):
                runs.append((start, i))
                start = None
        if not runs:
            raise ValueError(
                "no restitution coefficient in (0, 1] solves eq. (39) for any amplitude A in "
                f"[1e-4, 1e4] ({self.where})"
            )
        lo, hi = max(runs, key=lambda r: r[1] - r[0])
        lower = self._end(_SCAN[lo], roots[lo], _SCAN[lo - 1] if lo > 0 else 0.0)
        upper = self._end(_SCAN[hi], roots[hi], _SCAN[hi + 1]) if hi < len(_SCAN) - 1 else None
        return lower, upper

    def _end(self, A_in, k_in, A_out):
        """The end of S+ between A_in (root k_in) and A_out (no root, or another one)."""
        candidates = []
        k36 = self._manifold_end_kappa()
        if k36 is not None:
            A36 = float(gen.sim_a_min(restitution.rho(k36)))
            # For pbar < 0, G falls like -sqrt(kappa - k_low) off the manifold's edge: the root
            # leaving the edge at the (36) end and the largest one fold together just below it.
            near = self._fold_below_manifold_end(A36)
            candidates.append(near if near is not None else ManifoldEnd(A36, k36, END_KINDS[0]))
        fold = self._fold(A_in, k_in)
        if fold is not None:
            candidates.append(fold)
        lo, hi = sorted((A_in, A_out))
        g0 = lambda A: self._G(1e-300, A)  # noqa: E731 - G at kappa -> 0+
        if lo > 0 and np.isfinite(g0(lo)) and np.isfinite(g0(hi)) and np.sign(g0(lo)) != np.sign(g0(hi)):
            candidates.append(
                ManifoldEnd(
                    float(scipy_optimize().brentq(g0, lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps)),
                    0.0,
                    END_KINDS[2],
                )
            )
        # The scan's bracket is approximate near a fold (two close roots in one scan cell look
        # like none): widen it, then keep the candidate at which the tracked root itself ends
        # (another root may leave (0, 1] or fold away nearby, as for pbar = 2, n = 10).
        width = hi - lo
        inside = [c for c in candidates if lo - width <= c.A <= hi + width and self._ends_here(c, A_in)]
        if not inside:
            raise ValueError(
                f"the end of S+ between A = {lo:.6g} and {hi:.6g} could not be located ({self.where})"
            )
        return min(inside, key=lambda c: abs(c.A - A_in))

    def _ends_here(self, end: ManifoldEnd, A_in) -> bool:
        """Whether the largest root, just inside the end (toward A_in), is the end's kappa.

        Needed for every kind: for pbar = -2 the manifold end (36) lies on the *second* root,
        and the largest one folds away below it; for pbar = 2, n = 10 the second root leaves
        (0, 1] just before the largest one folds.
        """
        if end.kind == END_KINDS[0]:
            # At the manifold end the root sits on the edge kappa = k_low(A) of the manifold, where
            # (39) has a square root: instead of looking just inside, ask whether any root lies
            # above it at the end itself (then the largest root is another one).
            grid = np.linspace(1.0, end.kappa + 1e-6, 2001)
            values = np.array([self._G(k, end.A) for k in grid])
            return not np.any(np.isfinite(values) & (np.sign(values) != np.sign(values[0])))
        A = end.A * (1 + 1e-9 * np.sign(A_in - end.A))
        k_low = restitution.kappa_low(A)
        grid = np.linspace(1.0, max(k_low, 0.0) + 1e-9, 2001)
        values = np.array([self._G(k, A) for k in grid])
        change = np.flatnonzero(
            np.isfinite(values[:-1])
            & np.isfinite(values[1:])
            & (np.sign(values[:-1]) * np.sign(values[1:]) < 0)
        )
        if len(change):
            k = scipy_optimize().brentq(
                lambda kk: self._G(kk, A), grid[change[0] + 1], grid[change[0]], xtol=1e-14
            )
        elif end.kind == END_KINDS[2]:
            return True  # no root left above kappa = 0
        else:
            return bool(
                np.isfinite(self._G(end.kappa, A)) and self._G(end.kappa, A) < 0
            )  # two roots too close to scan
        return bool(np.isfinite(k) and abs(k - end.kappa) < 1e-2)

    def _edge_dip(self, A):
        """(least G, kappa there) over kappa just above the manifold's edge k_low(A), searched in
        log10 of the offset (1e-16 to 1e-3): negative when two roots hug the edge."""
        k_low = restitution.kappa_low(A)

        def g(s):
            value = self._G(k_low + 10.0**s, A)
            return value if np.isfinite(value) else 1.0

        s = np.linspace(-16, -3, 131)
        values = np.array([g(v) for v in s])
        i = int(np.argmin(values))
        res = scipy_optimize().minimize_scalar(
            g,
            bounds=(s[max(i - 1, 0)], s[min(i + 1, len(s) - 1)]),
            method="bounded",
            options={"xatol": 1e-12},
        )
        return min(res.fun, values[i]), k_low + 10.0 ** (res.x if res.fun <= values[i] else s[i])

    def _fold_below_manifold_end(self, A36):
        """The fold of (39) just below the (36) end, when G dips below zero off the edge there;
        located by bisection in A on whether the dip reaches below zero (to rounding)."""
        below = -1e-13  # a dip, not rounding (G is of order one)
        if self._edge_dip(A36)[0] >= below:
            return None
        inside, outside = A36, A36 * (1 - 1e-3)
        if self._edge_dip(outside)[0] < below:
            return None  # no fold this close: not this case
        for _ in range(80):
            mid = 0.5 * (inside + outside)
            if self._edge_dip(mid)[0] < below:
                inside = mid
            else:
                outside = mid
            if inside - outside <= 2 * np.finfo(float).eps * inside:
                break
        return ManifoldEnd(float(inside), float(self._edge_dip(inside)[1]), END_KINDS[1])

    def _manifold_end_kappa(self):
        """kappa at A = A_min(rho(kappa)) on (39) (alpha = alpha_min = 1/(1 + rho^2)), the largest root."""

        def at_end(k):
            r = restitution.rho(k)
            speed = 4.0 / (np.pi * (1.0 + k) * (1.0 + r**2))
            return k**2 - 1.0 + self._delta1 * speed**self._expo

        grid = np.linspace(1.0, 1e-6, 400)
        values = [at_end(k) for k in grid]
        for i in range(len(grid) - 1):
            if np.sign(values[i]) != np.sign(values[i + 1]):
                return float(scipy_optimize().brentq(at_end, grid[i + 1], grid[i], xtol=1e-15))
        return None

    def _fold(self, A, k):
        """Newton on (G, dG/dkappa) = 0 from (k, A); the second derivatives by central differences
        of the generated gradient (the residual is exact, so the root is to rounding)."""
        z = np.array([k, A], dtype=float)
        for _ in range(60):
            gk, gA = self._G_grad(*z)
            F = np.array([self._G(*z), gk])
            h = 1e-7 * max(1.0, abs(z[0]))
            hA = 1e-7 * max(1.0, abs(z[1]))
            gkk = (next(self._G_grad(z[0] + h, z[1])) - next(self._G_grad(z[0] - h, z[1]))) / (2 * h)
            gkA = (next(self._G_grad(z[0], z[1] + hA)) - next(self._G_grad(z[0], z[1] - hA))) / (2 * hA)
            J = np.array([[gk, gA], [gkk, gkA]])
            if not (np.all(np.isfinite(F)) and np.all(np.isfinite(J))):
                return None
            try:
                dz = np.linalg.solve(J, -F)
            except np.linalg.LinAlgError:
                return None
            dz = np.clip(dz, -0.25 * np.maximum(np.abs(z), 1e-3), 0.25 * np.maximum(np.abs(z), 1e-3))
            for _ in range(40):  # backtrack while the step leaves the manifold (where (39) is undefined)
                trial = z + dz
                if (
                    0 < trial[0] <= 1
                    and trial[1] > 0
                    and np.isfinite(self._G(*trial))
                    and np.isfinite(next(self._G_grad(*trial)))
                ):
                    break
                dz = 0.5 * dz
            else:
                return None
            z = trial
            if np.all(np.abs(dz) <= 4 * np.finfo(float).eps * np.maximum(1.0, np.abs(z))):
                break
        if abs(self._G(*z)) > 1e-12 or abs(next(self._G_grad(*z))) > 1e-6:
            return None
        return ManifoldEnd(float(z[1]), float(z[0]), END_KINDS[1])


@functools.lru_cache(maxsize=64)
def _eq39(lam, chi, n, pbar) -> _Eq39:
    # The window depends on the wall alone, and every SlowFlow, regime cell and figure asks for it.
    return _Eq39(lam, chi, n, pbar)


class ManifoldLaw:
    """kappa(A), rho(A), alpha_S+(A) on S+ and the ends of S+, for one parameter set.

    Attributes
    ----------
    newtonian : bool
        pbar == 0: kappa (40) and rho do not depend on A.
    lower, upper : ManifoldEnd or None
        The ends of S+ (``upper`` is None when S+ extends to every large amplitude).
    A_min, A_max : float
        The window of S+: ``lower.A`` and ``upper.A`` (``inf`` without an upper end).
    kappa_at_end : float
        kappa of (39) at the lower end.
    prefix : str
        Of the generated functions this law's slow flow uses (the paper's: none); ``values``,
        ``slopes`` and ``end_values`` give their arguments after A (the corrected law has the same).
    """

    prefix = ""

    def __init__(self, params):
        check_params(params)
        P = self.params = params
        self.newtonian = P.pbar == 0
        self._delta1 = float(restitution.dissipation_at_unit_speed(P.lam, P.chi, P.n, P.pbar))
        self._expo = P.pbar / (P.n + 1)
        if self.newtonian or self._delta1 == 0.0:
            k = float(restitution.kappa_newtonian(P.lam, P.chi, P.n)) if self.newtonian else 1.0
            self._rho0 = float(restitution.rho(k))
            self.lower, self.upper = ManifoldEnd(float(gen.sim_a_min(self._rho0)), k, END_KINDS[0]), None
        else:
            self._rho0 = None
            self._eq = _eq39(P.lam, P.chi, P.n, P.pbar)
            self.lower, self.upper = self._eq.lower, self._eq.upper
        self.A_min = self.lower.A
        self.A_max = self.upper.A if self.upper is not None else math.inf
        self.kappa_at_end = self.lower.kappa

    def kappa(self, A):
        """kappa of (39) on S+ at amplitude(s) A inside the window (NaN outside)."""
        A = np.asarray(A, dtype=float)
        if self._rho0 is not None:
            return np.full_like(A, self.lower.kappa)
        out = np.full(A.shape, np.nan)
        fold = [e for e in (self.lower, self.upper) if e is not None and e.kind == END_KINDS[1]]
        for i, a in np.ndenumerate(A):
            if not self.A_min <= a <= self.A_max:
                continue
            at_end = [
                e
                for e in (self.lower, self.upper)
                if e is not None and abs(a - e.A) <= 4 * np.finfo(float).eps * e.A
            ]
            if at_end:  # exactly on an end, where the root sits on the edge of its bracket
                out[i] = at_end[0].kappa
                continue
            k = self._eq._largest_root(a)
            if not np.isfinite(k) and self.lower.kind == END_KINDS[0]:
                k = self._eq._root_near_manifold_end(a, self.lower.kappa)
            near_fold = [e for e in fold if not np.isfinite(k) or abs(k - e.kappa) < 0.2]
            if near_fold and self._eq._G(near_fold[0].kappa, a) < 0:
                # Two roots close to the fold fall in one cell of the scan: bracket the upper one.
                k = scipy_optimize().brentq(
                    lambda kk: self._eq._G(kk, a), near_fold[0].kappa, 1.0, xtol=1e-15
                )
            out[i] = k
        return out

    # -- what the slow flow asks ----------------------------------------------------------------

    def rho(self, A):
        """rho on S+ at amplitude(s) A, and d rho/dA (zero for pbar = 0)."""
        A = np.asarray(A, dtype=float)
        if self._rho0 is not None:
            return np.full_like(A, self._rho0), np.zeros_like(A)
        k = self.kappa(A)
        if np.any(~np.isfinite(k)):
            bad = A[~np.isfinite(k)]
            raise ValueError(
                f"amplitude A = {bad.ravel()[:3]} lies outside S+, A in [{self.A_min:.10g}, "
                f"{self.A_max:.10g}]: {self.describe()}"
            )
        with np.errstate(divide="ignore", invalid="ignore"):
            g_kappa, g_A = gen.manifold_kappa_residual_grad(k, A, self._delta1, self._expo)
            return restitution.rho(k), _drho_dkappa(k) * (-g_A / g_kappa)

    def alpha(self, A):
        """alpha_S+(A) with rho(A), eq. (36)."""
        return manifold.alpha(A, self.rho(A)[0])

    def values(self, A):
        """(rho,) at A: the arguments of the generated slow-flow functions after A (and psi)."""
        return (self.rho(A)[0],)

    def slopes(self, A):
        """(rho, d rho/dA): the arguments of ``slow_jac`` and ``steady_residual_grad``."""
        return self.rho(A)

    def end_values(self, end: ManifoldEnd):
        """(rho,) at an end of S+ (its kappa is part of the end, and may be 0: a plastic wall)."""
        return (float(restitution.rho_unchecked(end.kappa)),)

    def describe(self) -> str:
        """The window of S+ and what ends it, in one line."""
        upper = (
            self.upper.describe()
            if self.upper is not None
            else f"no upper end (A up to {_SCAN[-1]:g} checked)"
            if self._rho0 is None
            else "no upper end"
        )
        return f"{self.lower.describe()}; {upper}"

    def branches(self, A_max: float, points: int = 300):
        """(A, alpha_S+, alpha_unstable) of (36) with rho(A), for A from A_min to ``A_max`` (at
        most the window's upper end), clustered at the fold where alpha has a square-root
        singularity."""
        top = min(A_max, self.A_max)
        A = self.A_min + (top - self.A_min) * np.linspace(0.0, 1.0, points) ** 2
        rho = self.rho(A)[0]
        return A, manifold.alpha(A, rho, manifold.STABLE), manifold.alpha(A, rho, manifold.UNSTABLE)
