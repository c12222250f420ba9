"""Eq. (39) on the stable branch S+ of the manifold (36): G(kappa, A) = kappa^2 - 1 + delta(v(kappa, A)) = 0,
its root reached continuously from the elastic limit, and where that root ends (the manifold's end
(36), a fold of (39), kappa reaching 0), each located from its own equations."""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

from slosh_bif.model._generated import slow_flow as gen
from slosh_bif.model.restitution import eq21 as restitution
from slosh_bif.newton import NewtonSettings, newton_loop

__all__ = ["END_KINDS", "SCAN", "Eq39", "ManifoldEnd", "eq39_for", "scipy_optimize"]


END_KINDS = ("manifold end (36)", "fold of (39)", "kappa reaches 0")


SCAN = np.geomspace(1e-4, 1e4, 801)  # amplitudes scanned for the window (refined at its ends)


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


class Eq39:
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
        return restitution.largest_root(float(A), self._delta1, self._expo)

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
        continuously, each located from its own equations (the scan's roots to 1e-10, those at
        the run's ends to the last digit)."""
        roots = restitution.largest_roots(SCAN, self._delta1, self._expo)
        ok = np.isfinite(roots)
        # A jump of the largest root between neighbours is a fold passed over: the run ends there.
        jump = np.abs(np.diff(roots)) > 0.2
        runs, start = [], None
        for i in range(len(SCAN)):
            if ok[i] and start is None:
                start = i
            if start is not None and (i == len(SCAN) - 1 or not ok[i + 1] or jump[i]):
                runs.append((start, i))
                start = None
        if not runs:
            raise ValueError(
                "no restitution coefficient in (0, 1] solves eq. (39) for any amplitude A in "
                f"[1e-4, 1e4] ({self.where})"
            )
        lo, hi = max(runs, key=lambda r: r[1] - r[0])
        roots[lo], roots[hi] = self._largest_root(SCAN[lo]), self._largest_root(SCAN[hi])
        lower = self._end(SCAN[lo], roots[lo], SCAN[lo - 1] if lo > 0 else 0.0)
        upper = self._end(SCAN[hi], roots[hi], SCAN[hi + 1]) if hi < len(SCAN) - 1 else None
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
        of the generated gradient (the residual is exact, so the root is to rounding). Each step
        is bounded to a quarter of the point's size and halved while it leaves the manifold (where
        (39) is undefined)."""

        def residual(z):
            return np.array([self._G(*z), next(self._G_grad(*z))])

        def jacobian(z):
            gk, gA = self._G_grad(*z)
            h, hA = 1e-7 * max(1.0, abs(z[0])), 1e-7 * max(1.0, abs(z[1]))
            gkk = (next(self._G_grad(z[0] + h, z[1])) - next(self._G_grad(z[0] - h, z[1]))) / (2 * h)
            gkA = (next(self._G_grad(z[0], z[1] + hA)) - next(self._G_grad(z[0], z[1] - hA))) / (2 * hA)
            return np.array([[gk, gA], [gkk, gkA]])

        def admissible(z):
            return 0 < z[0] <= 1 and z[1] > 0 and np.all(np.isfinite(residual(z)))

        def bounded(z, dz):
            room = 0.25 * np.maximum(np.abs(z), 1e-3)
            return np.clip(dz, -room, room)

        run = newton_loop(
            residual,
            jacobian,
            np.array([k, A], dtype=float),
            NewtonSettings(tol=4 * np.finfo(float).eps, max_iter=60, halvings=40),
            admissible=admissible,
            bound_step=bounded,
        )
        z = run.x
        if not (run.converged or (admissible(z) and run.iterations == 60)):
            return None
        if abs(self._G(*z)) > 1e-12 or abs(next(self._G_grad(*z))) > 1e-6:
            return None
        return ManifoldEnd(float(z[1]), float(z[0]), END_KINDS[1])


@functools.lru_cache(maxsize=64)
def eq39_for(lam, chi, n, pbar) -> Eq39:
    # The window depends on the wall alone, and every SlowFlow, regime cell and figure asks for it.
    return Eq39(lam, chi, n, pbar)
