"""Where S+ exists, for every restitution law: the ends of S+ and the frequency response between
them, against an independent evaluation of eq. (39) in plain numpy/scipy (issue 17, item 1).

The oracle types (21), (31), (36), (38), (39) from the paper, finds the largest root of (39) in
(0, 1] by a dense scan and bisection, and the ends of S+ by bisection on whether that root exists
and moves continuously. It shares no code with slosh_bif.
"""

import itertools
import warnings

import numpy as np
import pytest
from scipy import optimize, special

from slosh_bif import get_preset
from slosh_bif.model import ManifoldLaw
from slosh_bif.slowflow import AsymptoticsWarning, critical_forcing, frequency_response

BASE = get_preset("fig10").params


class Oracle:
    def __init__(self, lam, chi, n, pbar):
        a = pbar / (2 * (n + 1)) + 0.5
        I = np.sqrt(np.pi) * special.gamma(a) / (4 * (n + 1) * special.gamma(a + 1.5))  # noqa: E741 - (19)'s name
        self.delta1 = 4 * lam * ((n + 1) / chi) ** a * I  # (21) at unit speed
        self.e = pbar / (n + 1)

    @staticmethod
    def rho(k):
        return 2 * (1 - k) / (np.pi * (1 + k))  # (31)

    def G(self, k, A):
        r = self.rho(k)
        disc = (1 + r**2) * A**2 - r**2
        alpha = (1 + np.sqrt(np.maximum(disc, 0))) / (1 + r**2)  # (36), S+
        v = alpha * (2 / np.pi + r)  # (38)
        return np.where(
            disc >= -1e-15, k**2 - 1 + self.delta1 * v**self.e, np.nan
        )  # (39), on the manifold only

    def root(self, A, points=4001):
        """The largest root of (39) in (0, 1] at A, or NaN: a scan from kappa = 1 down to the
        smallest kappa with A on the manifold, A >= A_min(rho(kappa)) (36)."""
        r_max = A / np.sqrt(1 - A**2) if A < 1 else np.inf
        k_low = max((2 - np.pi * r_max) / (2 + np.pi * r_max), 1e-12) if np.isfinite(r_max) else 1e-12
        k = np.linspace(1.0, k_low, points)
        g = self.G(k, A)
        change = np.flatnonzero(
            np.isfinite(g[:-1]) & np.isfinite(g[1:]) & (np.sign(g[:-1]) != np.sign(g[1:]))
        )
        if not len(change):
            return np.nan
        i = change[0]
        f = lambda kk: float(self.G(kk, A))  # noqa: E731
        if f(k[i + 1]) * f(k[i]) > 0:  # a double root within rounding (at a fold): the sample is it
            return k[i + 1]
        return optimize.brentq(f, k[i + 1], k[i], xtol=1e-15)

    def dip(self, A, k_near):
        """Near a fold two roots of (39) may lie within one scan cell: minimise G near k_near and
        return the minimiser when G dips below zero there (a root pair exists), else NaN."""
        res = optimize.minimize_scalar(
            lambda k: float(self.G(k, A)) if np.isfinite(self.G(k, A)) else 1e9,
            bounds=(max(k_near - 0.05, 1e-12), min(k_near + 0.05, 1.0)),
            method="bounded",
            options={"xatol": 1e-15},
        )
        return res.x if res.fun < 0 else np.nan

    def largest(self, A):
        """The largest root, also where it hugs the manifold's edge with a second root (pbar < 0
        near A_min): then G dips below zero just above the edge, and the root lies above the dip."""
        k = self.root(A, 40001)
        if np.isfinite(k):
            return k
        r_max = A / np.sqrt(1 - A**2)
        k_low = (2 - np.pi * r_max) / (2 + np.pi * r_max)
        offsets = 10.0 ** np.linspace(-16, -2, 1401)
        g = np.array([float(self.G(k_low + d, A)) for d in offsets])
        neg = np.flatnonzero(np.isfinite(g) & (g < 0))
        if not len(neg):
            return np.nan
        last = neg[-1]
        return optimize.brentq(
            lambda kk: float(self.G(kk, A)), k_low + offsets[last], k_low + offsets[last + 1], xtol=1e-15
        )

    def ends(self, grid=np.geomspace(1e-4, 1e4, 401)):
        """(A_lo, A_hi) of the longest run of grid amplitudes with a continuous root, refined by
        bisection on existence (A_hi = inf when the run reaches the grid's top)."""
        roots = np.array([self.root(A, 801) for A in grid])
        ok = np.isfinite(roots)
        good = ok[:-1] & ok[1:] & (np.abs(np.diff(roots)) < 0.2)
        runs, start = [], None
        for i in range(len(grid)):
            if ok[i] and start is None:
                start = i
            if start is not None and (i == len(grid) - 1 or not good[i]):
                runs.append((start, i))
                start = None
        if not runs:
            return None
        lo, hi = max(runs, key=lambda r: r[1] - r[0])

        def refine(inside, outside):
            k_in = self.root(inside)
            for _ in range(60):
                mid = np.sqrt(inside * outside)
                k = self.root(mid, 40001)
                if not np.isfinite(k):
                    k = self.dip(mid, k_in)  # two roots closer than the scan: is G below 0 between?
                if np.isfinite(k) and abs(k - k_in) < 0.2:
                    inside, k_in = mid, k
                else:
                    outside = mid
            return inside

        A_lo = refine(grid[lo], grid[lo - 1]) if lo > 0 else grid[0]
        A_hi = refine(grid[hi], grid[hi + 1]) if hi < len(grid) - 1 else np.inf
        return A_lo, A_hi


def _walls():
    for lam, chi, n, pbar in itertools.product(
        (0.1, 0.35, 1.0), (0.2, 1.0, 5.0), (4, 10, 50), (-2, -1, 0, 1, 2, 4)
    ):
        if (pbar + n) % 2 == 0 and pbar > -(n + 1):
            try:
                BASE.replace(lam=lam, chi=chi, n=n, pbar=pbar)
            except ValueError:  # no real kappa at unit speed: not an admissible parameter set
                continue
            yield lam, chi, n, pbar


WALLS = list(_walls())
# The default run checks a few walls with each kind of end; `pytest -m slow` checks them all.
# (0.35, 1, 4, 2): upper end a fold of (39); (0.35, 1, 10, 2): a fold, while the smaller root leaves
# (0, 1] nearby; (0.35, 0.2, 10, 2): kappa reaches 0; (1, 1, 10, -2): the lower end is a fold.
FAST = [
    (0.35, 1.0, 4, 2),
    (0.35, 1.0, 10, 2),
    (0.35, 0.2, 10, 2),
    (1.0, 1.0, 10, -2),
    (0.35, 0.2, 50, 0),
    (0.1, 5.0, 10, -2),
]
SLOW_WALLS = {
    (0.35, 1.0, 10, 2),
    (0.35, 0.2, 10, 2),
    (1.0, 1.0, 10, -2),
}  # 5-7 s each: the rest of the default run covers each kind of window


def _check_window(wall):
    lam, chi, n, pbar = wall
    P = BASE.replace(lam=lam, chi=chi, n=n, pbar=pbar)
    ends = Oracle(*wall).ends()
    if ends is None:
        with pytest.raises(ValueError, match=r"no restitution coefficient in \(0, 1\] solves eq. \(39\)"):
            ManifoldLaw(P)
        return None
    law = ManifoldLaw(P)
    # The oracle's bisection on existence is exact for the manifold end and kappa -> 0, and to
    # ~1e-9 at a fold (two roots closer than its scan look like none).
    assert law.A_min == pytest.approx(ends[0], rel=1e-7), law.describe()
    if np.isinf(ends[1]):
        assert np.isinf(law.A_max) or law.A_max > 1e4 * 0.97
    else:
        assert law.A_max == pytest.approx(ends[1], rel=1e-7), law.describe()
    # and kappa on S+ is the oracle's root
    A = np.geomspace(law.A_min * (1 + 1e-6), min(law.A_max * (1 - 1e-6), 50.0), 7)
    oracle = Oracle(*wall)
    np.testing.assert_allclose(law.kappa(A), [oracle.largest(a) for a in A], atol=1e-10)
    return P


def _check_frc(P):
    oracle = Oracle(P.lam, P.chi, P.n, P.pbar)
    law = ManifoldLaw(P)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        try:
            fr = frequency_response(P, sigma_min=-6, sigma_max=8)
        except ValueError as err:
            # the only admissible failure: no steady state on S+ at this forcing
            assert "no steady state on the stable manifold branch" in str(err)
            return
    c = 1 - P.beta**2
    for b in fr.branches:
        assert b.status == "ok", b.message
        for (A, _), sigma in zip(b.x, b.p):
            k = law.kappa(A) if A in (law.A_min, law.A_max) else oracle.root(A, 40001)
            r = oracle.rho(k)
            a = (1 + np.sqrt(max((1 + r**2) * A**2 - r**2, 0))) / (1 + r**2)
            E = P.gamma * np.pi**2 * A**2 + 8 * r * a**2 * c
            Phi = np.pi**2 * (sigma - c) * A**2 - 8 * a * (1 - a) * c
            assert np.hypot(E, Phi) == pytest.approx(np.pi**2 * A * P.Abar, rel=1e-10)
        for end in b.special_of("END"):
            assert end.reason in ("parameter bound", "domain edge")
            if end.reason == "domain edge":  # on an end of S+, exactly
                assert end.x[0] in (law.A_min, law.A_max)


@pytest.mark.parametrize(
    "wall",
    [pytest.param(w, marks=pytest.mark.slow) if w in SLOW_WALLS else w for w in FAST],
    ids=[f"lam{w[0]}-chi{w[1]}-n{w[2]}-pbar{w[3]}" for w in FAST],
)
def test_window_of_s_plus_and_frc_against_an_independent_eq39(wall):
    P = _check_window(wall)
    if P is not None:
        _check_frc(P)


def test_fast_walls_cover_every_kind_of_end():
    kinds = set()
    for wall in FAST:
        law = ManifoldLaw(BASE.replace(lam=wall[0], chi=wall[1], n=wall[2], pbar=wall[3]))
        kinds |= {
            (which, e.kind) for which, e in (("lower", law.lower), ("upper", law.upper)) if e is not None
        }
    assert kinds == {
        ("lower", "manifold end (36)"),
        ("lower", "fold of (39)"),
        ("upper", "fold of (39)"),
        ("upper", "kappa reaches 0"),
    }


def _oracle_least_abar(P, sigma=1.0, points=1000):
    """The least Abar of (46) over S+ at sigma, by the oracle's closed form on a log grid of A."""
    law, oracle = ManifoldLaw(P), Oracle(P.lam, P.chi, P.n, P.pbar)
    top = min(law.A_max * (1 - 1e-9), 1e4)
    # alpha has a square root at the lower end: the end itself, and a grid that resolves it
    A = np.concatenate(
        [
            [law.A_min],
            law.A_min * (1 + np.geomspace(1e-9, 1e-2, 200)),
            np.geomspace(law.A_min * 1.01, top, points),
        ]
    )
    c = 1 - P.beta**2
    values = []
    for a_ in A:
        r = oracle.rho(
            oracle.largest(a_)
        )  # near a fold of (39) two roots share a scan cell: largest() finds them
        al = (1 + np.sqrt(max((1 + r**2) * a_**2 - r**2, 0.0))) / (1 + r**2)
        values.append(
            np.hypot(
                P.gamma * np.pi**2 * a_**2 + 8 * r * al**2 * c,
                np.pi**2 * (sigma - c) * a_**2 - 8 * al * (1 - al) * c,
            )
            / (np.pi**2 * a_)
        )
    return np.nanmin(values)


def _check_critical(P):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticsWarning)
        cp = critical_forcing(P, 1.0)
    least = _oracle_least_abar(P)
    assert cp.Abar_b == pytest.approx(least, rel=1e-4)  # the grid's resolution
    # never above the oracle's least by more than critical_forcing's resolution at the end: on
    # (1, 1, 10, 2) Abar dips 2e-9 below its end value within 1e-6 of A_min, inside the first cell
    assert cp.Abar_b <= least * (1 + 1e-8)
    return cp


# (0.35, 1, 4, 2): S+ ends at A_min (36) and at a fold of (39); (1, 1, 10, 2): a short window
# ending where kappa reaches 0 (the branch's start used to lie outside it); (0.1, 5, 4, 2): S+ up
# to A = 2664 (the Abar continuation used to stall); (0.1, 0.2, 4, 4): the least Abar at A_min.
@pytest.mark.parametrize(
    "wall",
    [
        (0.35, 1.0, 4, 2),
        pytest.param((1.0, 1.0, 10, 2), marks=pytest.mark.slow),
        pytest.param((0.1, 5.0, 4, 2), marks=pytest.mark.slow),
        (0.1, 0.2, 4, 4),
    ],
)
def test_critical_forcing_is_the_least_abar_over_the_window(wall):
    lam, chi, n, pbar = wall
    _check_critical(BASE.replace(lam=lam, chi=chi, n=n, pbar=pbar, beta=0.3))


@pytest.mark.slow
@pytest.mark.parametrize("beta", [0.0, 0.3])
@pytest.mark.parametrize("wall", WALLS, ids=[f"lam{w[0]}-chi{w[1]}-n{w[2]}-pbar{w[3]}" for w in WALLS])
def test_every_wall_of_the_grid(wall, beta):
    P = _check_window(wall)
    if P is not None:
        _check_frc(P.replace(beta=beta))
        _check_critical(P.replace(beta=beta))


@pytest.mark.parametrize(
    "wall",
    [*FAST, (0.1, 0.2, 4, 4)],
    ids=[f"lam{w[0]}-chi{w[1]}-n{w[2]}-pbar{w[3]}" for w in [*FAST, (0.1, 0.2, 4, 4)]],
)
def test_kappa_is_found_right_next_to_the_lower_end(wall):
    """Within 1e-8 of a lower end the root of (39) is closer to the manifold's edge than (39) can
    be evaluated; kappa is still found (it was NaN, "outside S+", on (0.1, 0.2, 4, 4)), equal to
    the oracle's where the oracle resolves it, and moves continuously into the end's kappa."""
    law = ManifoldLaw(BASE.replace(lam=wall[0], chi=wall[1], n=wall[2], pbar=wall[3]))
    oracle = Oracle(*wall)
    offsets = np.array([1e-13, 1e-11, 1e-9, 1e-8, 1e-7, 1e-6])
    kappa = law.kappa(law.A_min * (1 + offsets))
    assert np.all(np.isfinite(kappa))
    for k, e in zip(kappa, offsets):
        reference = oracle.largest(law.A_min * (1 + e))
        if np.isfinite(reference):
            assert k == pytest.approx(reference, abs=1e-10)
    assert abs(kappa[0] - law.lower.kappa) < 1e-5  # a fold-of-(39) end: kappa - kappa_end ~ sqrt(A - A_min)


def test_the_window_scans_every_amplitude_at_once_with_the_roots_one_at_a_time():
    """The window's scan (801 amplitudes in one pass, bisection to 1e-10) finds a root of (39)
    exactly where the scan one amplitude at a time (brentq) does, and the same one, on random
    walls of both signs of pbar."""
    from slosh_bif.model.restitution.eq21 import dissipation_at_unit_speed, kappa_on_manifold, largest_roots
    from slosh_bif.model.restitution.eq39 import SCAN

    rng = np.random.default_rng(11)
    A = SCAN[::16]
    for _ in range(6):
        n = int(rng.choice([3, 6, 20, 50]))
        pbar = int(rng.choice([-2, 2, 4])) + n % 2
        lam, chi = float(rng.uniform(0.02, 0.8)), float(rng.uniform(0.1, 2.0))
        one = kappa_on_manifold(A, lam, chi, n, pbar, strict=False).kappa
        every = largest_roots(A, float(dissipation_at_unit_speed(lam, chi, n, pbar)), pbar / (n + 1))
        np.testing.assert_array_equal(np.isfinite(every), np.isfinite(one))
        np.testing.assert_allclose(every, one, rtol=0, atol=1e-9)


def test_kappa_on_s_plus_for_many_amplitudes_at_once_is_kappa_one_at_a_time():
    """pbar != 0: kappa of (39) for an array of amplitudes (bisection, all at once) is kappa asked
    one amplitude at a time (brentq), to 1e-13, over the window and its ends."""
    rng = np.random.default_rng(4)
    for n, pbar in ((6, 2), (5, 3), (20, -2), (35, 1)):
        params = get_preset("fig10").params.replace(
            n=n, pbar=pbar, lam=float(rng.uniform(0.05, 0.3)), chi=float(rng.uniform(0.2, 1.5))
        )
        law = ManifoldLaw(params)
        top = law.A_max if np.isfinite(law.A_max) else 10 * law.A_min + 5
        A = np.concatenate([[law.A_min], np.geomspace(law.A_min * (1 + 1e-12), top, 40)])
        together = law.kappa(A)
        apart = np.array([law.kappa(np.array([a]))[0] for a in A])
        np.testing.assert_array_equal(np.isfinite(together), np.isfinite(apart))
        np.testing.assert_allclose(together, apart, rtol=0, atol=1e-13)
