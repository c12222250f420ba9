"""The minimally augmented system on the multiple-shooting residual of (9) (or on the
stroboscopic map of (8), :mod:`slosh_bif.orbits.impact.strobe`), the base of every curve of orbit
bifurcations in two parameters.

Formulation
-----------
The orbit is a zero of the multiple-shooting residual F(x; p1, p2) (:class:`ShootingProblem`).
The monodromy matrix M has the multiplier ``mu`` (+1 at a fold, -1 at a period doubling) exactly
when the block-cyclic matrix J_mu (the arc matrices Phi_k on the diagonal, -I beside them and
``-mu I`` in the block that closes the period) is singular. With bordering vectors b, c, the
scalar g(x; p1, p2) defined by

    [[J_mu, b], [c^T, 0]] [v; g] = [0; 1]

vanishes exactly there, and the augmented system [F; g] = 0 in (x, p2), continued in p1 by the
same pseudo-arclength engine, traces the curve. Its derivatives need second derivatives of the
flow only along v: with w from the transposed system, dg/dz = -w^T d(J_mu v)/dz, and
d(J_mu v)/dz . e = d/de [F_z(z + e v)]^T w: the arcs' derivatives along v, from the second-order
variational equations of (9) replayed on the steps the arcs were integrated with
(:meth:`~slosh_bif.orbits.shooting.ShootingProblem.arcs_along`; v is known only once the arcs
are), so that a Newton iteration costs the arcs and 28 more components where central
differences from x +- h v cost two more integrations of the arcs (and carry their rounding,
rtol / h); for the stroboscopic map of (8), central differences of its exact Jacobian. The system
stays of size 4m + 1 (AUTO's and MatCont's standard extended systems would double it). The
bordering vectors are renewed from v and w after every accepted point, as
BifurcationKit's MinAug problems do, so that the bordered matrix stays regular along the curve.

The kinds of curve (fold, flip, pitchfork: :mod:`.multiplier_curves`; Neimark-Sacker:
:mod:`.torus`) share this base and its one bordered solver (:meth:`MinAugCurveProblem._bordered`),
as BifurcationKit's MinAug problems do, and add their own codimension-2 test functions.
"""

from __future__ import annotations

import copy

import numpy as np

from slosh_bif.model.params import Params, real_pair
from slosh_bif.orbits.floquet import floquet_multipliers
from slosh_bif.orbits.shooting import ShootingProblem

__all__ = ["MinAugCurveProblem", "orthonormal"]


class MinAugCurveProblem:
    """The minimally augmented base of every curve of orbit bifurcations of (9): points (x, p2)
    at p1 where the orbit through x has the critical multiplier ``mu`` of its kind.

    A continuation problem in p1 (the engine's parameter); ``p2`` is the last state component.
    ``orbits``: the orbit equations, by default the multiple shooting of (9) built from
    ``segments``, ``period_multiple``, the tolerances, ``box`` and ``backend``; or another object
    with the same interface (names, ``arcs(x, params)`` with ends, arc matrices and the
    derivatives in (p1, p2), ``residual_of``, ``jacobian_of``, ``in_domain``; e.g. the
    stroboscopic map of (8), :class:`~slosh_bif.orbits.impact.strobe.ImpactStrobe`).
    ``p2_box`` bounds p2 (points outside are never evaluated); ``box`` bounds p1's corrector
    iterates as in :class:`ShootingProblem`. ``refresh_borders``: renew the bordering vectors
    from the null vectors at each accepted point (the default; without it they stay those of the
    start, which is cheaper per point but lets the bordered matrix grow ill-conditioned along a
    long curve). A kind (:mod:`.multiplier_curves`,
    :mod:`.torus`) sets ``kind``, ``mu``, ``symmetric`` (on the half-period map), and its
    codimension-2 tests: ``test_kinds``, ``test_functions`` and ``confirm``.
    """

    kind = ""
    mu = 1.0
    symmetric = False
    test_kinds: tuple = ()

    def __init__(
        self,
        params: Params,
        p1: str = "sigma",
        p2: str = "Abar",
        *,
        segments: int = 4,
        period_multiple: int = 1,
        rtol: float = 1e-10,
        atol: float = 1e-12,
        box: tuple | None = None,
        p2_box: tuple | None = None,
        backend: str = "auto",
        refresh_borders: bool = True,
        orbits=None,
    ):
        real_pair((p1, p2))
        self.refresh_borders = bool(refresh_borders)
        self.params, self.p1, self.p2 = params, p1, p2
        if orbits is None:  # multiple shooting of (9)
            orbits = ShootingProblem(
                params,
                p1,
                segments=segments,
                period_multiple=period_multiple,
                rtol=rtol,
                atol=atol,
                backend=backend,
                box=box,
                symmetric=self.symmetric,
                sensitivities=(p1, p2),
            )
        elif orbits.symmetric != self.symmetric or orbits.sensitivities != (p1, p2):
            raise ValueError(
                f"the orbit equations must be {'symmetric' if self.symmetric else 'whole-period'} "
                f"ones with derivatives in ({p1}, {p2})"
            )
        self.orbits = orbits
        if hasattr(orbits, "record_steps"):  # g's derivatives replay on every evaluation's steps
            orbits.record_steps()
        self.names = self.orbits.names + (p2,)
        self.branch_kind = f"{self.kind} curve of {orbits.branch_kind} in ({p1}, {p2})"
        self.p2_box = p2_box
        self._columns = (0, 1)  # the arcs' sensitivities are (p1, p2)
        self._b = self._c = None
        self._edge = None  # set by a kind's own domain check (a named edge)
        self._memo = {}
        self._last_second = None  # (u, the derivatives there) of the last computation
        self._multipliers = {}
        self._at = None  # ((p1, p2), the parameter set there) last asked for
        self._last_rows = None  # ((x, p), [F_x, F_p]) last computed, with the same borders

    # -- the augmented system ----------------------------------------------------------------

    _extra = 1  # unknowns after the orbit's states: p2 (the NS problem adds kappa)

    def params_at(self, x, p) -> Params:
        key = (float(p), float(x[-self._extra]))
        if self._at is None or self._at[0] != key:  # a point asks for its set ~10 times
            self._at = (key, self.params.replace(**{self.p1: key[0], self.p2: key[1]}))
        return self._at[1]

    def edge_name_at(self, x, p) -> str:
        """The edge that failed steps from the curve point (x, p) ran into: the kind's own (set by
        its domain check), else the orbit equations' (grazing or the section for (8)), else the box."""
        if self._edge:
            return self._edge
        near = getattr(self.orbits, "edge_name_at", None)
        return (near(x[: -self._extra], self.params_at(x, p)) if near else None) or "boundary"

    def edge_distance(self, x, p) -> float:
        """How near the curve point is to an end of ``p2_box`` (relative to its width) or to an
        edge of the orbits' own domain (for (8): the section, grazing): a corrector failing within
        1e-5 of one has met it (its solution lies just beyond), which is no stall."""
        distance = np.inf
        if self.p2_box is not None:
            lo, hi = self.p2_box
            p2 = float(x[-self._extra])
            distance = min(p2 - lo, hi - p2) / (hi - lo)
        near = getattr(self.orbits, "edge_distance_at", None)
        if near is not None:
            distance = min(distance, near(x[: -self._extra], self.params_at(x, p)))
        return distance

    def in_domain(self, x, p) -> bool:
        self._edge = None
        p2 = x[-self._extra]
        if self.p2_box is not None and not self.p2_box[0] <= p2 <= self.p2_box[1]:
            return False
        try:
            self.params_at(x, p)
        except ValueError:  # no parameter set (Abar < 0, eps <= 0, an imaginary restitution, ...)
            return False
        return self.orbits.in_domain(x[: -self._extra], p)

    def _matrix_at(self, x, p):
        """(arcs, J_mu) at (x, p); the NS problem makes J complex."""
        arcs = self.orbits.arcs(x[:-1], self.params_at(x, p))
        return arcs, self.orbits.jacobian_of(arcs, self.mu)

    _borders = 1  # bordering vectors (columns of b and c): 2 for the NS problem's real pair

    def init_borders(self, x, p):
        """b and c from the singular vectors of J_mu at (x, p): the directions g is read along."""
        U, _, Vh = np.linalg.svd(self._matrix_at(x, p)[1])
        k = self._borders
        self._b, self._c = U[:, -k:].copy(), Vh[-k:].conj().T.copy()
        self._memo.clear()
        self._last_second = self._last_rows = None

    def accept(self, x, p):
        """Renew the borders from the null vectors at an accepted point (keeps the bordered matrix
        regular)."""
        if not self.refresh_borders:
            return
        _, V, W, _ = self._bordered(x, p)
        self._b, self._c = orthonormal(W), orthonormal(V)
        self._memo.clear()
        self._last_second = self._last_rows = None

    def _bordered(self, x, p):
        """(arcs, V, W, G) of the bordered system at (x, p), one linear solver for every curve kind:

            [[J, b], [c^H, 0]] [V; G] = [0; I],    [[J, b], [c^H, 0]]^H [W; H] = [0; I]

        with k bordering columns (V, W: N x k; G: k x k). G vanishes where J has a k-dimensional
        null space, and dG = -W^H dJ V."""
        key = (x.tobytes(), float(p))
        hit = self._memo.get(key)
        if hit is not None:
            return hit
        if self._b is None:
            self.init_borders(x, p)
        arcs, J = self._matrix_at(x, p)
        n, k = len(J), self._borders
        B = np.zeros((n + k, n + k), dtype=np.result_type(J, self._b))
        B[:n, :n], B[:n, n:], B[n:, :n] = J, self._b, self._c.conj().T
        rhs = np.zeros((n + k, k), dtype=B.dtype)
        rhs[n:] = np.eye(k)
        try:
            VG = np.linalg.solve(B, rhs)
            WH = np.linalg.solve(B.conj().T, rhs)
        except (
            np.linalg.LinAlgError
        ):  # a failed evaluation (NaN arcs) or an exactly singular border: the corrector cuts its step
            VG = WH = np.full((n + k, k), np.nan, dtype=B.dtype)
        result = (arcs, VG[:n], WH[:n], VG[n:])
        if len(self._memo) > 8:
            self._memo.clear()
            self._last_rows = None  # built from what the memo held
        self._memo[key] = result
        return result

    def _solve(self, x, p):
        """(arcs, v, w, g) of the one-border system."""
        arcs, V, W, G = self._bordered(x, p)
        return arcs, V[:, 0], W[:, 0], G[0, 0]

    def _second(self, x, p):
        """(dg/d(x, p1, p2), w^T F_xx[v, v]) from the arcs at x +- h v (see :meth:`_along`).

        Reused at a point within ``NEAR`` of the last one computed (with the same borders): the
        corrector's last update is that small, and the converged point's tangent and tests
        then need no new integrations (a fifth of a curve's cost); the row changes by the
        update times g's second derivatives, far below the differences' own error."""
        key = ("second", x.tobytes(), float(p))
        if key not in self._memo:
            u, last = np.append(x, p), self._last_second
            if last is not None and np.linalg.norm(u - last[0]) <= self.NEAR * (1 + np.linalg.norm(u)):
                self._memo[key] = last[1]
            else:
                self._memo[key] = self._second_uncached(x, p)
                self._last_second = (u, self._memo[key])
        return self._memo[key]

    NEAR = 1e-7

    def _along(self, y, P, direction):
        """(d J / d e, d F_p / d e) at the orbit states y + e ``direction``, e = 0.

        Exact where the orbit equations give the arcs' derivatives along a direction
        (``arcs_along``: the second-order variational equations of (9)). Otherwise (the
        stroboscopic map of (8)) central differences: the flow's third derivatives can be large
        (the wall's force of (9) grows like |w|^n, with errors of order 0.1 % in g's row from
        forward differences at n = 50, where Newton would creep); the step balances the O(h^2)
        truncation with the integration's rounding (rtol ~1e-10)."""
        size = np.linalg.norm(direction)
        if size == 0:
            return 0.0, 0.0
        if hasattr(self.orbits, "arcs_along"):
            _, Psi, R = self.orbits.arcs_along(y, P, direction)
            m = len(Psi)
            dJ = np.zeros((4 * m, 4 * m))
            blocks = dJ.reshape(m, 4, m, 4)  # the diagonal: the -I, -mu I blocks are constant
            blocks[np.arange(m), :, np.arange(m), :] = Psi
            return dJ, R.reshape(len(y), -1)
        h = 1e-6 * (1 + np.linalg.norm(y)) / size
        ahead, behind = self.orbits.arcs(y + h * direction, P), self.orbits.arcs(y - h * direction, P)
        dJ = (self.orbits.jacobian_of(ahead) - self.orbits.jacobian_of(behind)) / (2 * h)
        dS = (ahead.sens - behind.sens).reshape(len(y), -1) / (2 * h)
        return dJ, dS

    def _second_uncached(self, x, p):
        _, v, w, _ = self._solve(x, p)
        dJ, dS = self._along(x[:-1], self.params_at(x, p), v)
        g_x = -(dJ.T @ w)
        g_p1 = -(dS[:, self._columns[0]] @ w)
        g_p2 = -(dS[:, self._columns[1]] @ w)
        return g_x, g_p1, g_p2, float(w @ dJ @ v)

    def residual(self, x, p):
        arcs, _, _, g = self._solve(x, p)
        return np.append(self.orbits.residual_of(x[:-1], arcs), g)

    def _g_row(self, second):
        """g's derivatives (see :meth:`_second`) as a row over (x, p2, p1)."""
        g_x, g_p1, g_p2 = second[:3]
        return np.concatenate([g_x, [g_p2, g_p1]])

    def _rows(self, x, p, g_row):
        """[F_x, F_p] of the augmented system with g's row ``g_row``."""
        arcs = self._solve(x, p)[0]
        n = len(x) - self._extra
        sens = arcs.sens.reshape(n, -1)
        top = np.column_stack(
            [
                self.orbits.jacobian_of(arcs),
                sens[:, self._columns[1]],
                np.zeros((n, self._extra - 1)),
                sens[:, self._columns[0]],
            ]
        )
        return np.vstack([top, g_row.real, g_row.imag]) if np.iscomplexobj(g_row) else np.vstack([top, g_row])

    def _full_rows(self, x, p):
        """[F_x, F_p] at (x, p), kept: the corrector asks for both parts at each iterate."""
        key = (x.tobytes(), float(p))
        if self._last_rows is None or self._last_rows[0] != key:
            self._last_rows = (key, self._rows(x, p, self._g_row(self._second(x, p))))
        return self._last_rows[1]

    def jacobian(self, x, p):
        return self._full_rows(x, p)[:, :-1]

    def dparam(self, x, p):
        return self._full_rows(x, p)[:, -1]

    # -- precision -------------------------------------------------------------------------------

    FINEST_RTOL = 1e-12  # the arcs' tolerance below which no finer problem is offered

    def refined(self):
        """This curve with the arcs integrated 100 times more tightly (rtol down to
        ``FINEST_RTOL``), its borders kept; None when it is there already. The engine resumes a
        stalled direction with it: the arcs' own error can hide a nearly singular but regular
        stretch of the curve (g's derivatives by central differences, whose rounding is rtol / h,
        need it past the cusps of the Fig. 10 and Fig. 13 fold curves of asymmetric orbits; the
        exact ones do not)."""
        s = self.orbits
        if not isinstance(s, ShootingProblem) or s.rtol <= self.FINEST_RTOL:  # an exact map has nothing finer
            return None
        factor = max(self.FINEST_RTOL / s.rtol, 1e-2)
        finer = copy.copy(self)
        finer.orbits = ShootingProblem(
            s.params,
            s.param,
            segments=s.segments,
            period_multiple=s.period_multiple,
            rtol=s.rtol * factor,
            atol=s.atol * factor,
            backend=s.backend,
            box=s.box,
            symmetric=s.symmetric,
            sensitivities=s.sensitivities,
        )
        finer._memo, finer._last_second, finer._multipliers = {}, None, {}
        finer._last_rows = None
        finer.orbits.record_steps()
        return finer

    def diagnostics(self, x, p) -> dict:
        """The arcs' relative tolerance at the point (tighter where a stall was resumed); 0 for an exact
        map."""
        return {"rtol": getattr(self.orbits, "rtol", 0.0)}

    # -- multipliers and codimension-2 tests --------------------------------------------------

    def multipliers(self, x, p):
        """The Floquet multipliers of the orbit at the curve point (x, p), kept for the last few
        points asked (the tests and the engine's stability ask at the same point)."""
        key = (x.tobytes(), float(p))
        if key not in self._multipliers:
            if len(self._multipliers) > 8:
                self._multipliers.clear()
            arcs = self._solve(x, p)[0]
            finite = np.all(np.isfinite(arcs.monodromy))
            self._multipliers[key] = floquet_multipliers(arcs.mats) if finite else np.full(4, np.nan + 0j)
        return self._multipliers[key]

    def eigenvalues(self, x, p):
        """The Floquet multipliers of the orbit, the critical one (nearest mu) first."""
        mu = self.multipliers(x, p)
        order = np.argsort(np.abs(mu - self.mu))
        return mu[order]

    @staticmethod
    def is_stable(multipliers) -> bool:
        """The curve point bounds stable orbits: every multiplier but the critical one inside the unit
        circle."""
        return bool(np.all(np.abs(multipliers[1:]) < 1))

    def other_multipliers(self, x, p):
        """The multipliers but the critical one, and the NS test of their pairs."""
        others = self.eigenvalues(x, p)[1:]
        return others, np.prod([others[i] * others[j] - 1 for i in range(3) for j in range(i + 1, 3)]).real


def orthonormal(A):
    """An orthonormal basis of A's columns that keeps their orientation (Q R with R's diagonal
    positive; one column: a / |a|): a border whose sign flipped from one point to the next would
    flip the sign of the fold's quadratic coefficient and report a cusp at every flip."""
    Q, R = np.linalg.qr(A)
    signs = np.sign(np.diag(R).real)
    signs[signs == 0] = 1.0
    return Q * signs
