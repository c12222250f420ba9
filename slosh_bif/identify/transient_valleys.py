"""The valleys of a transient's misfit (:mod:`.transient_fit`): the trajectory of an impacting
oscillator depends on its parameters so sharply that the misfit of a record from rest (eqs. 8, 9)
has narrow valleys side by side, and the valley the truth lies in need not be the one a least
squares from the last window's estimate falls into. Each window follows a few valleys and looks for
new ones about the best; at the horizon a wider search looks again, and the intervals are widened
to span the other minima within 3.84 of the best."""

from __future__ import annotations

import numpy as np

from slosh_bif.identify.goodness import goodness
from slosh_bif.identify.response_stats import CHI2_95, least_squares, misfit_of
from slosh_bif.identify.transient_record import TRAJECTORY_NAMES

__all__ = [
    "followed",
    "best_valley",
    "span_valleys",
    "search_valleys",
    "refit",
    "at_range_end",
    "VALLEYS",
    "VALLEY_SPAN",
    "BROAD_SPAN",
    "DISCOVER",
    "KEEP",
]

VALLEYS = 24  # seeded starts about the horizon's estimate that look for the misfit's other valleys
VALLEY_SPAN = 0.25  # each free parameter within this relative band of the estimate
BROAD_SPAN = 0.6  # the band where a short window's fit ran to a range end: the starts' own spread
DISCOVER = 6  # seeded starts of each window about its best valley
KEEP = 3  # valleys followed from one window to the next


def followed(objective, valleys, rng, pool) -> list:
    """The least-squares runs of a window from each valley the last window kept and from
    :data:`DISCOVER` seeded starts about the best of them (:data:`VALLEY_SPAN`; where a run ends at
    a range's end, :data:`BROAD_SPAN`), the distinct ones best first, at most :data:`KEEP` of those
    inside the admissible ranges: valleys split as a window grows, and the one the truth lies in
    need not be the best at first (the Fig. 10 decay at 1 % noise to tau = 15: lam 0.354 and 0.315
    within 4 of each other in chi-square; to tau = 25, 76 apart the other way)."""
    runs = [refit(objective, v) for v in valleys]
    span = BROAD_SPAN if all(at_range_end(objective, o.x) for o in runs) else VALLEY_SPAN
    best = min(runs, key=lambda o: o.cost)
    runs += search_valleys(objective, best.x, span, rng, pool, DISCOVER)
    runs.sort(key=lambda o: (at_range_end(objective, o.x), o.cost))
    kept = []
    for o in runs:
        scale = np.maximum(np.abs(o.x), 1e-9)
        if all(np.max(np.abs(o.x - k.x) / scale) > 1e-4 for k in kept):
            kept.append(o)
    return kept[:KEEP]


def best_valley(z, fitted, model: str, rng, pool, tracked=()) -> tuple:
    """The horizon window's best minimum among the continuation's and those refitted from
    :data:`VALLEYS` seeded starts about it (each free parameter within :data:`VALLEY_SPAN` of the
    estimate, a Latin hypercube; X0 kept) and the other valleys followed to it (``tracked``), and
    every minimum found as (misfit, z): a record's
    misfit has valleys side by side (the Fig. 10 decay at 1 % noise up to tau = 25: lam 0.318 and
    0.349 within a few units of chi-square), which the continuation alone does not see."""
    objective, run, r, verdict, end = fitted
    k = len(z) - 1
    runs = search_valleys(objective, z, VALLEY_SPAN, rng, pool) + list(tracked)
    scale_known = objective.record.std is not None
    minima = [(misfit_of(r, scale_known), np.array(z), run)]
    minima += [(misfit_of(objective(other.x), scale_known), other.x, other) for other in runs]
    best = min(minima, key=lambda m: m[0])
    if best[2] is not run:
        z, run = best[1], best[2]
        r = objective(z)
        verdict = goodness(objective.record, r, k + 1, TRAJECTORY_NAMES[model])
    return z, (objective, run, r, verdict, end), [(m, x) for m, x, _ in minima]


def span_valleys(estimate, names, z, minima, best: float) -> list:
    """Each interval widened to span the other minima within 3.84 of the best (each with the best's
    own half-widths about it), more than a standard error away in some parameter; a sentence."""
    sd = np.array([estimate[n]["std"] for n in names])
    near = [
        x for m, x in minima if m - best <= CHI2_95 and np.any(np.abs(x[: len(names)] - z[: len(names)]) > sd)
    ]
    if not near:
        return [
            f"The misfit of a trajectory has narrow valleys side by side: the search about the estimate "
            f"({len(minima) - 1} starts) found none other within 3.84, but one it did not reach may fit as "
            "well, so these intervals are those of the valley found (over 80 noisy copies of a decay "
            "about 5 in 6 held the truth: docs/findings/identify.md)."
        ]
    for k, name in enumerate(names):
        for key in ("wald_95", "profile_95"):
            lo, hi = estimate[name][key]
            values = [x[k] for x in near]
            if lo is not None:
                estimate[name][key][0] = float(min([lo] + [v - (z[k] - lo) for v in values]))
            if hi is not None:
                estimate[name][key][1] = float(max([hi] + [v + (hi - z[k]) for v in values]))
    where = "; ".join(", ".join(f"{n} = {x[k]:.4g}" for k, n in enumerate(names)) for x in near[:3])
    return [
        f"{len(near)} other {'minimum' if len(near) == 1 else 'minima'} of the misfit "
        f"{'lies' if len(near) == 1 else 'lie'} within 3.84 of the best ({where}): the record up to "
        "the horizon does not decide between these valleys; each interval is widened to span them."
    ]


def search_valleys(objective, z, span: float, rng, pool, count: int = 0) -> list:
    """Least-squares runs from ``count`` (default :data:`VALLEYS`) seeded Latin-hypercube starts,
    each free parameter within ``span`` (relative) of z's, within its range, X0 kept."""
    k, count = len(z) - 1, count or VALLEYS
    strata = np.column_stack([rng.permutation(count) for _ in range(k)])
    unit = (strata + rng.uniform(size=strata.shape)) / count
    box = (objective.lower[:k], objective.upper[:k])
    starts = [np.append(np.clip(z[:k] * (1 + span * (2 * u - 1)), *box), z[-1]) for u in unit]
    if pool is None:
        return [refit(objective, start) for start in starts]
    return [future.result() for future in [pool.submit(refit, objective, start) for start in starts]]


def refit(objective, start):
    """The least squares of ``objective`` from ``start`` (one start, no draw)."""
    return least_squares(objective, start, np.random.default_rng(0), starts=1)


def at_range_end(objective, z) -> bool:
    """Whether a free parameter sits at an end of its admissible range (a window too short to
    determine it lets it run there; the next window starts from the last estimate instead)."""
    k = len(z) - 1
    ends = np.concatenate([objective.lower[:k], objective.upper[:k]])
    return bool(np.any(np.isclose(np.concatenate([z[:k], z[:k]]), ends, rtol=1e-6, atol=1e-12)))
