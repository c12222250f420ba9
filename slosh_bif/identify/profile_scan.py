"""The profile likelihood of one parameter scanned on a grid, for a misfit with valleys side by
side (a transient's trajectory of (9) or (8), :mod:`.transient_fit`): held at the estimate plus
multiples of half its Wald standard error, out to :data:`SCAN` of them and on while the rise stays
within 3.84, the others refitted at each held value from where the linear fit at the estimate puts
them (and, where that rises past 3.84, from the last held value's). A walk that stops at the first
rise past 3.84 (:func:`~.response_stats.profile`) would report the first valley's width; the scan
reports every held value within 3.84 of the best, across valleys, and a lower misfit where it
finds one (a negative rise: the estimate was not the best minimum)."""

from __future__ import annotations

import numpy as np

from slosh_bif.identify.response_stats import CHI2_95, HeldObjective, least_squares, misfit_of

__all__ = ["scanned_profile", "LinearValley", "SCAN", "STEP", "MOST"]

STEP = 0.5  # the grid's step, in Wald standard errors
SCAN = 6.0  # the grid reaches at least this many standard errors either side
MOST = 60  # held values on each side at most


class LinearValley:
    """``valley(k, held)``: the other parameters where the linear fit at ``z`` (covariance ``cov``)
    puts them with parameter k held, within (lower, upper); an object, so that a profile sent to
    another process takes it along."""

    def __init__(self, z, cov, lower, upper):
        self.z, self.cov, self.lower, self.upper = z, cov, lower, upper

    def __call__(self, k, held):
        others = [j for j in range(len(self.z)) if j != k]
        move = self.cov[others, k] / self.cov[k, k] * (held - self.z[k])
        return np.clip(self.z[others] + move, self.lower[others], self.upper[others])


def scanned_profile(objective, z, k, best, scale_known, estimate, valley) -> tuple:
    """(interval, rows of (held, rise), lost) of parameter k as :func:`~.response_stats.profile`
    returns them, by the scan; ``valley(k, held)``: the others' start at each held value."""
    sd = estimate["std"] if np.isfinite(estimate["std"]) and estimate["std"] > 0 else 0.05 * abs(z[k])
    rows, bounds = [(float(z[k]), 0.0)], []
    for side, end in ((-1.0, objective.lower[k]), (1.0, objective.upper[k])):
        last_inside, crossing, previous = z[k], None, np.delete(np.asarray(z, dtype=float), k)
        for m in range(1, MOST + 1):
            held = z[k] + side * m * STEP * sd
            at_end = side * (held - end) >= 0
            held = float(end if at_end else held)
            rise, previous = _refit(objective, z, k, held, (valley(k, held), previous), best, scale_known)
            rows.append((held, rise))
            if rise <= CHI2_95:
                last_inside, crossing = held, None
            elif crossing is None:
                crossing = (held, rise)
            if at_end or (crossing is not None and m * STEP >= SCAN and abs(held - last_inside) > STEP * sd):
                break
        if crossing is None:  # still within 3.84 where the scan ended: at the range's end, or unbounded
            bounds.append(float(end) if side * (last_inside - end) >= 0 else None)
        else:
            inside_rise = min(r for h, r in rows if h == last_inside)
            w = (CHI2_95 - inside_rise) / max(crossing[1] - inside_rise, 1e-300)
            bounds.append(float(last_inside + w * (crossing[0] - last_inside)))
    return bounds, sorted(rows), []


def _refit(objective, z, k, held, starts, best, scale_known) -> tuple:
    """(rise, others) at ``held``: from the first start, and from the second where the first's
    rise passes 3.84."""
    sub = HeldObjective(objective, z, k, held)
    rng = np.random.default_rng(0)
    found = None
    for start in starts:
        start = np.clip(start, sub.lower, sub.upper)
        run = least_squares(sub, start, rng, starts=1)
        rise = misfit_of(sub(run.x), scale_known) - best
        if found is None or rise < found[0]:
            found = (rise, run.x)
        if found[0] <= CHI2_95:
            break
    return found
