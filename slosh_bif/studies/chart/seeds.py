"""Where a chart seeds its families in its second parameter: the primary branch's points at a
few values of sigma (away from its special points), the parts of the sigma range the branch does
not reach, and how a seed switches at its pitchforks; the seeds' branches give the folds and
period doublings met as the forcing Abar falls (Figs. 10-13), which a family in sigma misses."""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["regular_points", "seed_branching", "seed_points", "uncovered_points"]


def seed_points(pieces, sigma_range, count: int) -> list:
    """Where the chart continues the primary branch's orbits in its second parameter: ``count``
    values of sigma spread over the part of ``sigma_range`` the branch covers (all of it, unless
    the branch is an isola or ends inside the range), and for each the nearest regular point of
    ``pieces`` (pairs of the branch's sigma values and a mask of its points away from special
    ones). Returns (piece, index) pairs, each point once: targets that fall on the same point
    (a short branch) would trace the same curves again."""
    covered = [np.asarray(p, dtype=float) for p, _ in pieces if len(p)]
    if not covered or count <= 0:
        return []
    lo = max(sigma_range[0], min(float(np.min(p)) for p in covered))
    hi = min(sigma_range[1], max(float(np.max(p)) for p in covered))
    chosen = []
    for sigma in np.linspace(lo, hi, count + 2)[1:-1] if lo < hi else ():
        best = None
        for k, (p, regular) in enumerate(pieces):
            if not np.any(regular):
                continue
            i = int(np.argmin(np.where(regular, np.abs(np.asarray(p) - sigma), np.inf)))
            if best is None or abs(p[i] - sigma) < abs(pieces[best[0]][0][best[1]] - sigma):
                best = (k, i)
        if best is not None and best not in chosen:
            chosen.append(best)
    return chosen


def uncovered_points(pieces, sigma_range, count: int, least: float = 0.02) -> list:
    """Values of sigma where the chart seeks orbits of its own, outside the primary branch: in
    each part of ``sigma_range`` that no piece of ``pieces`` (arrays of the branch's sigma) covers
    and that is at least ``least`` of the range long (an isola, a branch ending inside the range),
    as many as that part's share of ``count`` (at least one), spread over its inside. Empty
    where the branch spans the range, or ``count`` is 0 (no seeds asked for)."""
    lo, hi = sigma_range
    covered = [(float(np.min(p)), float(np.max(p))) for p in pieces if len(p)]
    if not covered or count <= 0:
        return []
    gaps, at = [], lo
    for a, b in sorted(covered):
        if a > at:
            gaps.append((at, min(a, hi)))
        at = max(at, b)
    if at < hi:
        gaps.append((at, hi))
    out = []
    for a, b in gaps:
        if b - a >= least * (hi - lo):
            k = max(1, round(count * (b - a) / (hi - lo)))
            out += [float(v) for v in np.linspace(a, b, k + 2)[1:-1]]
    return out


def seed_branching(branching):
    """How a seed continued in the chart's second parameter switches: at its pitchforks as
    ``branching`` says (their pairs' folds and flips can bound the stable region below everything
    the family reaches), not at period doublings, three branches at most."""
    return dataclasses.replace(branching, doublings=False, max_branches=3)


def regular_points(branch) -> np.ndarray:
    """A mask of the branch's points at least three points away from its special points: an orbit
    at a pitchfork continued in another parameter shows its mirror pair's meeting as spurious folds."""
    regular = np.ones(len(branch), dtype=bool)
    for sp in branch.special:
        regular[max(sp.index - 2, 0) : sp.index + 3] = False
    return regular
