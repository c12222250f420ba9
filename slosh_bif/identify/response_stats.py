"""The statistics of a frequency-response fit (:mod:`.response_fit`, by the steady states of (46)
or the orbits of (9)): the misfit, the seeded
least squares within the parameters' ranges, the Gauss-Newton covariance with its Wald intervals
and rank, and the profile likelihood, each held value refitted from the last and the 3.84
crossing located by Brent."""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy import optimize, stats

__all__ = [
    "CHI2_95",
    "STARTS",
    "ORBIT_SPREAD",
    "misfit_of",
    "seeded_starts",
    "spread_starts",
    "search_starts",
    "SEARCH",
    "least_squares",
    "wald",
    "profile",
    "profile_all",
    "lost_sentence",
    "range_end_sentences",
    "ELASTIC",
    "interval_statistics",
    "HeldObjective",
]

CHI2_95 = 3.841458820694124  # chi-square(1) 95 % quantile: the profile's threshold
STARTS = 4  # seeded starts of the least squares (the base values and three spread about them)
ORBIT_SPREAD = (1.0, 0.5, 2.0, 0.25)  # an orbit fit's starts: the base values scaled by these


def misfit_of(r, scale_known: bool) -> float:
    """The misfit on the log-likelihood's scale: chi-square with the data's std, else N log RSS."""
    rss = float(r @ r)
    return rss if scale_known else len(r) * math.log(max(rss, 1e-300))


def seeded_starts(z0, rng, count, lower, upper) -> list:
    """``count`` starts inside (lower, upper): z0, then z0 scaled by seeded log-normal factors."""
    inside = _inside(lower, upper)
    return [
        np.clip(z0 if k == 0 else z0 * np.exp(rng.normal(0.0, 0.5, size=len(z0))), *inside)
        for k in range(count)
    ]


def spread_starts(z0, lower, upper, factors=ORBIT_SPREAD) -> list:
    """z0 scaled by each of ``factors`` (the first 1), inside (lower, upper): starts far enough
    apart to reach the other minima an orbit fit has (each start chooses its orbits afresh)."""
    return [np.clip(z0 * f, *_inside(lower, upper)) for f in factors]


SEARCH = 8  # seeded Latin-hypercube starts of the global search, beside the given ones
SEARCH_SPAN = 4.0  # the search box: each start value divided and multiplied by this (log scale)


def search_starts(z0, lower, upper, rng, count=SEARCH) -> list:
    """``count`` seeded Latin-hypercube points (one in each of ``count`` strata of every
    parameter, the strata paired at random) over the box [z0 / 4, 4 z0] in log scale, cut to the
    parameters' ranges (lower, upper); a parameter at 0 spans [1/4, 4]."""
    z0 = np.asarray(z0, dtype=float)
    lo_in, hi_in = _inside(lower, upper)
    base = np.where(np.abs(z0) > 0, np.abs(z0), 1.0)
    lo = np.maximum(np.log(base / SEARCH_SPAN), np.log(np.maximum(lo_in, 1e-300)))
    hi = np.minimum(np.log(base * SEARCH_SPAN), np.log(hi_in))
    strata = np.column_stack([rng.permutation(count) for _ in z0]) if len(z0) else np.zeros((count, 0))
    unit = (strata + rng.uniform(size=strata.shape)) / count
    return [np.clip(np.exp(lo + u * (hi - lo)), lo_in, hi_in) for u in unit]


def _inside(lower, upper):
    """Bounds just inside (lower, upper), where a start may sit."""
    return lower + 1e-12 * np.abs(lower), np.where(np.isfinite(upper), upper * (1 - 1e-9), np.inf)


def least_squares(objective, z0, rng, starts=STARTS):
    """The best of ``starts`` least-squares runs within the objective's bounds, the first from z0,
    the others from z0 scaled by seeded log-normal factors; differences of relative step
    ``objective.diff_step`` (None: scipy's, sqrt of the machine epsilon), or the derivatives
    ``objective.jacobian(z)`` where the objective has them."""
    best = None
    for start in seeded_starts(z0, rng, starts, objective.lower, objective.upper):
        run = optimize.least_squares(
            objective,
            start,
            bounds=(objective.lower, objective.upper),
            method="trf",
            x_scale="jac",
            xtol=1e-12,
            ftol=1e-12,
            # the gradient J^T r is as small as the residuals times a weak parameter's effect (eps:
            # 5e-3 in A per unit): scipy's default 1e-8 stops far from the least squares' minimum
            gtol=1e-15,
            diff_step=getattr(objective, "diff_step", None),
            jac=getattr(objective, "jacobian", None) or "2-point",
        )
        if best is None or run.cost < best.cost:
            best = run
    return best


def wald(objective, z, r, scale_known, n_points):
    """Per parameter: value, standard error and Wald interval (clipped to the parameter's range);
    the correlation matrix; a sentence when the Jacobian is (nearly) rank deficient."""
    names = objective.names
    if not names:
        return {}, np.zeros((0, 0)), ""
    J = _jacobian(objective, z)
    dof = max(n_points - len(names), 1)
    s2 = 1.0 if scale_known else float(r @ r) / dof
    scale = np.maximum(np.abs(z), 1e-12)  # the SVD of the relative Jacobian: units do not matter
    _, sv, vt = np.linalg.svd(J * scale, full_matrices=False)
    note = ""
    # a parameter at its lower end (lam at 0) has no relative change: its sentence is the range's
    inside = [k for k in range(len(names)) if not _at_lower_end(objective, z, k)]
    if inside:
        _, sv_in, vt_in = np.linalg.svd((J * scale)[:, inside], full_matrices=False)
        if sv_in[-1] <= 1e-8 * sv_in[0]:
            direction = ", ".join(
                f"{c:+.3g} d{names[k]}/{names[k]}" for c, k in zip(vt_in[-1], inside) if abs(c) > 0.05
            )
            note = (
                f"The data do not determine the combination {direction} (the relative Jacobian's "
                f"singular values {sv_in[0]:.3g} and {sv_in[-1]:.3g})."
            )
    cov = s2 * np.outer(scale, scale) * ((vt.T / np.maximum(sv, 1e-300 * sv[0]) ** 2) @ vt)
    quantile = 1.959963984540054 if scale_known else float(stats.t.ppf(0.975, dof))
    estimate = {}
    for k, name in enumerate(names):
        sd = math.sqrt(max(cov[k, k], 0.0))
        lo, hi = z[k] - quantile * sd, z[k] + quantile * sd
        estimate[name] = {
            "value": float(z[k]),
            "std": float(sd),
            "wald_95": [
                _at_end(max(lo, objective.lower[k]), objective.lower[k]),
                float(min(hi, objective.upper[k])),
            ],
        }
    d = np.sqrt(np.maximum(np.diag(cov), 1e-300))
    return estimate, cov / np.outer(d, d), note


def _at_end(value, lower) -> float:
    """A lower end at the parameter's floor written as 0 (lam's floor 1e-9 is the elastic wall)."""
    return 0.0 if value <= lower * (1 + 1e-6) and lower <= 1e-9 else float(value)


def _jacobian(objective, z, rel=1e-6):
    """The objective's own derivatives where it has them; else differences of the residuals in
    each parameter: central, or one-sided inward within a step of the parameter's range."""
    if getattr(objective, "jacobian", None) is not None:
        return objective.jacobian(z)
    cols = []
    for k in range(len(z)):
        h = rel * max(abs(z[k]), 1e-6)
        e = np.zeros(len(z))
        e[k] = h
        if z[k] - h < objective.lower[k]:
            cols.append((objective(z + e) - objective(z)) / h)
        elif z[k] + h > objective.upper[k]:
            cols.append((objective(z) - objective(z - e)) / h)
        else:
            cols.append((objective(z + e) - objective(z - e)) / (2 * h))
    return np.column_stack(cols)


PROFILE_STEPS = 30  # held values on each side at most (steps growing by half each)


def profile(objective, z, k, best, scale_known, estimate, rng):
    """The 95 % profile-likelihood interval of parameter k: held at values stepping away from the
    estimate (a fifth of its value or three quarters of its standard error, the smaller, growing
    by half each step), the others refitted (each from the last: the valley may curve), until the
    misfit rises past 3.84, the crossing then located by Brent; (interval, rows of (value, rise),
    lost). A side that reaches the parameter's range end first ends there (lam: 0, an elastic
    wall); one that reaches neither in PROFILE_STEPS steps is None: the data do not bound it there.
    A side whose refit ends where the objective has lost its model (``objective.lost``: the orbits
    it follows) is None too, and ``lost`` holds (side, held value) of it: no misfit was found there,
    so no bound either."""
    others = [j for j in range(len(z)) if j != k]

    def rise_at(held, start):
        sub = HeldObjective(objective, z, k, held)
        fit = least_squares(sub, start, rng, starts=1) if others else None
        r = sub(fit.x) if fit is not None else sub(np.zeros(0))
        if getattr(objective, "lost", False):
            return None, start
        rows.append((float(held), misfit_of(r, scale_known) - best))
        return rows[-1][1], (fit.x if fit is not None else start)

    def excess(held, origin):
        rise = rise_at(held, origin)[0]
        if rise is None:  # lost inside the bracket: the chord instead
            raise ValueError("the model is lost inside the bracket")
        return rise - CHI2_95

    # at a range end (lam = 0) the value sets no scale: then a thousandth of the standard error
    first = max(min(0.75 * estimate["std"], 0.2 * abs(z[k])), 1e-3 * max(estimate["std"], abs(z[k]), 1e-6))
    rows, bounds, lost = [(float(z[k]), 0.0)], [], []
    # an objective with a state (the orbits it follows) starts each side from the estimate's
    home = objective.save() if hasattr(objective, "save") else None
    for side, end in ((-1.0, objective.lower[k]), (1.0, objective.upper[k])):
        if home is not None:
            objective.restore(home)
        previous, found, step, held, start = (z[k], 0.0, z[others]), None, first, z[k], z[others]
        for _ in range(PROFILE_STEPS):
            held = held + side * step
            step *= 1.5
            at_end = side * (held - end) >= 0
            held = end if at_end else held
            rise, start = rise_at(held, start)
            if rise is None:
                lost.append((side, float(held)))
                break
            if rise >= CHI2_95:
                found = _crossing(lambda h, origin=previous[2]: excess(h, origin), previous, held, rise, z[k])
                break
            if at_end:
                found = _at_end(held, end) if side < 0 else held
                break
            previous = (held, rise, start)
        bounds.append(None if found is None or not np.isfinite(found) else float(found))
    if home is not None:
        objective.restore(home)
    return bounds, sorted(rows), lost


def profile_all(objective, z, which, best, scale_known, estimate, rng, *, pool=None, say=None) -> list:
    """:func:`profile` of each parameter ``which`` names ((index, name) pairs) (or the objective's
    own ``profile`` method with the same arguments but the objective), one after another or side
    by side on ``pool`` (an executor): the same result, as each profile starts from the objective's
    state at the estimate and leaves it there."""
    say = say or (lambda message: None)
    method = getattr(objective, "profile", None) or functools.partial(profile, objective)
    if pool is None:
        out = []
        for k, name in which:
            say(f"profile likelihood of {name}")
            out.append(method(z, k, best, scale_known, estimate[name], rng))
        return out
    say(f"profile likelihoods of {', '.join(name for _, name in which)} side by side")
    futures = [pool.submit(method, z, k, best, scale_known, estimate[name], rng) for k, name in which]
    return [future.result() for future in futures]


ELASTIC = "lam's interval reaches 0: an elastic wall (kappa = 1) is consistent with the data."


def _at_lower_end(objective, z, k) -> bool:
    end = objective.lower[k]
    return bool(np.isfinite(end) and abs(z[k] - end) <= 1e-6 * (1.0 + abs(end)))


def range_end_sentences(objective, names, z) -> list:
    """A sentence for each estimate at an end of its admissible range (``objective.lower``,
    ``upper``), but lam's lower end (an elastic wall, physical)."""
    out = []
    for k, name in enumerate(names):
        for end, side in ((objective.lower[k], "lower"), (objective.upper[k], "upper")):
            if (
                (name, side) != ("lam", "lower")
                and np.isfinite(end)
                and abs(z[k] - end) <= 1e-6 * (1.0 + abs(end))
            ):
                out.append(
                    f"{name} = {z[k]:.4g} sits at the {side} end of its admissible range: the data push "
                    "it beyond what the model allows, a sign that a parameter held fixed (the wall's n, "
                    "say) is not the data's, or (eps at 0: the slow flow's limit) that the data cannot "
                    "tell it; no interval, Wald or profile, is to be trusted from an estimate there."
                )
    return out


def lost_sentence(name: str, lost) -> list:
    """What a profile's ``lost`` sides mean, one sentence each."""
    return [
        f"{name}'s profile stops at {name} = {held:.4g} ({'below' if side < 0 else 'above'} the estimate), "
        "where the model's orbits followed from the estimate are lost: the 95 % bound on that side is "
        "not known (reported as none)."
        for side, held in lost
    ]


def _crossing(excess, previous, held, rise, scale) -> float:
    """Where the profile's rise crosses 3.84 between the last held value below it and the first
    above, by Brent; by the chord where a refit does not reproduce the bracket (the full model's
    orbits are followed from call to call, and may come back to another)."""
    lo, hi = sorted((previous[0], held))
    try:
        return optimize.brentq(excess, lo, hi, xtol=1e-6 * max(abs(scale), 1e-9), maxiter=40)
    except ValueError:
        w = (CHI2_95 - previous[1]) / max(rise - previous[1], 1e-300)
        return previous[0] + w * (held - previous[0])


class HeldObjective:
    """The residuals with parameter k held at ``held``, the others free (their bounds kept)."""

    def __init__(self, objective, z, k, held):
        self.objective, self.z, self.k, self.held = objective, np.array(z, dtype=float), k, held
        self.lower, self.upper = np.delete(objective.lower, k), np.delete(objective.upper, k)
        self.diff_step = getattr(objective, "diff_step", None)
        self.jacobian = self._jacobian if getattr(objective, "jacobian", None) is not None else None

    def _full(self, others):
        return np.insert(np.asarray(others, dtype=float), self.k, self.held)

    def __call__(self, others):
        return self.objective(self._full(others))

    def _jacobian(self, others):
        return np.delete(self.objective.jacobian(self._full(others)), self.k, axis=1)


def interval_statistics(objective, z, r, scale_known, points, rng, profiled, *, pool=None, say=None) -> tuple:
    """(estimate, correlation, profiles, sentences) of a record's fit at ``z`` (residuals ``r``,
    ``points`` of them): Wald for every parameter, the profile of each of ``profiled`` (the first
    names of ``objective.names``), and what the record cannot tell: an estimate at its range's end,
    a rank-deficient Jacobian, a profile side that is lost, unbounded or stops at the range's end."""
    names = objective.names
    misfit = misfit_of(r, scale_known)
    sentences = range_end_sentences(objective, profiled, z)
    objective(z)
    estimate, correlation, rank_note = wald(objective, z, r, scale_known, points)
    if rank_note:
        sentences.append(rank_note)
    profiles = {}
    outcomes = profile_all(
        objective, z, list(enumerate(profiled)), misfit, scale_known, estimate, rng, pool=pool, say=say
    )
    for k, (name, (interval, rows, lost)) in enumerate(zip(names, outcomes)):
        estimate[name]["profile_95"] = interval
        profiles[name] = rows
        sentences += lost_sentence(name, lost)
        lost_sides = {"lower" if side < 0 else "upper" for side, _ in lost}
        for bound, end, side in zip(interval, (objective.lower[k], objective.upper[k]), ("lower", "upper")):
            if bound is None and side not in lost_sides:
                sentences.append(f"The record does not bound {name} on its {side} side.")
            elif (
                bound is not None and np.isfinite(end) and end > 1e-9 and abs(bound - end) <= 1e-6 * abs(end)
            ):
                sentences.append(
                    f"{name}'s profile reaches the {side} end of its admissible range ({end:.4g}) within "
                    "3.84: the record does not bound it there."
                )
    return estimate, correlation, profiles, sentences
