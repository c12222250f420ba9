"""The branches along a chart's lowest Abar: where a seed's stable orbits with wall contact (of
(8): with impacts) reach the box's bottom, the orbit there is continued in sigma at that Abar, and
wherever it stays stable with contact the critical forcing Abar_c (the counterpart of the slow
flow's Abar_b of (46)) lies below the box. Between the seeds no curve need say so: a response
stable with contact over the whole box has no bifurcation to bound it."""

from __future__ import annotations

import numpy as np

from slosh_bif.model.params import Params
from slosh_bif.orbits.settings import SHOOTING
from slosh_bif.orbits.stable_contact import along_bottom, family_low_ends

__all__ = ["below_bottom", "smooth_bottom", "impact_bottom"]


def below_bottom(bottom, sigma) -> bool:
    """Whether one of the branches along the box's lowest Abar (``Chart.bottom``: (sigma, good)
    pairs) has a stable orbit with wall contact at sigma, between two good points: Abar_c lies
    below the box there."""
    for s, good in bottom:
        a, b = s[:-1], s[1:]
        spans = (np.minimum(a, b) <= sigma) & (sigma <= np.maximum(a, b)) & good[:-1] & good[1:]
        if spans.any():
            return True
    return False


def smooth_bottom(seeds, params: Params, sigma_range, a0: float, say, shooting=SHOOTING) -> tuple:
    """The branches of (9) in sigma along the box's lowest Abar ``a0`` from each seed ((sigma,
    family in Abar)) whose stable orbits with wall contact reach it
    (:func:`~slosh_bif.orbits.stable_contact.along_bottom`); a seed on one already traced is
    skipped."""
    bottom = []
    for sigma, family in seeds:
        for end in family_low_ends(family.branches, a0):
            if not end.below_range or below_bottom(bottom, sigma):
                continue
            found = along_bottom(end.branch, params.replace(sigma=sigma), a0, sigma_range, shooting)
            if found is not None:
                bottom.append(found)
                _said(say, "wall contact", a0, sigma)
    return tuple(bottom)


def impact_bottom(seeds, params: Params, sigma_range, a0: float, say) -> tuple:
    """The branches of (8) in sigma along the box's lowest Abar ``a0`` from each seed ((sigma,
    ImpactFamily in Abar)) whose stable orbits with impacts reach it
    (:func:`~slosh_bif.orbits.impact.stable_impacts.impacts_along_bottom`); a seed on one
    already traced is skipped."""
    from slosh_bif.orbits.impact.stable_impacts import impacts_along_bottom, lowest_stable_impacts

    bottom = []
    for sigma, family in seeds:
        for nb in family.branches:
            end = lowest_stable_impacts(nb.branch, a0, nb.symmetric)
            if end is None or not end.below_range or below_bottom(bottom, sigma):
                continue
            found = impacts_along_bottom(
                nb.branch, params.replace(sigma=sigma), a0, sigma_range, nb.symmetric
            )
            if found:
                bottom += found
                _said(say, "impacts", a0, sigma)
    return tuple(bottom)


def _said(say, what: str, a0: float, sigma: float) -> None:
    say(f"stable orbits with {what} reach Abar = {a0:g} at sigma = {sigma:.4g}: followed in sigma along it")
