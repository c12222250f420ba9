"""Hard or soft: the normal-form coefficient of every LP, PD, NS and BP point of a family of
periodic orbits of the smooth model (9) (:func:`~slosh_bif.orbits.map_derivatives.criticality`
on the map over the orbit's period; a symmetric orbit's pitchfork on its half-period map), with
the plain sentence a user reads beside each point."""

from __future__ import annotations

import math

from slosh_bif.orbits.map_derivatives import criticality

__all__ = ["KINDS", "MAX_LINES", "special_criticality", "describe", "verdict_lines"]

MAX_LINES = 30  # more judged points than this (a scan): counted in one line, each in branch.csv

KINDS = ("LP", "PD", "NS", "BP")
_NAMES = {"LP": "a", "PD": "b", "NS": "d", "BP": "b"}


def special_criticality(ob) -> dict:
    """``{index of the special point in ob.branch.special: NormalForm or a reason (str)}`` for the
    LP, PD, NS and BP points of the orbit branch ``ob`` (an OrbitBranch of (9))."""
    problem, out = ob.problem, {}
    period = 2 * math.pi * problem.period_multiple
    for k, sp in enumerate(ob.branch.special):
        if sp.kind not in KINDS:
            continue
        if sp.kind == "BP" and not problem.symmetric:
            out[k] = "where the orbit meets its symmetric parent: see the parent's pitchfork"
            continue
        try:
            out[k] = criticality(
                problem.params_at(sp.p), sp.x[:4], sp.kind, period=period, symmetric=problem.symmetric
            )
        except ValueError as err:  # the variational equations could not be integrated
            out[k] = f"not computed: {err}"
    return out


def describe(kind: str, nf) -> str:
    """One phrase: ``soft (b = 4.57): a stable period-2 orbit grows beside it`` and the like."""
    if isinstance(nf, str):
        return nf
    if nf.status != "ok":
        return f"undetermined: {nf.status}"
    value = f"{_NAMES[kind]} = {nf.coefficient:.3g}"
    if kind == "LP":
        return f"a jump ({value}): the branch folds back, with hysteresis"
    born = {
        "PD": "a period-2 orbit",
        "NS": "an invariant torus (a modulated response)",
        "BP": "the asymmetric pair",
    }[kind]
    if nf.verdict == "soft":
        return f"soft ({value}): {born} is born stable where this orbit loses stability"
    return f"hard ({value}): {born} is born unstable on the stable side; the response jumps"


def verdict_lines(family, verdicts, *, every: bool = False) -> list:
    """What ``shoot`` prints: a line a judged point (``LP at sigma = S on NAME: ...``), or, past
    :data:`MAX_LINES` points and unless ``every``, one line counting them."""
    lines = [
        f"  {ob.branch.special[k].kind} at {ob.branch.param} = {ob.branch.special[k].p:.6g} on {ob.name}: "
        + describe(ob.branch.special[k].kind, nf)
        for ob, found in zip(family.branches, verdicts)
        for k, nf in found.items()
        if not isinstance(nf, str)
    ]
    if len(lines) <= MAX_LINES or every:
        return lines
    soft, hard = (sum(f": {word}" in line for line in lines) for word in ("soft", "hard"))
    return [
        f"  {len(lines)} points judged ({soft} soft, {hard} hard): each in branch.csv's 'criticality' "
        "column (-v lists them here)"
    ]
