"""The full model's critical forcing read off a chart's curves at one sigma: the lowest curve that
bounds stable orbits with wall contact, and, where the stable orbits lie below it, the lower end
of those (:mod:`slosh_bif.orbits.stable_contact`); the curves that leave the box through its
lowest Abar. The least forcing with a stable response in contact is the counterpart of the slow
flow's Abar_b of (46)."""

from __future__ import annotations

import functools

import numpy as np

from slosh_bif.model.params import Params
from slosh_bif.orbits.codim2 import CODIM2_KINDS, corrected_at, curve_boundary
from slosh_bif.orbits.criticality import impact_criticality, special_criticality
from slosh_bif.orbits.settings import SHOOTING, ShootingSettings
from slosh_bif.orbits.stable_contact import LowEnd, family_low_ends, stable_orbit_below, stable_side_below
from slosh_bif.studies.chart.bottom import below_bottom
from slosh_bif.studies.chart.result import Chart

__all__ = [
    "critical_at",
    "beyond_exit",
    "exits_below",
    "impact_low_end_reading",
    "low_end_reading",
    "lowest_stable_boundary",
    "seed_disagreements",
    "variant_of",
    "SECOND_ON_CIRCLE",
]

SECOND_ON_CIRCLE = 1e-5  # a located codimension-2 point has its second multiplier this near the circle


def _point_loss(ob, j) -> str:
    """How the stable response is lost at special point j of the orbit branch ``ob``."""
    found = special_criticality(ob, only=j).get(j)
    return found.verdict if hasattr(found, "verdict") else "undetermined"


def lowest_stable_boundary(curves, sigma, params: Params | None = None, variant: str = "paper"):
    """(Abar, kind, loss) of the lowest point at sigma of the ``curves`` that bounds stable
    period-1 orbits with wall contact, and how stability is lost there (the curve's ``boundary``:
    jump, soft, hard, undetermined; '' where not computed); (nan, "", "") when none. Each curve is
    read by linear interpolation between its points; with ``params`` (the chart's set), the
    crossing is then corrected on the curve's own system at sigma
    (:func:`~slosh_bif.orbits.codim2.corrected_at`; the interpolation kept where that fails; a
    curve of (8) on the impact model ``variant``'s map).
    Grazing curves of (8) are not read: there the number of impacts changes, not stability (on
    the Fig. 13 set the lowest is where the impact-free response first touches the walls).
    Which side of the point the stable orbits lie on is not asked here: :func:`critical_at` does."""
    return _lowest_reading(curves, sigma, params, variant)[:3]


def _lowest_reading(curves, sigma, params, variant="paper"):
    """:func:`lowest_stable_boundary` with the curve read, the crossing's orbit y0 (on the section
    of the segment's nearer point, for a curve of (8) whose section moves there), the segment's
    first point and its nearer point (None and -1 for none)."""
    best = (np.nan, "", "", None, None, -1, -1)
    for c in curves:
        if c.period_multiple != 1 or c.kind == "GR":
            continue  # a period-2 branch's curves bound period-2 orbits; a grazing is no loss of stability
        good = _bounds_stable(c)
        crossing = _lowest_crossing(c["sigma"], np.where(good, c["Abar"], np.nan), sigma)
        if crossing is None:
            continue
        value, i, t = crossing
        if params is not None:
            corrected = (
                corrected_at(c, params, sigma, i)
                if _smooth(c)
                else _impact_corrected_at(c, params, sigma, i, variant)
            )
            value = value if corrected is None else corrected
        if not value >= best[0]:
            near = i if t <= 0.5 else i + 1
            y0 = c.branch.x[i, :4] + t * (c.branch.x[i + 1, :4] - c.branch.x[i, :4])
            if not _smooth(c) and c["phase"][i] != c["phase"][i + 1]:
                y0 = c.branch.x[near, :4]
            best = (value, c.kind, str(curve_boundary(c)[1][near]), c, y0, i, near)
    return best


def critical_at(
    curves,
    sigma,
    params: Params,
    abar_min: float,
    shooting: ShootingSettings = SHOOTING,
    *,
    corrected: bool = True,
    sides: dict | None = None,
    variant: str = "paper",
    bottom=(),
):
    """(Abar, kind, loss, below) of the critical forcing at sigma read off a chart's ``curves``
    (of (9), or of the impact model ``variant`` of (8)): the lowest point that bounds stable
    orbits with wall contact (:func:`lowest_stable_boundary`; ``corrected`` False: the curve's
    interpolation, not corrected at sigma), unless stable orbits with contact lie just below it,
    in which case the lower end of those (:func:`~slosh_bif.orbits.stable_contact.stable_side_below`,
    :func:`~slosh_bif.orbits.impact.stable_impacts.stable_impacts_below`: a special point, a
    contact crossing or grazing, or NaN with ``below`` True where they reach ``abar_min``).

    Which side of a curve the stable orbits lie on changes only where the curve turns in sigma
    or at a codimension-2 point; between those it is asked once, at a computed point of the
    curve, and kept in ``sides`` (a dict shared by the calls over one chart's sigmas). Where a
    branch along the box's bottom (``bottom``, ``Chart.bottom``) is stable with contact at sigma,
    Abar_c lies below the box: NaN with ``below`` True, the curves not read."""
    if below_bottom(bottom, sigma):
        return np.nan, "", "", True
    value, kind, loss, curve, y0, i, near = _lowest_reading(
        curves, sigma, params if corrected else None, variant
    )
    if curve is None:
        return value, kind, loss, False
    probe = functools.partial(_probe, curve, abar_min=abar_min, shooting=shooting, variant=variant)
    if not _side_is_below(curve, i, params, probe, {} if sides is None else sides):
        return value, kind, loss, False
    at = params.replace(sigma=float(sigma), Abar=float(value))
    found = probe(at, y0, near)
    if _smooth(curve):
        end = stable_side_below(at, found, abar_min, shooting)
        return (value, kind, loss, False) if end is None else low_end_reading(end)
    from slosh_bif.orbits.impact.stable_impacts import stable_impacts_below

    end = stable_impacts_below(at, found, abar_min)
    return (value, kind, loss, False) if end is None else impact_low_end_reading(end, at)


def _impact_corrected_at(curve, params, sigma, i, variant):
    """:func:`~slosh_bif.orbits.impact.curves.impact_corrected_at` (numba loaded only here)."""
    from slosh_bif.orbits.impact.curves import impact_corrected_at

    return impact_corrected_at(curve, params, sigma, i, variant)


def _smooth(curve) -> bool:
    """Whether ``curve`` is of orbits of (9) (else of the impact model (8))."""
    return "(9)" in curve.branch.kind


def _probe(curve, at: Params, y, j: int, *, abar_min, shooting, variant):
    """The stable orbit with wall contact (with impacts, for (8)) just below the point ``at`` of
    ``curve`` from the orbit through y (on point j's section), or None."""
    fold = curve.kind == "LP"
    if _smooth(curve):
        return stable_orbit_below(at, y, abar_min, fold=fold, shooting=shooting)
    from slosh_bif.orbits.impact.stable_impacts import stable_impact_orbit_below

    phase = float(curve["phase"][j])
    return stable_impact_orbit_below(
        at, y, abar_min, phase=phase, symmetric=curve.kind == "BP", fold=fold, variant=variant
    )


def _side_is_below(curve, i, params, probe, sides) -> bool:
    """Whether the piece of ``curve`` holding point i has stable orbits with contact just below
    it, asked by ``probe`` at that point (or the next, where it is a codimension-2 point) and
    kept in ``sides`` by (curve, piece)."""
    s = curve["sigma"]
    codim2 = [sp.index for sp in curve.branch.special if sp.kind in CODIM2_KINDS]
    turns = np.r_[False, np.diff(np.sign(np.diff(s))) != 0]
    turns[[k for k in codim2 if 0 <= k < len(turns)]] = True
    key = (id(curve), int(np.count_nonzero(turns[: i + 1])))
    if key not in sides:
        j = i + 1 if i in codim2 and i + 1 < len(s) else i
        at = params.replace(sigma=float(s[j]), Abar=float(curve["Abar"][j]))
        sides[key] = probe(at, curve.branch.x[j, :4], j) is not None
    return sides[key]


def low_end_reading(end: LowEnd):
    """(Abar, kind, loss, below) of a lower end of stable orbits with contact."""
    if end.below_range:
        return np.nan, "", "", True
    if end.kind == "contact":
        return end.Abar, "contact", "none", False
    loss = _point_loss(end.branch, end.index) if end.index >= 0 else "undetermined"
    return end.Abar, end.kind, loss, False


def impact_low_end_reading(end, params: Params):
    """(Abar, kind, loss, below) of a lower end of stable orbits with impacts of (8) (an
    :class:`~slosh_bif.orbits.impact.stable_impacts.ImpactLowEnd` on a branch in Abar at
    ``params``' sigma)."""
    if end.below_range:
        return np.nan, "", "", True
    if end.index < 0:
        return end.Abar, end.kind, end.loss, False
    judged = impact_criticality(end.branch, params, symmetric=end.symmetric, only=(end.piece, end.index))
    found = judged[end.piece].get(end.index)
    return end.Abar, end.kind, found.verdict if hasattr(found, "verdict") else "undetermined", False


def exits_below(chart: Chart) -> list:
    """(curve index, kind, sigma, side) where a curve that bounds stable period-1 orbits with wall
    contact leaves the chart through its lowest Abar: beyond that sigma (below it for side -1,
    above for +1, the side away from the curve's points inside the box; 0 where it has none) the
    least stable forcing may lie below the box, which the box's curves cannot show."""
    if chart.second != "Abar":
        return []
    low = chart.abar_range[0]
    found = []
    for k, c in enumerate(chart.curves):
        if c.period_multiple != 1 or c.kind == "GR" or not len(c):
            continue
        at_edge = np.abs(c["Abar"] - low) <= 1e-9 * (1 + abs(low))
        inside = np.flatnonzero(~at_edge)
        for i in np.flatnonzero(at_edge & _bounds_stable(c)):
            sigma = float(c["sigma"][i])
            # a curve keeps its end point twice
            if any(e[0] == k and abs(e[2] - sigma) <= 1e-6 for e in found):
                continue
            near = inside[np.argmin(np.abs(inside - i))] if len(inside) else None
            side = 0 if near is None else -int(np.sign(c["sigma"][near] - sigma))
            found.append((k, c.kind, sigma, side))
    return found


def beyond_exit(exits, sigma) -> bool:
    """Whether sigma lies beyond one of ``exits`` (:func:`exits_below`), on the side away from its
    curve: there the least stable forcing may lie below the box."""
    return any(side != 0 and (sigma - at) * side > 0 for _, _, at, side in exits)


def _lowest_crossing(s, v, at):
    """(value, i, t) of the lowest linear interpolation of the curve (s, v) at s = at, over the
    segment (i, i + 1) at fraction t (segments with a non-finite end skipped; of equal values the
    first segment's); None where no segment spans ``at``."""
    s, v = np.asarray(s, dtype=float), np.asarray(v, dtype=float)
    a, b, va, vb = s[:-1], s[1:], v[:-1], v[1:]
    spans = (a != b) & (np.minimum(a, b) <= at) & (at <= np.maximum(a, b))
    (i,) = np.nonzero(spans & np.isfinite(va) & np.isfinite(vb))
    if not len(i):
        return None
    t = (at - a[i]) / (b[i] - a[i])
    values = va[i] + t * (vb[i] - va[i])
    k = int(np.argmin(values))
    return float(values[k]), int(i[k]), float(t[k])


def _bounds_stable(curve) -> np.ndarray:
    """Whether each point of ``curve`` bounds stable orbits with wall contact. At a codimension-2
    point a second multiplier is on the unit circle (BPLP, LPPD, ...), and the point's own flag is
    decided by rounding: there the flag of its stable neighbour holds, as the segment between them
    bounds stable orbits up to that point."""
    contact = curve["max_abs_w"] >= 1.0
    good = curve.branch.stable & contact
    second = curve["max_abs_multiplier"]
    for i in np.flatnonzero(contact & (np.abs(second - 1.0) < SECOND_ON_CIRCLE)):
        good[i] = bool(good[max(i - 1, 0)] or good[min(i + 1, len(good) - 1)])
    return good


def seed_disagreements(chart: Chart, rtol: float = 1e-4) -> list:
    """(sigma, read, found, below) at each seed of ``chart`` (its families in Abar at one sigma)
    whose stable orbits with wall contact (of (8): with impacts) reach lower than the curves read
    there: ``read`` the chart's Abar_c at that sigma (:func:`critical_at`), ``found`` the lower
    end on the seed's branches (NaN with ``below`` where they reach the box's bottom). The curves
    then miss a boundary (one no traced curve carries, or none at all: stable orbits with contact
    down to the bottom); a check the chart makes of itself, at no cost but the reading, and only
    of a complete chart (:func:`~.critical.critical_rows`)."""
    if not chart.reads_critical:
        return []
    low = chart.abar_range[0]
    variant = variant_of(chart)
    exits = exits_below(chart)
    found = []
    sides = {}
    for sigma, family in chart.seeds:
        ends = _seed_low_ends(family, low, smooth=variant is None)
        if not ends or beyond_exit(exits, sigma):
            continue  # a curve leaving through the box's bottom already marks the rows there
        read, _, _, read_below = critical_at(
            chart.curves,
            sigma,
            chart.params,
            low,
            sides=sides,
            variant=variant or "paper",
            bottom=chart.bottom,
        )
        below = any(e.below_range for e in ends)
        least = np.nan if below else min(e.Abar for e in ends)
        if read_below:
            continue
        if below or not least >= read * (1 - rtol):
            found.append((float(sigma), float(read), float(least), below))
    return found


def variant_of(chart: Chart) -> str | None:
    """The impact model's variant a chart's orbits are of ("paper" for (8), "corrected"), None for
    a chart of (9)."""
    if chart.orbits == "(9)":
        return None
    from slosh_bif.orbits.impact.problem import VARIANT_NAMES

    return next((k for k, name in VARIANT_NAMES.items() if name == chart.orbits), "paper")


def _seed_low_ends(family, low: float, smooth: bool) -> list:
    """The lower ends of the stable orbits with contact on a seed's period-1 branches: of (9)
    (:func:`~slosh_bif.orbits.stable_contact.family_low_ends`) or of (8) (each named branch's
    :func:`~slosh_bif.orbits.impact.stable_impacts.lowest_stable_impacts`)."""
    if smooth:
        return family_low_ends(family.branches, low)
    from slosh_bif.orbits.impact.stable_impacts import lowest_stable_impacts

    ends = (lowest_stable_impacts(nb.branch, low, nb.symmetric) for nb in family.branches)
    return [e for e in ends if e is not None]
