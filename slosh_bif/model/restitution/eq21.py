"""Velocity-dependent restitution coefficient of the high-power wall, eqs. (13)-(21), (31), (38)-(40).

A particle of unit mass in the wall potential and dissipation of eq. (10) (``R = 1``),

    x'' + chi * x**(2n+1) + lam * x' * x**(2p) = 0,    pbar = 2p - n,

enters the wall at ``x = 0`` with speed ``v0`` and leaves it with speed ``kappa * v0``. To first
order in the dissipation (the conservative path (16) under the integral (15)) the energy lost is

    1 - kappa**2 = delta(v0) = 4 lam ((n+1)/chi)**(pbar/(2(n+1)) + 1/2) I(n, pbar) v0**(pbar/(n+1)),   (21)

with ``I(n, pbar) = sqrt(pi) Gamma(a) / (4 (n+1) Gamma(a + 3/2))``, ``a = pbar/(2(n+1)) + 1/2`` (19):
the Beta-function value of the integral (18). At ``pbar = 0`` this is the Newtonian,
velocity-independent ``kappa = sqrt(1 - pi lam / sqrt(chi (n+1)))`` (40).

Notes
-----
Eq. (21) is a small-dissipation approximation and it always *under*-estimates kappa (the real
particle loses speed on the way in, so it dissipates less on the way out). Against the direct
simulation :func:`simulate_rebound`, the error is second order in ``delta``:
``kappa_sim - kappa_21 ~ (q/8) delta**2`` with ``q = 2 + pbar/(n+1)`` (the speed exponent of the
dissipated energy (18)); in the Newtonian case that is ``delta**2/4 = pi**2 lam**2 / (4 chi (n+1))``:
quadratic in ``lam`` and inversely proportional to ``n + 1``. The tests check that law. It is not
small at the paper's n = 6 sets (Figs. 11, 12: lam = 0.35, chi = 0.2): eq. (21) gives kappa = 0.266
where the wall of eq. (10) gives 0.625.

On the manifold the impact speed is ``alpha (2/pi + rho) = 4 alpha / (pi (1 + kappa))`` (38), which
makes kappa depend on the amplitude A through ``alpha(A, rho(kappa))``: eq. (39) is implicit in
kappa and :func:`kappa_on_manifold` solves it by bracketing. (The paper says (38) is substituted
"into (23)"; it is into (21).)
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from slosh_bif.model import manifold

# log Gamma of (19) by math.lgamma, not scipy.special.gammaln: importing scipy.special cost every
# command ~0.2 s of start-up; the arguments are positive and few.
_lgamma = np.vectorize(math.lgamma, otypes=[float])

__all__ = [
    "I",
    "dissipation_at_unit_speed",
    "kappa",
    "kappa_newtonian",
    "rho",
    "drho_dkappa",
    "kappa_on_manifold",
    "largest_root",
    "largest_roots",
    "kappa_low",
    "ManifoldKappa",
    "simulate_rebound",
    "Eq21Law",
]


def I(n, pbar):  # noqa: E743 - the paper's name
    """Closed form (19) of the integral (18), ``int_0^1 z**(2p) sqrt(1 - z**(2(n+1))) dz``.

    Valid for ``pbar > -(n+1)`` (checked); vectorised over ``n`` and ``pbar``.
    """
    if np.ndim(n) == 0 and np.ndim(pbar) == 0 and pbar > -(n + 1):  # the common case, without vectorize
        a = pbar / (2 * (n + 1)) + 0.5
        return math.sqrt(math.pi) * math.exp(math.lgamma(a) - math.lgamma(a + 1.5)) / (4 * (n + 1))
    n = np.asarray(n, dtype=float)
    pbar = np.asarray(pbar, dtype=float)
    if np.any(pbar <= -(n + 1)):
        raise ValueError(f"I(n, pbar) needs pbar > -(n+1); got n={n}, pbar={pbar}")
    a = pbar / (2 * (n + 1)) + 0.5
    return np.sqrt(np.pi) * np.exp(_lgamma(a) - _lgamma(a + 1.5)) / (4 * (n + 1))


def dissipation_at_unit_speed(lam, chi, n, pbar):
    """``delta(1) = 1 - kappa(1)**2`` of eq. (21): the energy fraction lost in one impact at v0 = 1."""
    exponent = pbar / (2 * (n + 1)) + 0.5
    return 4.0 * lam * ((n + 1) / chi) ** exponent * I(n, pbar)


def kappa(v0, lam, chi, n, pbar):
    """Restitution coefficient of eq. (21) at impact speed(s) ``v0`` (vectorised).

    Raises ``ValueError`` when some ``v0`` is not positive and finite, or when kappa is not real
    there (the first-order dissipation exceeds the kinetic energy).
    """
    v0 = np.asarray(v0, dtype=float)
    if np.any(~np.isfinite(v0)) or np.any(v0 <= 0):
        raise ValueError(f"impact speed v0 must be positive and finite; got {v0}")
    delta = dissipation_at_unit_speed(lam, chi, n, pbar) * v0 ** (pbar / (n + 1))
    if np.any(delta > 1.0):
        bad = np.broadcast_to(v0, delta.shape)[delta > 1.0]
        raise ValueError(
            f"kappa (eq. 21) is not real for impact speed v0 in [{bad.min():.6g}, {bad.max():.6g}] "
            f"with lam={lam}, chi={chi}, n={n}, pbar={pbar}"
        )
    return np.sqrt(1.0 - delta)


def kappa_newtonian(lam, chi, n):
    """Velocity-independent restitution coefficient of the Newtonian case pbar = 0, eq. (40)."""
    kappa_sq = 1.0 - np.pi * lam / np.sqrt(chi * (n + 1))
    if np.any(kappa_sq < 0):
        raise ValueError(f"Newtonian kappa (eq. 40) is not real for lam={lam}, chi={chi}, n={n}")
    return np.sqrt(kappa_sq)


def rho(kappa_value):
    """Impact parameter ``rho = 2 (1 - kappa) / (pi (1 + kappa))`` of eq. (31)."""
    k = np.asarray(kappa_value, dtype=float)
    if np.any(~(k > 0)) or np.any(k > 1):
        raise ValueError(f"kappa must be in (0, 1]; got {k}")
    return rho_unchecked(k)


def drho_dkappa(k):
    """d rho / d kappa of (31)."""
    return -4.0 / (np.pi * (1.0 + k) ** 2)


def rho_unchecked(k):
    """:func:`rho` without its input check, for callers whose kappa is in [0, 1] by construction
    and that ask thousands of times a branch (the check costs 60 us a call); floats stay floats."""
    return 2.0 * (1.0 - k) / (np.pi * (1.0 + k))


def _kappa_from_rho(r):
    """Inverse of :func:`rho`."""
    return (2.0 - np.pi * r) / (2.0 + np.pi * r)


def kappa_low(A) -> float:
    """The smallest kappa at which amplitude A lies on the manifold, A >= A_min(rho(kappa)) (36):
    rho falls as kappa grows, so the manifold at A needs kappa >= this (0 for A >= 1)."""
    return float(_kappa_from_rho(A / np.sqrt(1 - A**2))) if A < 1 else 0.0


@dataclasses.dataclass(frozen=True)
class ManifoldKappa:
    """kappa(A) on the stable manifold branch, eq. (39), with where it exists.

    Arrays share the shape of ``A``; where ``exists`` is False, kappa, rho and alpha are NaN.
    """

    A: np.ndarray
    kappa: np.ndarray
    rho: np.ndarray
    alpha: np.ndarray
    exists: np.ndarray


def _manifold_residual(k, A, delta1, exponent):
    """kappa**2 - (1 - delta(v_impact)) with the impact speed (38) on S+ at amplitude A."""
    r = rho(k)
    speed = 4.0 * manifold.alpha(A, r) / (np.pi * (1.0 + k))
    return k**2 - 1.0 + delta1 * speed**exponent


_FOLD_ULPS = 8 * np.finfo(float).eps  # manifold.alpha's allowance for rounding at the fold


def _manifold_residual_at(k, A, delta1, exponent):
    """:func:`_manifold_residual` for one float kappa, in floats (rho (31), alpha_S+ (36) with its
    fold, the speed (38)): brentq calls it about eight times a root, 1 us a call against 60."""
    r = 2.0 * (1.0 - k) / (math.pi * (1.0 + k))
    r2 = r * r
    disc = (1.0 + r2) * (A * A) - r2
    tiny = _FOLD_ULPS * max(1.0, r2)
    if not disc >= -tiny:
        raise ValueError(f"amplitude A must be >= A_min = rho/sqrt(1+rho**2) on the manifold; got A = {A}")
    if disc <= tiny:  # at the fold, where rounding may put the root's argument below zero
        alpha = 1.0 / (1.0 + r2)
    else:
        x1 = r2 + 1.0
        x2 = 1.0 / x1
        alpha = x2 * (math.sqrt(x1) * math.sqrt(A * A - r2 * x2) + 1.0)
    speed = 4.0 * alpha / (math.pi * (1.0 + k))
    return k * k - 1.0 + delta1 * speed**exponent


def _scan_grid(k_low):
    """The kappas the scan for (39)'s largest root tries, from 1 down to just above ``k_low``: the
    manifold needs A >= A_min(rho(kappa)), and rho falls as kappa grows, so kappa >= k_low(A). 65
    of them; one column per entry of an array ``k_low``."""
    k_low = np.clip(k_low, 0.0, 1.0)
    grid = np.linspace(1.0, k_low, 65)[:-1]
    return np.concatenate([grid, [k_low + (grid[-1] - k_low) * 1e-9]])


def _solve_manifold_kappa(A, delta1, exponent, xtol):
    """Largest root in (0, 1] of the scalar residual, or NaN when none exists."""
    if delta1 == 0.0:
        return 1.0 if A >= 0 else np.nan
    grid = _scan_grid(kappa_low(A))
    grid = grid[grid > 0]
    # Scanning down from kappa = 1 (where the residual is > 0) picks the root nearest the elastic
    # limit: the one reached continuously from small dissipation. Point by point, in floats: the
    # root is most often in the first cells.
    A = float(A)
    previous = _manifold_residual_at(float(grid[0]), A, delta1, exponent)
    if previous == 0.0:
        return grid[0]
    for i in range(len(grid) - 1):
        value = _manifold_residual_at(float(grid[i + 1]), A, delta1, exponent)
        if value == 0.0:
            return grid[i + 1]
        if np.sign(value) != np.sign(previous):
            break
        previous = value
    else:
        return np.nan
    from scipy.optimize import brentq

    return brentq(_manifold_residual_at, grid[i + 1], grid[i], args=(A, delta1, exponent), xtol=xtol)


def largest_root(A: float, delta1: float, exponent: float, *, xtol=1e-14) -> float:
    """kappa of (39) on S+ at one amplitude A, from the wall's ``delta1`` (the dissipation at unit
    speed) and ``exponent`` pbar / (n + 1), or NaN: :func:`kappa_on_manifold`'s kappa without its
    checks and its rho and alpha (a slow flow at pbar != 0 asks for it at every amplitude)."""
    return float(_solve_manifold_kappa(A, delta1, exponent, xtol))


def largest_roots(A, delta1, exponent, *, xtol=1e-10) -> np.ndarray:
    """The root of :func:`_solve_manifold_kappa` at every amplitude of the 1-d array ``A`` at
    once (NaN where none), to ``xtol`` by bisection in the same first bracket of the same scan down
    from kappa = 1: for callers that need where the root exists and roughly where (the window of
    S+ scans 801 amplitudes, 1 s one root at a time), not its last digits."""
    A = np.asarray(A, dtype=float)
    if delta1 == 0.0:
        return np.where(A >= 0, 1.0, np.nan)
    grid = _scan_grid(np.array([kappa_low(a) for a in A]))  # one column per amplitude
    values = _manifold_residual(grid, A, delta1, exponent)
    sign = np.sign(values)
    change = sign[:-1] != sign[1:]
    i = np.argmax(change, axis=0)
    cols = np.arange(len(A))
    out = np.full(len(A), np.nan)
    found = change.any(axis=0)
    out[values[0] == 0.0] = 1.0
    exact = found & (values[0] != 0.0) & (values[i + 1, cols] == 0.0)
    out[exact] = grid[i + 1, cols][exact]
    todo = found & (values[0] != 0.0) & ~exact
    lo, hi, s_lo = grid[i + 1, cols][todo], grid[i, cols][todo], sign[i + 1, cols][todo]
    at = A[todo]
    for _ in range(int(np.ceil(np.log2(max(float(np.max(hi - lo, initial=0.0)), xtol) / xtol)))):
        mid = 0.5 * (lo + hi)
        same = np.sign(_manifold_residual(mid, at, delta1, exponent)) == s_lo
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    out[todo] = 0.5 * (lo + hi)
    return out


def kappa_on_manifold(A, lam, chi, n, pbar, *, strict=True, xtol=1e-14) -> ManifoldKappa:
    """Solve the implicit eq. (39) for kappa at amplitude(s) A on the stable branch S+.

    Parameters
    ----------
    A : array_like
        Amplitude(s) of X, positive.
    lam, chi, n, pbar
        Wall parameters (see :mod:`slosh_bif.model.params`).
    strict : bool
        If True (default), raise ``ValueError`` naming the amplitudes where no kappa in (0, 1]
        exists (A below the manifold's end A_min(kappa), or kappa not real); if False, return
        NaN there and report it in ``exists``.
    xtol : float
        Absolute tolerance on kappa.
    """
    A_arr = np.asarray(A, dtype=float)
    if np.any(~np.isfinite(A_arr)) or np.any(A_arr <= 0):
        raise ValueError(f"amplitude A must be positive and finite; got {A_arr}")
    delta1 = float(dissipation_at_unit_speed(lam, chi, n, pbar))
    exponent = pbar / (n + 1)
    flat = np.array([_solve_manifold_kappa(a, delta1, exponent, xtol) for a in A_arr.ravel()])
    k = flat.reshape(A_arr.shape)
    exists = np.isfinite(k)
    if strict and not np.all(exists):
        bad = A_arr[~exists]
        raise ValueError(
            f"no restitution coefficient in (0, 1] solves eq. (39) on the stable manifold branch for "
            f"A in [{bad.min():.6g}, {bad.max():.6g}] (lam={lam}, chi={chi}, n={n}, pbar={pbar}): "
            "A lies below the manifold's end A_min(kappa) or kappa is not real there"
        )
    r = np.where(exists, rho(np.where(exists, k, 1.0)), np.nan)
    alpha = np.full_like(k, np.nan)
    alpha[exists] = manifold.alpha(A_arr[exists], r[exists])
    return ManifoldKappa(A=A_arr, kappa=k, rho=r, alpha=alpha, exists=exists)


def simulate_rebound(v0, lam, chi, n, pbar, *, rtol=1e-12, atol=1e-14):
    """Measured restitution ``-v_+/v0`` (13) of one particle rebounding in the wall of eq. (10).

    The particle starts at ``x = 0`` with speed ``v0 > 0`` and is integrated (DOP853) until it
    crosses ``x = 0`` again (:func:`slosh_bif.model.restitution.wall.contact`). This is the physical
    check of eq. (21), independent of (16)-(19).

    Raises ``RuntimeError`` if the particle does not come back (an overdamped wall).
    """
    from slosh_bif.model.restitution.wall import contact

    return contact(v0, lam, chi, n, pbar, rtol=rtol, atol=atol).kappa


@dataclasses.dataclass(frozen=True)
class Eq21Law:
    """Eq. (21) as a :class:`~slosh_bif.model.restitution.laws.SpeedLaw`: kappa(v0) =
    sqrt(1 - delta(1) v0^(pbar/(n+1))) with the wall at |w| = 1 (D = 1)."""

    lam: float
    chi: float
    n: int
    pbar: int

    def kappa(self, v0):
        return kappa(v0, self.lam, self.chi, self.n, self.pbar)

    def clearance(self, v0):
        return np.ones_like(np.asarray(v0, dtype=float))

    def slopes(self, v0, *, checked: bool = True):
        """(kappa, d kappa/dv0, D, dD/dv0) at v0: d kappa/dv0 = -(pbar/(n+1)) delta / (2 kappa v0)."""
        v0 = np.asarray(v0, dtype=float)
        k = self.kappa(v0)
        exponent = self.pbar / (self.n + 1)
        dk = -exponent * (1.0 - k**2) / (2.0 * k * v0)
        return k, dk, np.ones_like(k), np.zeros_like(k)
