"""Hard or soft: the normal-form coefficient of every LP, PD, NS and BP point of a family of
periodic orbits of the smooth model (9) (:func:`~slosh_bif.orbits.map_derivatives.criticality`
on the map over the orbit's period; a symmetric orbit's pitchfork on its half-period map), the
normal form's prediction of the motion born there (its size against the distance to the point,
:func:`~slosh_bif.continuation.normal_forms.growth_law`, with the rate at which the critical
multiplier crosses from :func:`~slosh_bif.orbits.map_derivatives.crossing_rate`), and the plain
sentence a user reads beside each point. A PD, NS or BP coefficient integrated by the variational
equations is settled under refinement (:func:`~slosh_bif.orbits.map_derivatives.settle`), the
verdict undetermined where it does not settle. The vibro-impact model (8) is judged the same way,
on its map's exact derivatives through the impacts
(:class:`~slosh_bif.orbits.impact.map_derivatives.ImpactMapDerivatives`)."""

from __future__ import annotations

import copy
import dataclasses
import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from slosh_bif.continuation.normal_forms import NormalForm, growth_law
from slosh_bif.orbits.map_derivatives import (
    FINE_RTOL,
    RTOL,
    FlowDerivatives,
    criticality,
    crossing_rate,
    settle,
)
from slosh_bif.orbits.switch_ahead import threads

__all__ = [
    "KINDS",
    "MAX_LINES",
    "Verdict",
    "judge",
    "special_criticality",
    "family_criticality",
    "impact_criticality",
    "phrases",
    "npz_arrays",
    "describe",
    "verdict_lines",
]

MAX_LINES = 30  # more judged points than this (a scan): counted in one line, each in branch.csv

KINDS = ("LP", "PD", "NS", "BP")
_NAMES = {"LP": "a", "PD": "b", "NS": "d", "BP": "b"}
_STATE = ("X", "X'", "w", "w'")
_AT_PARENT = "where the orbit meets its symmetric parent: see the parent's pitchfork"
# on a branch of period-m orbits (m > 1), the branch point where it is born or ends
_AT_PARENT_M = (
    "where the orbit meets its parent (at the parent's period doubling, or a symmetric orbit's "
    "pitchfork): see the parent's point"
)


@dataclasses.dataclass(frozen=True)
class Verdict:
    """A special point's criticality: its ``nf`` (:class:`NormalForm`), where it is (``param``,
    ``at``) and the motion born there: its state component ``component`` (the one the critical
    eigenvector moves most: X, X', w or w') on the map's section, at tau = ``section`` (0 for (9);
    for (8) the piece's section, where the coefficient and the growth are computed), differs from
    the parent orbit's by ``growth |param - at|^0.5`` (for a torus: is modulated by up to that), on
    the side ``sign(param - at) == side`` (NaN and 0 at a fold or where the point is undetermined);
    the parent's period is ``multiple`` forcing periods."""

    kind: str
    nf: NormalForm
    param: str
    at: float
    growth: float
    side: int
    component: str = "w"
    multiple: int = 1  # the parent orbit's period in forcing periods (a PD doubles it)
    section: float = 0.0  # the section's time, where the component is read

    @property
    def verdict(self) -> str:
        return self.nf.verdict

    @property
    def coefficient(self) -> float:
        return self.nf.coefficient


def _tangent_rate(sp):
    """d y0 / dp at the special point from the branch's unit tangent (None at a fold or where the
    tangent is not known)."""
    t = sp.tangent
    if t is None or not np.all(np.isfinite(t)) or abs(t[-1]) < 1e-8:
        return None
    return t[:4] / t[-1]


def judge(problem, sp, param: str):
    """The :class:`Verdict` of the special point ``sp`` (an LP, PD, NS or BP of a branch of
    ``problem``'s orbits continued in ``param``), or the reason it is not computed (a str)."""
    if sp.kind == "BP" and not problem.symmetric:
        return _at_parent(problem)
    period = 2 * math.pi * problem.period_multiple
    # (8)'s problem states its own (jets through its impacts); (9)'s variational equations
    derivatives = getattr(problem, "map_derivatives", FlowDerivatives)

    def at(rtol):
        return criticality(
            problem.params_at(sp.p),
            sp.x[:4],
            sp.kind,
            period=period,
            symmetric=problem.symmetric,
            rtol=rtol,
            derivatives=derivatives,
        )

    try:
        nf = at(RTOL)
    except ValueError as err:  # not integrated, or (8)'s map not smooth there
        return f"not computed: {err}"
    if nf.status == "ok" and sp.kind != "LP":  # a fold is a jump whatever a's size
        nf = _settled(nf, at, getattr(derivatives, "exact", False))
    dy = _tangent_rate(sp)
    slope = math.nan
    if dy is not None and nf.status == "ok" and sp.kind != "LP":
        slope = crossing_rate(
            problem.params_at, sp.p, sp.x[:4], dy, sp.kind, nf, period=period, derivatives=derivatives
        )
    K, side = growth_law(nf, slope)
    c = int(np.argmax(np.abs(nf.q)))
    scale = 2.0 * abs(nf.q[c]) if sp.kind == "NS" else abs(nf.q[c])  # x = 2 Re(z q) on a circle
    section = float(getattr(problem, "phase", 0.0))
    return Verdict(
        sp.kind, nf, param, float(sp.p), K * scale, side, _STATE[c], problem.period_multiple, section
    )


def _settled(nf, at, exact):
    """``nf`` (at :data:`~slosh_bif.orbits.map_derivatives.RTOL`), or the one at FINE_RTOL where
    the coefficient needed it (:func:`~slosh_bif.orbits.map_derivatives.settle`; ``exact``
    derivatives as they are), undetermined where it has not settled: its sign is not known from
    the integrations."""

    def quiet(rtol):
        try:
            return at(rtol)
        except ValueError:
            return None

    found, settled = settle(quiet, nf, exact=exact)
    if settled:
        return found
    status = (
        f"the coefficient has not settled under refinement ({_NAMES[nf.kind]} = {nf.coefficient:.3g} "
        f"at rtol {RTOL:g}, {found.coefficient:.3g} at {FINE_RTOL:g})"
    )
    return dataclasses.replace(found, verdict="undetermined", status=status)


def _at_parent(problem) -> str:
    """Why a branch point (or the pair's turn there) of ``problem``'s orbits is not judged."""
    return _AT_PARENT if problem.period_multiple == 1 else _AT_PARENT_M


def _plan(problem, branch, only=None) -> list:
    """``(index in branch.special, point to judge or None)`` over its LP, PD, NS and BP points; None:
    a fold that sits at a BP of an asymmetric branch, the pair's turn through its symmetric parent
    (the pitchfork seen from the pair), named so instead of judged as a fold."""
    pitchforks = [sp.p for sp in branch.special if sp.kind == "BP"] if not problem.symmetric else []
    plan = []
    for k, sp in enumerate(branch.special):
        if sp.kind not in KINDS or only not in (None, k):
            continue
        at_parent = sp.kind == "LP" and any(abs(sp.p - p) <= 1e-6 * (1 + abs(p)) for p in pitchforks)
        plan.append((k, None if at_parent else sp))
    return plan


def special_criticality(ob, *, only: int | None = None) -> dict:
    """``{index of the special point in ob.branch.special: Verdict or a reason (str)}`` for the
    LP, PD, NS and BP points of the orbit branch ``ob`` (an OrbitBranch of (9)); ``only``: that
    one point."""
    return _judged(ob.problem, ob.branch, only)


def _judged(problem, branch, only=None) -> dict:
    plan = _plan(problem, branch, only)
    return {k: _at_parent(problem) if sp is None else judge(problem, sp, branch.param) for k, sp in plan}


def family_criticality(branches) -> list:
    """:func:`special_criticality` of each orbit branch of ``branches``, the points judged side by
    side in threads (:func:`~slosh_bif.orbits.switch_ahead.threads`; the variational equations'
    integrations release the GIL), each on its own copy of its problem (whose caches are
    per-object): the verdicts of one point at a time."""
    plans = [_plan(ob.problem, ob.branch) for ob in branches]
    jobs = [(ob.problem, sp, ob.branch.param) for ob, plan in zip(branches, plans) for _, sp in plan]
    jobs = [job for job in jobs if job[1] is not None]
    count = min(threads(), len(jobs))
    if count > 1:
        with ThreadPoolExecutor(max_workers=count, thread_name_prefix="criticality") as pool:
            found = iter(list(pool.map(lambda job: judge(copy.copy(job[0]), *job[1:]), jobs)))
    else:
        found = iter([judge(*job) for job in jobs])
    return [
        {k: _at_parent(ob.problem) if sp is None else next(found) for k, sp in plan}
        for plan, ob in zip(plans, branches)
    ]


def impact_criticality(branch, params, *, symmetric: bool = False, only: tuple | None = None) -> list:
    """Per piece of the :class:`~slosh_bif.orbits.impact.branches.ImpactBranch` ``branch`` of (8)
    (traced on the half-period map when ``symmetric``), ``{index in the piece's special points:
    Verdict or a reason}`` as :func:`special_criticality` gives them for (9); ``only``: (piece,
    index) of one point, the other pieces left empty."""
    from slosh_bif.orbits.impact.problem import ImpactOrbitProblem  # numba only where (8) is judged

    out = []
    for k, piece in enumerate(branch.pieces):
        if only is not None and only[0] != k:
            out.append({})
            continue
        problem = ImpactOrbitProblem(
            params,
            piece.branch.param,
            symmetric=symmetric,
            phase=piece.phase,
            period_multiple=piece.period_multiple,
            variant=branch.variant,
        )
        out.append(_judged(problem, piece.branch, None if only is None else only[1]))
    return out


def phrases(per_piece, keep=None) -> list:
    """Per piece, ``{index: describe(verdict)}`` of :func:`impact_criticality`'s result; ``keep``:
    which verdicts or reasons to phrase (all by default)."""
    return [{k: describe(v) for k, v in found.items() if keep is None or keep(v)} for found in per_piece]


def npz_arrays(branch, verdicts: dict) -> dict:
    """The arrays a branch's ``.npz`` carries beside it (:meth:`Branch.save`'s extras), one entry a
    special point: ``special_verdict`` (soft, hard, jump, undetermined, or '' where not judged),
    ``special_coefficient``, ``special_growth`` and ``special_side`` (as in :class:`Verdict`; NaN,
    0 where not given) and ``special_criticality``, the phrase of :func:`describe`."""
    judged = [verdicts.get(k) for k in range(len(branch.special))]
    real = [v if isinstance(v, Verdict) else None for v in judged]
    return {
        "special_verdict": np.array([v.verdict if v else "" for v in real], dtype=str),
        "special_coefficient": np.array([v.coefficient if v else math.nan for v in real], dtype=float),
        "special_growth": np.array([v.growth if v else math.nan for v in real], dtype=float),
        "special_side": np.array([v.side if v else 0 for v in real], dtype=int),
        "special_criticality": np.array(["" if v is None else describe(v) for v in judged], dtype=str),
    }


def describe(verdict) -> str:
    """One phrase: ``soft (b = 4.57): the asymmetric pair is born stable where this orbit loses
    stability (sigma > -2.034), w at tau = 0 shifted by +-0.627 |sigma + 2.034|^0.5`` and the like."""
    if isinstance(verdict, str):
        return verdict
    nf, kind = verdict.nf, verdict.kind
    if nf.status != "ok":
        return f"undetermined: {nf.status}"
    value = f"{_NAMES[kind]} = {nf.coefficient:.3g}"
    if kind == "LP":
        return f"a jump ({value}): the branch folds back, with hysteresis"
    born, change = {
        "PD": (f"a period-{2 * verdict.multiple} orbit", "alternating by"),
        "NS": ("an invariant torus (a modulated response)", "modulated by up to"),
        "BP": ("the asymmetric pair", "shifted by"),
    }[kind]
    law = ""
    if verdict.side:
        name, at = verdict.param, verdict.at
        distance = f"{name} - {at:.4g}" if at >= 0 else f"{name} + {-at:.4g}"
        law = (
            f" ({name} {'>' if verdict.side > 0 else '<'} {at:.4g}), {verdict.component} at "
            f"{'tau = 0' if verdict.section == 0 else f'the section tau = {verdict.section:.4g}'} {change} "
            f"+-{verdict.growth:.3g} |{distance}|^0.5"
        )
    if nf.verdict == "soft":
        return f"soft ({value}): {born} is born stable where this orbit loses stability{law}"
    return f"hard ({value}): {born} is born unstable on the stable side{law}; the response jumps"


def verdict_lines(
    family, verdicts, *, every: bool = False, where: str = "branch.csv's 'criticality' column"
) -> list:
    """What ``shoot`` prints: a line a judged point (``LP at sigma = S on NAME: ...``), or, past
    :data:`MAX_LINES` points and unless ``every``, one line counting them (each is ``where``)."""
    lines = [
        f"  {ob.branch.special[k].kind} at {ob.branch.param} = {ob.branch.special[k].p:.6g} on {ob.name}: "
        + describe(v)
        for ob, found in zip(family.branches, verdicts)
        for k, v in found.items()
        if not isinstance(v, str)
    ]
    if len(lines) <= MAX_LINES or every:
        return lines
    soft, hard = (sum(f": {word}" in line for line in lines) for word in ("soft", "hard"))
    return [
        f"  {len(lines)} points judged ({soft} soft, {hard} hard, the rest jumps at folds or undetermined): "
        f"each in {where} (-v lists them here)"
    ]
