"""Families of periodic orbits of the smooth model (9): a primary branch and what branches off it.

Model (9) is odd under the shift-reflection (X, X', w, w', tau) -> (-X, -X', -w, -w', tau + pi)
(the forcing cos tau changes sign over half a period). A 2pi-orbit is either *symmetric*
(y(tau + pi) = -y(tau)) or one of a mirror pair of *asymmetric* orbits; the pair is born at a
symmetry-breaking pitchfork of the symmetric branch. A symmetric branch is traced on the
half-period map (a symmetric :class:`~slosh_bif.orbits.shooting.ShootingProblem`: half the
integration), where the pitchfork is a regular multiplier -1 located like a period doubling; on
the 2pi problem it would be a branch point. A multiplier through -1 (PD) of an asymmetric orbit
gives birth to a *period-2* branch of 4pi-orbits.

:func:`trace_orbits` continues the branch through a starting orbit, then switches at each branch
point onto the crossing branch and at each period doubling onto the 4pi branch (traced by a
:class:`~slosh_bif.orbits.shooting.ShootingProblem` with twice the period, on which the PD is a branch
point), and keeps one member of each mirror pair. Every point carries its orbit's first-harmonic
amplitude A1, max |X|, max |w|, largest multiplier and Liouville check.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import warnings

import numpy as np

from slosh_bif.continuation import (
    ContinuationOptions,
    ConvergenceError,
    continuation,
)
from slosh_bif.continuation.branch import (
    BRANCH_POINT,
    PERIOD_DOUBLING,
    Branch,
)
from slosh_bif.model.params import Params
from slosh_bif.orbits.known import on_branch, on_known
from slosh_bif.orbits.orbit_branch import LIOUVILLE_TOL, OrbitBranch, OrbitFamily, unique_name
from slosh_bif.orbits.orbit_tools import orbit_at, orbit_measures
from slosh_bif.orbits.pitchforks import refine_pitchforks
from slosh_bif.orbits.settings import (
    BRANCHING,
    LOCATE_TOL,
    SHOOTING,
    BranchingSettings,
    ParameterRange,
    ShootingSettings,
)
from slosh_bif.orbits.shooting import MAX_PERIOD_MULTIPLE, PARAMETERS, ShootingProblem
from slosh_bif.orbits.switch_ahead import SwitchesAhead, threads
from slosh_bif.orbits.switching import (
    cut_where_it_rejoins,
    image_of_settled,
    meets_parent,
    point_counter,
    switched_branch,
    symmetric_parent,
    symmetrized_point,
)

__all__ = [
    "trace_orbits",
    "trace_new_family",
    "SHOOTING_OPTIONS",
]

# Shooting residuals carry the integration's rounding (~1e-13 at rtol 1e-10), so the corrector's
# tolerance sits above it; steps are capped so that orbits change little from one point to the next.
# Special points located to LOCATE_TOL; the Fig. 10 scan's longest branch (period 4) takes 3,545 steps.
SHOOTING_OPTIONS = ContinuationOptions(
    step=0.05, step_max=0.3, tol=1e-9, max_steps=5000, locate_tol=LOCATE_TOL
)


def _orbit_rows(problem: ShootingProblem, branch: Branch, points_per_2pi: int, check=None) -> list:
    """Each orbit's measures along ``branch`` (``check()`` before each orbit, if given: a trace
    ahead that is abandoned stops here)."""
    rows = []
    for x, p in zip(branch.x, branch.p):
        if check is not None:
            check()
        rows.append(orbit_measures(problem, x, p, points_per_2pi=points_per_2pi))
    return rows


def _measures(problem: ShootingProblem, branch: Branch, points_per_2pi: int, rows=None) -> dict:
    """The branch's per-point measures (its orbits', from ``rows`` where given), multipliers and
    Liouville check."""
    rows = rows or _orbit_rows(problem, branch, points_per_2pi)
    out = {key: np.array([r[key] for r in rows]) for key in rows[0]}
    out["max_abs_multiplier"] = np.max(np.abs(branch.eigenvalues), axis=1)
    out["liouville_error"] = branch.diagnostics.get("liouville_error")
    if out["liouville_error"] is None:  # a branch saved without its diagnostics: from the arcs again
        out["liouville_error"] = np.array([problem.liouville_error(x, p) for x, p in zip(branch.x, branch.p)])
    return out


def _checked(out: dict, name: str) -> dict:
    """``out`` (:func:`_measures`), after a warning if orbits fail Liouville's check."""
    bad = out["liouville_error"] > LIOUVILLE_TOL
    if np.any(bad):
        warnings.warn(
            f"{int(np.sum(bad))} of {len(bad)} orbits of the {name or 'traced'} branch fail "
            "Liouville's check (largest error "
            f"{np.nanmax(out['liouville_error']):.3g} > {LIOUVILLE_TOL:g}): their multipliers and "
            "stability are not reliable (flag 'liouville' in branch.csv)",
            RuntimeWarning,
            stacklevel=3,
        )
    return out


def _switch_job(parent: OrbitBranch, sp, param, opts, make_problem, points_per_2pi):
    """``run(say, trace)`` (:class:`~slosh_bif.orbits.switch_ahead.SwitchesAhead`): (problem,
    branch, name or None, its orbits' measures or None) switched onto at ``sp`` of ``parent`` (at the
    pitchfork of an asymmetric pair, its symmetric parent). Run ahead (``trace`` given), it
    traces on problems of its own and measures the branch's orbits too; in its turn, the family
    measures what it keeps."""

    def run(say, trace):
        if meets_parent(parent, sp):
            problem, new, name = symmetric_parent(sp, param, opts, make_problem, say)
        else:
            problem, new, name = switched_branch(
                parent, sp, param, opts, make_problem, say, own_problem=trace is not None
            )
        if trace is None:
            return problem, new, name, None
        return problem, new, name, _orbit_rows(copy.copy(problem), new, points_per_2pi, trace.check)

    return run


def _too_long(parent: OrbitBranch, sp) -> bool:
    """Whether switching at ``sp`` would pass the longest period followed."""
    return sp.kind == PERIOD_DOUBLING and 2 * parent.problem.period_multiple > MAX_PERIOD_MULTIPLE


def _ahead_order(current, queue) -> list:
    """The switches of ``queue`` worth tracing ahead while ``current`` is traced, likeliest first.
    A branch switched at a point of its parent most often meets the parent again at the parent's
    next point of that kind (an asymmetric pair between two pitchforks, a period-2 branch between
    two period doublings), which then leaves the queue: such presumed partners come last."""
    open_, first, last = set(), [], []
    for ob, s in [current, *queue]:
        pair = (ob.name, s.kind)
        (last if pair in open_ else first).append((ob, s))
        open_ ^= {pair}
    return [(ob, s) for ob, s in first[1:] + last if not _too_long(ob, s)]


def _check(params, param, p_min, p_max):
    if param not in PARAMETERS:
        raise ValueError(f"param must be one of {PARAMETERS}; got {param!r}")
    if not (np.isfinite(p_min) and np.isfinite(p_max) and p_min < p_max):
        raise ValueError(f"need finite p_min < p_max; got [{p_min}, {p_max}]")
    p0 = getattr(params, param)
    if not p_min <= p0 <= p_max:
        raise ValueError(f"{param} = {p0} of the start orbit lies outside [{p_min}, {p_max}]")


def _not_isolated(problem, x0, p0, multipliers, params) -> str:
    """Why a start orbit with a multiplier at +1 cannot be continued (empty when it has none): it
    is not isolated; at a small beta an orbit clear of the walls leaves the particle nearly free,
    held only by the wall force chi w^(2n+1) of (9)."""
    gap = float(np.min(np.abs(np.asarray(multipliers) - 1)))
    if not gap < 1e-3:
        return ""
    why = f"; the start orbit has a Floquet multiplier at +1 (|mu - 1| = {gap:.1g}): it is (nearly) not"
    why += " isolated"
    reach = orbit_measures(problem, x0, p0, points_per_2pi=64)["max_abs_w"]
    if reach < 1:
        why += (
            f" (it stays clear of the walls, max |w| = {reach:.2g}, where beta = {params.beta:g} and the"
            " wall force chi w^(2n+1) barely hold the particle); start where the response reaches the"
            " walls: a larger Abar, or sigma nearer resonance"
        )
    return why


def _primary(
    params, y0, param, opts, make_problem, points_per_2pi, say, known=(), found_from=""
) -> OrbitBranch:
    """The branch through the orbit near y0, named by its symmetry (a symmetric one traced on the
    half-period map)."""
    problem = make_problem(1)
    p0 = getattr(params, param)
    start = orbit_at(problem, problem.initial_states(y0), p0, tol=opts.tol)
    if not start.converged:
        raise ConvergenceError(f"no periodic orbit near the guess at {param} = {p0}: {start.message}")
    x0 = problem.initial_states(start.y0)
    symmetric = orbit_measures(problem, x0, p0, points_per_2pi=points_per_2pi)["symmetry_defect"] < 1e-6
    kind = "symmetric" if symmetric else "asymmetric"
    name = unique_name(kind, known)
    if symmetric and problem.segments % 2 == 0:
        problem = make_problem(1, symmetric=True)
        x0 = x0[: 4 * problem.segments]
    try:
        branch = continuation(
            problem, x0, p0, param=param, options=opts, callback=point_counter(say, name, param)
        )
    except ConvergenceError as err:
        raise ConvergenceError(f"{err}{_not_isolated(problem, x0, p0, start.multipliers, params)}") from None
    if symmetric and not problem.symmetric:
        branch = refine_pitchforks(problem, branch)
    say(f"{name}: {len(branch)} points, {len(branch.special)} special points")
    return OrbitBranch(
        name,
        problem,
        branch,
        _checked(_measures(problem, branch, points_per_2pi), name),
        kind=kind,
        found_from=found_from,
    )


def trace_orbits(
    params: Params,
    y0,
    *,
    interval: ParameterRange,
    shooting: ShootingSettings = SHOOTING,
    branching: BranchingSettings = BRANCHING,
    options: ContinuationOptions | None = None,
    progress=None,
) -> OrbitFamily:
    """Continue the 2pi-orbit through the guess y0 (at the preset's value of the parameter) over
    ``interval``, then the branches born at its branch points and period doublings.

    ``shooting``: how each orbit is computed and measured; ``branching``: which branches are
    followed beyond the first (``NO_SWITCHING``: the first alone); ``options``: the
    continuation's step control (:data:`SHOOTING_OPTIONS` by default). ``progress(message)`` is
    called as the work goes on (one call per accepted point and per branch). Period doublings are
    followed up to period 8. The next switches are traced ahead in threads
    (:mod:`~slosh_bif.orbits.switch_ahead`); the family does not depend on how many. Raises
    :class:`ConvergenceError` when no orbit is found near y0.
    """
    return trace_new_family(
        params,
        y0,
        (),
        interval=interval,
        shooting=shooting,
        branching=branching,
        options=options,
        progress=progress,
    )


def trace_new_family(
    params: Params,
    y0,
    known,
    *,
    interval: ParameterRange,
    shooting: ShootingSettings,
    branching: BranchingSettings,
    options: ContinuationOptions | None,
    progress=None,
    found_from: str = "",
    asked: list | None = None,
) -> OrbitFamily:
    """:func:`trace_orbits` beside the OrbitBranches ``known`` already traced (by other starts of
    a scan): a switched branch on one of them (or its mirror image) is not traced again, and
    names stay unique among them. ``found_from`` describes the start. ``asked``: a list that gets
    each question put to ``known`` (:func:`~slosh_bif.orbits.known.on_known`), so that a family
    traced beside other starts can be checked against the branches known when its turn comes
    (:func:`~slosh_bif.orbits.known.answers_hold`)."""
    param, p_min, p_max = interval.name, interval.lo, interval.hi
    _check(params, param, p_min, p_max)
    opts = dataclasses.replace(options or SHOOTING_OPTIONS, p_min=p_min, p_max=p_max)
    segments, points_per_2pi = shooting.segments, shooting.points_per_2pi
    say = progress or (lambda message: None)

    span = p_max - p_min
    box = (p_min - 0.5 * span, p_max + 0.5 * span)  # corrector iterates stay near the requested range

    def make_problem(
        multiple, symmetric=False
    ):  # a period of multiple * 2 pi, in as many times the arcs (half for the half period)
        arcs = segments // 2 if symmetric else multiple * segments
        return ShootingProblem(
            params,
            param,
            segments=arcs,
            period_multiple=multiple,
            rtol=shooting.rtol,
            atol=shooting.atol,
            backend=shooting.backend,
            box=box,
            symmetric=symmetric,
        )

    family = [_primary(params, y0, param, opts, make_problem, points_per_2pi, say, known, found_from)]
    if not branching.switch:
        return OrbitFamily(params, param, family)
    switched = (BRANCH_POINT, PERIOD_DOUBLING) if branching.doublings else (BRANCH_POINT,)
    queue = [(family[0], s) for s in family[0].branch.special if s.kind in switched]
    # A family started on an asymmetric orbit meets the symmetric parent first: its branch carries
    # the response away from the pair's interval, before the pair's period doublings.
    queue.sort(key=lambda item: not meets_parent(*item))
    job = functools.partial(
        _switch_job, param=param, opts=opts, make_problem=make_problem, points_per_2pi=points_per_2pi
    )
    settled = []  # (branch, point) switched at or met again
    with SwitchesAhead(threads() if family[0].problem.backend == "numba" else 1, say) as switches:
        while queue and len(family) < branching.max_branches:
            parent, sp = queue.pop(0)
            origin = f"{sp.kind} at {param} = {sp.p:.6g} on the {parent.name} branch"
            if _too_long(parent, sp):
                say(f"not switched at {origin}: the cascade is followed up to period {MAX_PERIOD_MULTIPLE}")
                continue
            twin = image_of_settled(parent, sp, settled)
            if twin is not None:
                say(
                    f"not switched at {origin}: its orbit is an image of the one at {twin[1].kind} "
                    f"{param} = {twin[1].p:.6g} on the {twin[0].name} branch (switched at or met already)"
                )
                continue
            settled.append((parent, sp))
            parent_of_pair = meets_parent(parent, sp)
            u = symmetrized_point(sp) if parent_of_pair else None
            tol_u = 1e-5 * (1 + np.linalg.norm(u)) if parent_of_pair else 0.0
            if parent_of_pair and (
                on_known(u, tol_u, known, asked, kind="symmetric")
                or any(on_branch(u, ob, tol_u) for ob in family if ob.kind == "symmetric")
            ):
                continue  # the pair meets its symmetric parent, traced already
            fresh = [item for item in queue if image_of_settled(*item, settled) is None]
            upcoming = [((ob.name, s.index), job(ob, s)) for ob, s in _ahead_order((parent, sp), fresh)]
            try:
                problem, new, kind_name, rows = switches.take(
                    (parent.name, sp.index), job(parent, sp), upcoming
                )
            except (ConvergenceError, np.linalg.LinAlgError) as err:
                say(f"no branch switched at {origin}: {err}")
                continue
            new, met = (new, None) if parent_of_pair else cut_where_it_rejoins(new, problem, parent, queue)
            if met is not None:
                settled.append((parent, met))
                say(
                    f"the new branch meets the {parent.name} branch again at its {met.kind} "
                    f"{param} = {met.p:.6g}"
                )
            first = np.append(new.x[min(1, len(new) - 1)], new.p[min(1, len(new) - 1)])
            tol_first = 1e-5 * (1 + np.linalg.norm(first))
            if on_known(first, tol_first, known, asked) or any(
                on_branch(first, ob, tol_first) for ob in family
            ):
                say(f"the branch at {origin} is one already traced")
                continue
            rows = rows and rows[: len(new)]  # measured ahead, before a cut
            measures = _checked(_measures(problem, new, points_per_2pi, rows), kind_name or "switched")
            if kind_name is None:
                kind_name = "symmetric" if np.median(measures["symmetry_defect"]) < 1e-6 else "asymmetric"
                if kind_name == "symmetric":
                    new = refine_pitchforks(problem, new)
            ob = OrbitBranch(
                unique_name(kind_name, [*known, *family]), problem, new, measures, origin, kind=kind_name
            )
            family.append(ob)
            say(f"{ob.name} ({origin}): {len(new)} points")
            # Not the start (the parent's point) and not a cut end (where it met the parent again); a
            # symmetric parent, traced both ways, not at its start.
            queue += [
                (ob, s)
                for s in new.special
                if s.kind in switched
                and 1 < s.index < len(new) - (met is not None)
                and not (parent_of_pair and abs(s.p - sp.p) <= 1e-6 * (1 + abs(sp.p)))
            ]
    if queue:  # the cap, not the family, ended the switching: say where it was not tried
        left = ", ".join(f"{s.kind} {param} = {s.p:.6g} on {ob.name}" for ob, s in queue[:4])
        say(
            f"not switched at {len(queue)} more ({left}{', ...' if len(queue) > 4 else ''}): "
            f"the family has its {branching.max_branches} branches (max_branches, --max-branches)"
        )
    return OrbitFamily(params, param, family)
