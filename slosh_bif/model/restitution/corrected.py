"""The corrected restitution law on S+: kappa(A) and the clearance D(A) from the measured wall.

The paper's slow flow takes kappa from eq. (21) (first order in the wall's dissipation) and the
wall at |w| = 1. The smooth wall of (9)/(10) returns kappa_wall(v0), and the free flights in and
out of a contact are those of a rigid wall at |w| = D(v0) (:mod:`slosh_bif.model.restitution.wall`: where
the two flights' lines meet, beyond the turning point d(v0) because the particle lingers there;
n = 6, unit speed: d = 1.25, D = 1.39), both functions of the impact speed v0 alone. The
corrected slow flow puts the wall at |w| = D(v0) in (31)-(36) and uses kappa_wall(v0): the
manifold (36) becomes A^2 = (rho alpha)^2 + (D - alpha)^2, A_min = D rho / sqrt(1 + rho^2), and
the impact speed on S+ (38) is v = 4 alpha_S+(A, rho, D) / (pi (1 + kappa)) with kappa, rho and D
taken at v itself: a fixed point in v at every A (the counterpart of eq. (39)), solved by Newton
with the interpolants' slopes. Its derivative gives d rho/dA and dD/dA for the slow flow's
Jacobian. With D = 1 and kappa from (21) it is (39) again (checked in the derivation).

Ends of S+: the manifold's end (36) at the impact speed v_end solving v = 4 D(v) / (pi (1 +
kappa(v)) (1 + rho(v)^2)) (alpha = alpha_min), and the top of the speed range over which the wall
was measured (:data:`V_RANGE`), far above the amplitudes of the paper's figures.
"""

from __future__ import annotations

import bisect
import functools
import math

import numpy as np

from slosh_bif.model._generated import slow_flow as gen
from slosh_bif.model.restitution import eq21 as restitution
from slosh_bif.model.restitution.checks import check_params
from slosh_bif.model.restitution.eq39 import END_KINDS, ManifoldEnd, scipy_optimize
from slosh_bif.model.restitution.wall import WallLaw, wall_law

__all__ = ["CorrectedLaw", "V_RANGE", "TOP_KIND", "measured_wall"]

V_RANGE = (0.05, 100.0)
"""Impact speeds over which the wall is measured: the manifold's end of every preset lies near
0.6 and v grows like A on S+, so A up to ~100 is covered."""
NODES = 32
TOP_KIND = "top of the measured wall law"


@functools.lru_cache(maxsize=32)
def measured_wall(lam, chi, n, pbar) -> WallLaw:
    """The wall's :class:`WallLaw` over :data:`V_RANGE` (one per wall and process)."""
    try:
        return wall_law(lam, chi, n, pbar, *V_RANGE, nodes=NODES)
    except RuntimeError as err:
        raise ValueError(
            "the corrected model needs the wall's restitution at impact speeds "
            f"{V_RANGE[0]:g}-{V_RANGE[1]:g}: {err}"
        ) from None


class CorrectedLaw:
    """kappa(A), rho(A), D(A) on S+ of the corrected slow flow, and the ends of S+.

    The interface of :class:`~slosh_bif.model.restitution.on_manifold.ManifoldLaw` (``lower``, ``upper``,
    ``A_min``, ``A_max``, ``kappa``, ``rho``, ``alpha``, ``describe``, ``branches``) and
    ``clearance``; ``values``/``slopes``/``end_values`` are the arguments the generated
    ``corrected_*`` functions take after A.
    """

    prefix = "corrected_"
    newtonian = False  # D(A) varies even where kappa does not

    def __init__(self, params):
        check_params(params)
        P = params
        self.wall_params = (P.lam, P.chi, P.n, P.pbar)  # all the law depends on
        self.wall = measured_wall(*self.wall_params)
        self.lower = self._lower_end()
        self.upper = self._upper_end()
        self.A_min, self.A_max = self.lower.A, self.upper.A
        self.kappa_at_end = self.lower.kappa
        # A table of v and dv/du against u = sqrt(A - A_min) (v is smooth in u: alpha has a square
        # root at A_min) for Newton's first guess by cubic Hermite interpolation: within ~1e-9 of
        # the root, so that one Newton step and its check finish (five steps from the end's speed).
        self._guess = (np.array([0.0, 1.0]), np.full(2, self.v_end), np.zeros(2))  # for the table's own solve
        u = np.sqrt(self.A_max - self.A_min) * np.linspace(0.0, 1.0, 400) ** 2
        v, dv_dA = self._speed_bracketed(self.A_min + u**2)
        with np.errstate(invalid="ignore"):  # 0 * inf at u = 0, replaced below
            dv_du = 2.0 * u * dv_dA
        dv_du[0] = (v[1] - v[0]) / (u[1] - u[0])  # dv/dA is unbounded at A_min; dv/du is not
        self._guess = (u, v, dv_du)
        self._last = (None, None)
        self._check_single_valued()

    # -- the fixed point in the impact speed ------------------------------------------------------

    def _end_gap(self, v):
        k, dk, d, dd = self.wall.slopes(v, checked=False)
        s, s_k, s_d = gen.corrected_end_speed(k, d)
        return v - s, 1.0 - s_k * dk - s_d * dd

    def _lower_end(self) -> ManifoldEnd:
        v = np.geomspace(*V_RANGE, 400)
        gap = self._end_gap(v)[0]
        change = np.flatnonzero(np.sign(gap[:-1]) != np.sign(gap[1:]))
        if len(change) != 1:
            raise ValueError(
                "the corrected manifold's end: the impact speed v = 4 D(v)/(pi (1 + kappa(v))(1 + "
                f"rho^2)) has {len(change)} solutions in {V_RANGE} (need one); {self._where()}"
            )
        i = change[0]
        v_end = scipy_optimize().brentq(
            lambda x: self._end_gap(x)[0], v[i], v[i + 1], xtol=1e-15, rtol=4 * np.finfo(float).eps
        )
        k, d = float(self.wall.kappa(v_end)), float(self.wall.clearance(v_end))
        self.v_end, self.D_at_end = float(v_end), d
        return ManifoldEnd(float(gen.corrected_a_min(restitution.rho(k), d)), k, END_KINDS[0])

    def _upper_end(self) -> ManifoldEnd:
        v = V_RANGE[1]
        k, d = float(self.wall.kappa(v)), float(self.wall.clearance(v))
        low = float(gen.corrected_a_min(restitution.rho(k), d)) * (
            1 + 1e-12
        )  # the manifold with the top's kappa and D
        top = scipy_optimize().brentq(
            lambda A: gen.corrected_impact_speed(A, k, d)[0] - v, low, 10 * v + 10, xtol=1e-13
        )
        return ManifoldEnd(float(top), k, TOP_KIND)

    def _speed(self, A):
        """(v, dv/dA) at amplitude(s) A inside the window: Newton from the table's guess on the
        manifold (36) with alpha of (38), F(v) = (rho alpha)^2 + (D - alpha)^2 - A^2 = 0 where
        alpha = pi v (1 + kappa) / 4 and kappa, rho, D are the wall's at v. F has no square root:
        near A_min its other root (the unstable branch) is O(sqrt(A - A_min)) away, while Newton on
        v = S(A, v) (S holds (36)'s square root, singular within O(A - A_min) of the root) took four
        steps there and a corrected branch spends many points there. An element that does not
        converge in 6 steps, or lands on the unstable branch, takes the bracketed solve."""
        A = np.asarray(A, dtype=float)
        at_end = A <= self.A_min
        v = np.clip(self._first_guess(np.sqrt(np.maximum(A - self.A_min, 0.0))), self.v_end, V_RANGE[1])
        for _ in range(6):
            F, dF, on_stable = self._manifold_gap(A, v)
            with np.errstate(invalid="ignore", divide="ignore"):
                step = F / dF
            # A step of 1e-9 leaves an error of order 1e-18 times F''/F' (quadratic convergence),
            # and dF at the last iterate is dF at the root to that step: no evaluation after it.
            converged = np.isfinite(step) & (np.abs(step) <= 1e-9 * v)
            v = np.where(np.isfinite(step), np.clip(v - step, self.v_end, V_RANGE[1]), v)
            if np.all(converged | at_end):
                break
        with np.errstate(invalid="ignore", divide="ignore"):
            dv = 2.0 * A / dF
        good = converged & on_stable & np.isfinite(dv)
        if not np.all(good | at_end):
            safe_v, safe_dv = self._speed_bracketed(A)
            v, dv = np.where(good, v, safe_v), np.where(good, dv, safe_dv)
        return np.where(at_end, self.v_end, v), np.where(at_end, np.inf, dv)

    def _speed_one(self, A: float):
        """:meth:`_speed` at one amplitude, in floats (a continuation asks for thousands, one at a
        time, and numpy's per-call cost on 0-d arrays was most of a corrected branch's time)."""
        if A <= self.A_min:
            return self.v_end, math.inf
        v = min(max(float(self._first_guess(math.sqrt(A - self.A_min))), self.v_end), V_RANGE[1])
        for _ in range(6):
            F, dF, on_stable = self._manifold_gap(A, v)
            step = F / dF if dF != 0.0 else math.nan
            if not math.isfinite(step):
                break
            v = min(max(v - step, self.v_end), V_RANGE[1])
            if abs(step) <= 1e-9 * v:
                if on_stable:
                    return v, 2.0 * A / dF
                break
        v, dv = self._speed_bracketed(np.asarray(A))
        return float(v), float(dv)

    def _manifold_gap(self, A, v):
        """F(v) of :meth:`_speed`, dF/dv, and whether alpha lies on S+ (alpha >= D / (1 + rho^2))."""
        k, dk, D, dD = self.wall.slopes(v, checked=False)
        rho = restitution.rho_unchecked(k)
        drho = restitution.drho_dkappa(k) * dk
        alpha = 0.25 * np.pi * v * (1.0 + k)  # (38): v = 4 alpha / (pi (1 + kappa))
        dalpha = 0.25 * np.pi * (1.0 + k + v * dk)
        F = (rho * alpha) ** 2 + (D - alpha) ** 2 - A**2
        dF = 2.0 * rho * alpha * (drho * alpha + rho * dalpha) + 2.0 * (D - alpha) * (dD - dalpha)
        return F, dF, alpha >= D / (1.0 + rho**2) * (1.0 - 1e-12)

    def _speed_bracketed(self, A):
        """(v, dv/dA) at amplitude(s) A inside the window: Newton on g(v) = v - S(A, kappa(v), D(v)),
        kept inside the bracket [v_end, v_max] (g < 0 at v_end for A > A_min; above the root D(v)
        grows until A falls below the manifold's end, where S is undefined: counted as g > 0)."""
        A = np.asarray(A, dtype=float)
        lo, hi = np.full(A.shape, self.v_end), np.full(A.shape, V_RANGE[1])
        v = np.clip(self._first_guess(np.sqrt(np.maximum(A - self.A_min, 0.0))), lo, hi)
        defined = lo.copy()  # the last iterate at which (38) was defined
        for _ in range(100):
            k, dk, d, dd = self.wall.slopes(v, checked=False)
            with np.errstate(invalid="ignore", divide="ignore"):  # dv/dA is unbounded at A_min: not used here
                s, _, s_k, s_d = gen.corrected_impact_speed(A, k, d)
            g = np.where(np.isfinite(s), v - s, np.inf)
            defined = np.where(np.isfinite(s), v, defined)
            lo, hi = np.where(g < 0, v, lo), np.where(g >= 0, v, hi)
            with np.errstate(invalid="ignore"):
                trial = v - g / (1.0 - s_k * dk - s_d * dd)
            newton = np.isfinite(trial) & (trial >= lo) & (trial <= hi)
            # A Newton step of 1e-8 leaves an error of order 1e-16 (quadratic convergence).
            done = newton & (np.abs(trial - v) <= 1e-8 * v)
            v = np.where(newton, trial, 0.5 * (lo + hi))
            if np.all(done):
                break
        # On the end itself v is the end's, and dv/dA infinite (alpha's square root at A_min).
        at_end = A <= self.A_min
        v = np.where(at_end, self.v_end, v)
        k, dk, d, dd = self.wall.slopes(v, checked=False)
        with np.errstate(invalid="ignore", divide="ignore"):
            s, s_A, s_k, s_d = gen.corrected_impact_speed(A, k, d)
        # Within ~1e-9 of A_min the manifold's end moves with v faster than Newton's last step
        # resolves: the final iterate can leave (38)'s domain. The last defined iterate is then
        # the answer (an error of at most that step, 1e-8 relative, where dv/dA is unbounded).
        undefined = ~np.isfinite(s) & ~at_end
        if np.any(undefined):
            v = np.where(undefined, defined, v)
            k, dk, d, dd = self.wall.slopes(v, checked=False)
            with np.errstate(invalid="ignore", divide="ignore"):
                s, s_A, s_k, s_d = gen.corrected_impact_speed(A, k, d)
        with np.errstate(invalid="ignore", divide="ignore"):
            return v, np.where(at_end, np.inf, s_A / (1.0 - s_k * dk - s_d * dd))

    def _first_guess(self, u):
        """v at u = sqrt(A - A_min) from the table, cubic Hermite between its nodes."""
        nodes, v, dv = self._guess
        if isinstance(u, float):  # one amplitude: no array calls
            i = min(max(bisect.bisect_right(nodes, u) - 1, 0), len(nodes) - 2)
            h = nodes[i + 1] - nodes[i]
            t = min(max((u - nodes[i]) / h, 0.0), 1.0)
        else:
            i = np.clip(np.searchsorted(nodes, u) - 1, 0, len(nodes) - 2)
            h = nodes[i + 1] - nodes[i]
            t = np.clip((u - nodes[i]) / h, 0.0, 1.0)
        return (
            (1 + 2 * t) * (1 - t) ** 2 * v[i]
            + t * (1 - t) ** 2 * h * dv[i]
            + t**2 * (3 - 2 * t) * v[i + 1]
            + t**2 * (t - 1) * h * dv[i + 1]
        )

    def _check_single_valued(self):
        """The speed must grow with A along S+ (one fixed point): refuse a wall where it folds."""
        A = self.A_min + (min(self.A_max, 50.0) - self.A_min) * np.linspace(1e-6, 1.0, 200) ** 2
        k, dk, d, dd = self.wall.slopes(self._speed(A)[0])
        with np.errstate(
            invalid="ignore", divide="ignore"
        ):  # s_A's square root at A_min; s_k and s_d are regular
            _, _, s_k, s_d = gen.corrected_impact_speed(A, k, d)
        if np.any(1.0 - s_k * dk - s_d * dd <= 0):
            raise ValueError(
                "the corrected model's impact speed folds on S+ (two fixed points at one "
                f"amplitude): not supported; {self._where()}"
            )

    def _where(self):
        return "wall lam={}, chi={}, n={}, pbar={}".format(*self.wall_params)

    def _at(self, A):
        """(v, dv/dA, kappa, dkappa/dv, D, dD/dv) at A, the last scalar A remembered: a
        continuation step asks for the residual, the Jacobian and d/dparam at the same point."""
        if np.ndim(A) == 0:
            A = float(A)
            if self._last[0] != A:
                v, dv = self._speed_one(float(self._inside(A)))
                self._last = (A, (v, dv) + tuple(self.wall.slopes(v, checked=False)))
            return self._last[1]
        v, dv = self._speed(self._inside(A))
        return (v, dv) + tuple(self.wall.slopes(v, checked=False))  # v lies in [v_end, V_RANGE[1]]

    def _inside(self, A):
        tol = 4 * np.finfo(float).eps
        if isinstance(A, float) and self.A_min * (1 - tol) <= A <= self.A_max * (
            1 + tol
        ):  # the continuation's case, without arrays
            return min(max(A, self.A_min), self.A_max)
        A = np.asarray(A, dtype=float)
        if (
            np.any(~np.isfinite(A))
            or np.any(A < self.A_min * (1 - tol))
            or np.any(A > self.A_max * (1 + tol))
        ):
            raise ValueError(
                f"amplitude A = {A.ravel()[:3]} lies outside S+ of the corrected model, A in "
                f"[{self.A_min:.10g}, {self.A_max:.10g}]: {self.describe()}"
            )
        return np.clip(A, self.A_min, self.A_max)

    # -- what the slow flow asks ------------------------------------------------------------------

    def kappa(self, A):
        """The wall's kappa at the impact speed of amplitude(s) A on S+."""
        return self._at(A)[2]

    def rho(self, A):
        """rho on S+ at amplitude(s) A, and d rho/dA."""
        _, dv, k, dk, _, _ = self._at(A)
        return restitution.rho_unchecked(k), restitution.drho_dkappa(k) * dk * dv

    def clearance(self, A):
        """The clearance D on S+ at amplitude(s) A (the equivalent rigid wall's position), and dD/dA."""
        _, dv, _, _, d, dd = self._at(A)
        return d, dd * dv

    def values(self, A):
        """(rho, D) at A: the arguments of the generated ``corrected_*`` functions after A (and psi)."""
        return self.rho(A)[0], self._at(A)[4]

    def slopes(self, A):
        """(rho, drho/dA, D, dD/dA): the arguments of ``corrected_slow_jac`` and ``..._grad``."""
        return self.rho(A) + self.clearance(A)

    def end_values(self, end: ManifoldEnd):
        """(rho, D) at an end of S+ (the lower end's from its own speed, not from a solve)."""
        if end is self.lower:
            return float(restitution.rho(end.kappa)), self.D_at_end
        return tuple(float(x) for x in self.values(end.A))

    def alpha(self, A, branch: int = +1):
        """alpha on S+ (or, ``branch=-1``, the unstable branch) with rho(A), D(A)."""
        rho, d = self.values(A)
        fn = gen.corrected_alpha if branch == +1 else gen.corrected_alpha_unstable
        disc = (1 + rho**2) * np.asarray(A, dtype=float) ** 2 - (rho * d) ** 2
        with np.errstate(invalid="ignore"):
            return np.where(disc <= 8 * np.finfo(float).eps * d**2, d / (1 + rho**2), fn(A, rho, d))

    def describe(self) -> str:
        w = self.wall
        return (
            f"{self.lower.describe()} (impact speed {self.v_end:.6g}, clearance D = {self.D_at_end:.6g}); "
            f"{self.upper.describe()} (v0 = {V_RANGE[1]:g}); wall measured to {w.kappa_error:.1e} "
            f"in kappa, {w.clearance_error:.1e} in D"
        )

    def branches(self, A_max: float, points: int = 300):
        """(A, alpha_S+, alpha_unstable) of the corrected manifold from A_min to ``A_max``."""
        top = min(A_max, self.A_max)
        A = self.A_min + (top - self.A_min) * np.linspace(0.0, 1.0, points) ** 2
        return A, self.alpha(A), self.alpha(A, -1)
