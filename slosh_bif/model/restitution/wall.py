"""The smooth wall's own restitution kappa(v0) and turning point d(v0), measured once per wall.

Eq. (21) gives the restitution of the wall of eq. (10) to first order in its dissipation; at the
paper's n = 6 sets it says 0.27 where the wall returns 0.63 (:mod:`slosh_bif.model.restitution.eq21`).
And the particle penetrates the wall: it turns at |w| = d(v0), the clearance it actually uses,
not at the nominal |w| = 1 (n = 50: d = 1.054 at unit speed; n = 6: 1.25). Both
are functions of the impact speed v0 alone, so they are measured by integrating single contacts
(:func:`contact`: the unit particle of (10) entering at x = 0 with speed v0, to its turning point
x = d and back out with speed kappa v0) at Chebyshev nodes in log v0 over the speeds a study
needs, and kept as polynomial interpolants whose error is measured at the midpoints between the
nodes and stated (:class:`WallLaw`); a Newtonian wall's (pbar = 0) from one contact and the
exact scaling below, its error measured at both ends of the range. One law per (lam, chi, n,
pbar) and speed range is computed once per process (:func:`wall_law`).

Exact checks that need no integration: without dissipation (lam = 0) kappa = 1 and d is the
turning point of eq. (17), ((n+1) v0^2 / chi)^(1/(2n+2)); at pbar = 0 the wall's equation is
invariant under x -> s^(1/(n+1)) x, t -> s^(-n/(n+1)) t, v -> s v, so kappa does not depend on v0
(eq. 40's "Newtonian" wall) and d grows exactly like v0^(1/(n+1)).
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

__all__ = ["Contact", "contact", "WallLaw", "wall_law", "AT_CORNER"]

# An impact within this relative distance of a law's least speed v_min is at the law's corner: the
# impact models hold the law constant below v_min, so its derivatives in the speed jump there (the
# orbits' special points and the normal forms' jets are not computed at it).
AT_CORNER = 1e-6


@dataclasses.dataclass(frozen=True)
class Contact:
    """One contact with the wall: ``kappa`` = exit speed / entry speed, ``depth`` = the turning
    point d (the largest |w|; d - 1 is the penetration past the nominal wall), ``clearance`` = the
    position D of the rigid wall with restitution kappa that gives the same free flights in and
    out: where the lines x = v0 t and x = -kappa v0 (t - t_exit) meet, D = kappa v0 t_exit /
    (1 + kappa). D > d: the particle lingers near its turning point (conservative wall:
    D = d B(1/m, 1/2) / m, m = 2n + 2, 11 % beyond d at n = 6, 1.4 % at n = 50)."""

    v0: float
    kappa: float
    depth: float
    clearance: float


def _check_wall(lam, chi, n, pbar):
    if not (np.isfinite(lam) and lam >= 0):
        raise ValueError(f"lam (the wall's damping) must be finite and >= 0; got {lam!r}")
    if not (np.isfinite(chi) and chi > 0):
        raise ValueError(f"chi (the wall's stiffness) must be finite and > 0; got {chi!r}")
    if not (isinstance(n, (int, np.integer)) and n >= 1):
        raise ValueError(f"n must be an integer >= 1; got {n!r}")
    p = (pbar + n) // 2
    if 2 * p - n != pbar or p < 0:
        raise ValueError(
            f"pbar must make p = (pbar + n)/2 a non-negative integer; got n = {n}, pbar = {pbar}"
        )
    return p


def contact(
    v0: float, lam: float, chi: float, n: int, pbar: int, *, rtol: float = 1e-12, atol: float = 1e-14
) -> Contact:
    """Integrate one contact (scipy DOP853, events at the turning point and at the exit).

    Raises ``RuntimeError`` when the particle does not come back (an overdamped wall)."""
    from scipy.integrate import solve_ivp

    if not (np.isfinite(v0) and v0 > 0):
        raise ValueError(f"impact speed v0 must be positive and finite; got {v0!r}")
    p = _check_wall(lam, chi, n, pbar)

    def rhs(_t, y):
        x, xdot = y
        return [xdot, -chi * x ** (2 * n + 1) - lam * xdot * x ** (2 * p)]

    def turning(_t, y):
        return y[1]

    def exit_(_t, y):
        return y[0]

    turning.direction = -1
    exit_.terminal, exit_.direction = True, -1
    x_max = ((n + 1) * v0**2 / chi) ** (1.0 / (2 * n + 2))  # the conservative turning point (17)
    t_end = 100.0 * x_max / v0  # a round trip takes ~4 x_max / v0; only an overdamped wall needs more
    with np.errstate(over="ignore", invalid="ignore"):
        sol = solve_ivp(
            rhs, (0.0, t_end), [0.0, v0], method="DOP853", events=(turning, exit_), rtol=rtol, atol=atol
        )
    if sol.status != 1 or len(sol.t_events[1]) == 0 or len(sol.t_events[0]) == 0:
        raise RuntimeError(
            f"the particle did not return to x = 0 within t = {t_end:.3g} (v0 = {v0}, lam = {lam}, "
            f"chi = {chi}, n = {n}, pbar = {pbar}): the wall is overdamped"
        )
    k = float(-sol.y_events[1][0][1] / v0)
    return Contact(float(v0), k, float(sol.y_events[0][0][0]), float(k * v0 * sol.t_events[1][0] / (1.0 + k)))


@dataclasses.dataclass(frozen=True)
class WallLaw:
    """kappa(v0) and d(v0) of one wall over [v_min, v_max], as Chebyshev series in log v0.

    ``kappa_error`` and ``depth_error``: the largest difference between the interpolant and a
    direct contact at the midpoints between the nodes (the interpolant's measured error)."""

    lam: float
    chi: float
    n: int
    pbar: int
    v_min: float
    v_max: float
    kappa_series: np.polynomial.Chebyshev
    depth_series: np.polynomial.Chebyshev
    clearance_series: np.polynomial.Chebyshev
    kappa_error: float
    depth_error: float
    clearance_error: float

    def _log_v(self, v0):
        v0 = np.asarray(v0, dtype=float)
        if (
            np.any(~np.isfinite(v0))
            or np.any(v0 < self.v_min * (1 - 1e-12))
            or np.any(v0 > self.v_max * (1 + 1e-12))
        ):
            raise ValueError(
                f"impact speed outside the measured range [{self.v_min:g}, {self.v_max:g}]: {v0!r}"
            )
        return np.log(v0)

    def kappa(self, v0):
        """The restitution at impact speed v0 (within the range)."""
        return self.kappa_series(self._log_v(v0))

    def depth(self, v0):
        """The turning point d at impact speed v0: the clearance the particle uses (nominal 1)."""
        return np.exp(self.depth_series(self._log_v(v0)))

    def clearance(self, v0):
        """The equivalent rigid wall's position D at impact speed v0 (:class:`Contact`)."""
        return np.exp(self.clearance_series(self._log_v(v0)))

    @functools.cached_property
    def highest_clearance(self) -> float:
        """The largest D over the measured speeds (on a grid of 4001 in log v0): how far out a
        rebound can leave the particle."""
        return float(np.max(self.clearance(np.geomspace(self.v_min, self.v_max, 4001))))

    @functools.cached_property
    def _coefficients(self):
        # The four series (kappa, its slope, log D, its slope) as the columns of one coefficient
        # array on the window [-1, 1], evaluated together: a corrected slow flow asks for them at
        # every evaluation of its right-hand side.
        k, d = self.kappa_series, self.clearance_series
        columns = (k.coef, k.deriv().coef, d.coef, d.deriv().coef)
        stacked = np.zeros((max(len(c) for c in columns), 4))
        for j, c in enumerate(columns):
            stacked[: len(c), j] = c
        # Trailing terms below 1e-14 of each series' size change nothing the stated errors allow
        # (for pbar = 0 kappa is a constant and log D linear in log v0: two terms, not 32).
        size = np.maximum(np.abs(stacked).max(axis=0), 1e-300)
        keep = np.flatnonzero(np.any(np.abs(stacked) > 1e-14 * size, axis=1))
        stacked = stacked[: keep[-1] + 1 if len(keep) else 1]
        return k.mapparms(), stacked, np.arange(stacked.shape[0], dtype=float)

    def slopes(self, v0, *, checked: bool = True):
        """(kappa, d kappa/dv0, D, dD/dv0) at impact speed(s) v0, D the clearance: the interpolants
        differentiated. ``checked=False``: the caller keeps v0 inside the range (no check)."""
        (off, scale), stacked, degrees = self._coefficients
        if not checked and np.ndim(v0) == 0:  # a continuation's one amplitude: floats, not arrays
            v0 = float(v0)
            k, dk, log_d, dlog_d = (
                np.cos(math.acos(min(max(off + scale * math.log(v0), -1.0), 1.0)) * degrees) @ stacked
            )
            clearance = math.exp(log_d)
            return k, dk / v0, clearance, clearance * dlog_d / v0
        s = self._log_v(v0) if checked else np.log(v0)
        # T_k(x) = cos(k arccos x) for all k at once, one product for the four series: numpy's
        # chebval runs a Python loop over the ~30 terms (150 us a call, most of a corrected
        # branch's time). Near x = +-1 arccos is sensitive to x's rounding, but T_k is flat there.
        x = np.clip(off + scale * s, -1.0, 1.0)
        k, dk, log_d, dlog_d = np.moveaxis(np.cos(np.multiply.outer(np.arccos(x), degrees)) @ stacked, -1, 0)
        v0 = np.exp(s)
        clearance = np.exp(log_d)
        return k, dk / v0, clearance, clearance * dlog_d / v0  # deriv() is in the domain variable log v0


@functools.lru_cache(maxsize=32)
def wall_law(
    lam: float, chi: float, n: int, pbar: int, v_min: float = 0.05, v_max: float = 20.0, *, nodes: int = 24
) -> WallLaw:
    """The :class:`WallLaw` of (lam, chi, n, pbar) over [v_min, v_max] from ``nodes`` contacts at
    Chebyshev points in log v0 (and ``nodes - 1`` more at the midpoints, for the stated error).
    Cached: a parameter set is measured once per process (about a second)."""
    _check_wall(lam, chi, n, pbar)
    if not (np.isfinite(v_min) and np.isfinite(v_max) and 0 < v_min < v_max):
        raise ValueError(f"need 0 < v_min < v_max, both finite; got [{v_min}, {v_max}]")
    if not (isinstance(nodes, int) and 4 <= nodes <= 200):
        raise ValueError(f"nodes must be an integer in [4, 200]; got {nodes!r}")
    if pbar == 0:
        return _newtonian_law(lam, chi, n, v_min, v_max)
    domain = [np.log(v_min), np.log(v_max)]
    # Chebyshev points of the second kind (the ends included) and the midpoints between them.
    theta = np.pi * np.arange(nodes) / (nodes - 1)
    s = 0.5 * (domain[0] + domain[1]) - 0.5 * (domain[1] - domain[0]) * np.cos(theta)
    mid = 0.5 * (domain[0] + domain[1]) - 0.5 * (domain[1] - domain[0]) * np.cos(
        0.5 * (theta[:-1] + theta[1:])
    )
    at_nodes = [contact(float(np.exp(x)), lam, chi, n, pbar) for x in s]
    kappa = np.polynomial.Chebyshev.fit(s, [c.kappa for c in at_nodes], nodes - 1, domain=domain)
    # log d and log D are nearly linear in log v0 (exactly, at pbar = 0)
    depth = np.polynomial.Chebyshev.fit(s, [np.log(c.depth) for c in at_nodes], nodes - 1, domain=domain)
    clearance = np.polynomial.Chebyshev.fit(
        s, [np.log(c.clearance) for c in at_nodes], nodes - 1, domain=domain
    )
    check = [contact(float(np.exp(x)), lam, chi, n, pbar) for x in mid]
    kappa_error = float(max(abs(kappa(x) - c.kappa) for x, c in zip(mid, check)))
    depth_error = float(max(abs(np.exp(depth(x)) - c.depth) for x, c in zip(mid, check)))
    clearance_error = float(max(abs(np.exp(clearance(x)) - c.clearance) for x, c in zip(mid, check)))
    return WallLaw(
        float(lam),
        float(chi),
        int(n),
        int(pbar),
        float(v_min),
        float(v_max),
        kappa,
        depth,
        clearance,
        kappa_error,
        depth_error,
        clearance_error,
    )


def _newtonian_law(lam, chi, n, v_min, v_max) -> WallLaw:
    """The law of a Newtonian wall (pbar = 0) from one contact at unit speed and its exact
    scaling (the module docstring): kappa constant, d and D growing like v0^(1/(n+1)). Its stated
    errors are those of the scaled contact against direct contacts at both ends of the range."""
    unit = contact(1.0, lam, chi, n, 0)
    domain = [np.log(v_min), np.log(v_max)]
    ends = np.array(domain)
    kappa = np.polynomial.Chebyshev.fit(ends, [unit.kappa] * 2, 0, domain=domain)
    depth = np.polynomial.Chebyshev.fit(ends, np.log(unit.depth) + ends / (n + 1), 1, domain=domain)
    clearance = np.polynomial.Chebyshev.fit(ends, np.log(unit.clearance) + ends / (n + 1), 1, domain=domain)
    check = [contact(float(np.exp(x)), lam, chi, n, 0) for x in ends]
    errors = [
        float(max(abs(f(x) - getattr(c, name)) for x, c in zip(ends, check)))
        for f, name in (
            (kappa, "kappa"),
            (lambda x: np.exp(depth(x)), "depth"),
            (lambda x: np.exp(clearance(x)), "clearance"),
        )
    ]
    return WallLaw(
        float(lam), float(chi), int(n), 0, float(v_min), float(v_max), kappa, depth, clearance, *errors
    )
