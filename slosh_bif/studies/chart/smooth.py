"""The (sigma, Abar) chart of the full model (9): the curves where its periodic orbits fold (LP),
double their period (PD), lose stability to a torus (NS) or break their symmetry (BP), traced
from every such point of the orbit families (side by side on several processes), and the full
model's critical forcing read off them, beside the slow flow's Abar_b of (46).

The second parameter may be any other real field of :class:`Params` (a box ``{"sigma": (lo, hi),
"beta": (lo, hi)}``: the (sigma, beta) chart); the critical forcing and the slow flow's Abar_b then
have no meaning on the chart and are left out.

What "critical" means on each model
-----------------------------------
* Slow flow (46): Abar_b(sigma) is the least forcing with a steady state on S+ at sigma, i.e.
  with a 1:1 resonant response of the reduced model (it may be unstable).
* Full model (9): Abar_c(sigma) is the least forcing at which the boundary of the region of
  *stable* period-1 orbits with wall contact (max |w| >= 1) lies at that sigma, read off the
  curves: a curve point bounds stable orbits when every multiplier but the critical one(s) is
  inside the unit circle. It is an envelope of curves, not a sweep.

  The LP, PD and NS curves all count (a BP curve bounds the symmetric orbits, not the stable
  ones: the asymmetric pair born there can be stable).

The two differ for three reasons: (46) is an asymptotic model (eps, 1/n); its steady states can
be unstable in (9) (the stable orbit is then elsewhere, or there is none: strongly modulated
response); and a stable orbit of (9) can lose stability through a period doubling or a torus
(NS) with (46) saying nothing about it.

:func:`critical_forcing_full` asks the same at one sigma (``answer critical-forcing`` and the
bench's ``critical_forcing.csv``): every family of orbits at that sigma, continued in Abar, and
the curves through their special points in a narrow sigma box; they cross that sigma at the
special points, so the envelope there is the lowest stable-bounding one.
"""

from __future__ import annotations

import time

from slosh_bif.continuation import ConvergenceError
from slosh_bif.model.params import Params
from slosh_bif.orbits.families import trace_orbits
from slosh_bif.orbits.scan import scan_families
from slosh_bif.orbits.settings import (
    BRANCHING,
    SHOOTING,
    BranchingSettings,
    ParameterRange,
    ShootingSettings,
)
from slosh_bif.orbits.starts import start_orbit
from slosh_bif.report.files import Resume
from slosh_bif.slowflow.critical import critical_curve
from slosh_bif.studies.chart.bottom import smooth_bottom
from slosh_bif.studies.chart.curves import (
    family_starts,
    torus_starts,
    trace_curves,
)
from slosh_bif.studies.chart.result import Chart, ChartSettings, check_box, where
from slosh_bif.studies.chart.seeds import regular_points, seed_branching, seed_points, uncovered_points

__all__ = ["bifurcation_chart"]


def bifurcation_chart(
    params: Params,
    state0,
    *,
    box: dict,
    shooting: ShootingSettings = SHOOTING,
    branching: BranchingSettings = BRANCHING,
    settings: ChartSettings | None = None,
    progress=None,
    resume: Resume | None = None,
) -> Chart:
    """Trace the family of orbits at the parameter set's Abar over sigma's range (from a
    simulation from ``state0``, switched as ``branching`` says) and the primary branch's orbits at
    ``settings.seeds`` values of sigma continued in Abar (with the pairs born at their pitchforks
    unless ``branching.switch`` is off), then the LP, PD, NS and BP curve through
    each of their special points (each curve once) in ``box``, ``{"sigma": (lo, hi), "Abar": (lo, hi)}``,
    on ``settings.workers`` processes (:class:`ChartSettings`), every orbit computed with ``shooting``.
    Interrupted while
    tracing curves, it returns those finished, ``status`` saying so. ``resume``: its ``done``,
    {start index: curve} of an earlier run with the same settings (which finds the same starts in
    the same order), and ``keep(i, curve)``, called as each curve finishes.

    The box's second name is the chart's second parameter: Abar, or any real field of
    :class:`Params` but sigma (the seeds are then continued in it, and there is no slow-flow
    critical curve). ``settings.model``: the slow flow whose Abar_b is drawn beside the curves."""
    if not (isinstance(box, dict) and len(box) == 2 and next(iter(box)) == "sigma"):
        raise ValueError(f'box must be {{"sigma": (lo, hi), NAME: (lo, hi)}}, sigma first; got {box!r}')
    (_, sigma_range), (second, abar_range) = box.items()
    check_box(params, sigma_range, abar_range, second)
    (s0, s1), (a0, a1) = sigma_range, abar_range
    box = {"sigma": (s0, s1), second: (a0, a1)}
    settings = settings or ChartSettings()
    workers, tasks = settings.slots, []
    resume = resume or Resume()
    say = progress or (lambda message: None)
    started = time.perf_counter()
    start = start_orbit(
        params, state0, (s0, s1), settle=settings.settle, segments=shooting.segments, backend=shooting.backend
    )
    family = trace_orbits(
        start.params,
        start.y0,
        shooting=shooting,
        branching=branching,
        progress=say,
        interval=ParameterRange(lo=s0, hi=s1),
    )
    say(f"orbit family: {len(family.branches)} branch(es), {sum(len(ob) for ob in family.branches)} points")
    starts = family_starts(family, params, box, shooting)
    # Folds and period doublings met when the forcing falls: the primary branch's orbits at
    # ``seeds`` values of sigma, each continued in Abar (the second parameter) over the box, from
    # regular points (see :func:`regular_points`).
    primary = family.branches[0].branch
    seeds = []
    for _, i in seed_points([(primary.p, regular_points(primary))], (s0, s1), settings.seeds):
        at = params.replace(sigma=float(primary.p[i]))
        if not a0 <= getattr(at, second) <= a1:
            continue
        try:
            down = trace_orbits(
                at,
                primary.x[i, :4],
                shooting=shooting,
                branching=seed_branching(branching),
                progress=say,
                interval=ParameterRange(name=second, lo=a0, hi=a1),
            )
        except (ConvergenceError, ValueError) as err:
            say(f"no {second} branch at sigma = {at.sigma:.4g}: {err}")
            continue
        starts += family_starts(down, at, box, shooting)
        seeds.append((float(at.sigma), down))
    bottom = smooth_bottom(seeds, params, (s0, s1), a0, say, shooting) if second == "Abar" else ()
    # Where the primary branch does not reach (an isola, a branch ending inside the box), the
    # orbits the family scan finds at sigmas there, continued in Abar: a torus curve of the
    # linear response at large sigma bounds stable orbits that no curve of the branch meets.
    gaps = uncovered_points([primary.p], (s0, s1), settings.seeds) if second == "Abar" else []
    for sigma in gaps:
        starts += _scan_seeds(params.replace(sigma=sigma), state0, box, shooting, branching, say)
    say(f"{len(starts)} special points to start curves from, {where(settings)}")
    if resume.done:
        say(f"{len(resume.done)} curves from an earlier run")
    curves, status, failures = trace_curves(
        starts, say, workers, resume.done, resume.keep, executor=settings.executor, tasks=tasks
    )
    met = list(torus_starts(curves, params, box, shooting)) if status == "complete" else []
    if met:  # one more round, not stored for a resume (it is found again from the curves)
        say(f"{len(met)} NS curves met by the fold and period-doubling curves, not yet traced")
        tori, status, more = trace_curves(met, say, workers, executor=settings.executor, tasks=tasks)
        curves, failures = curves + tori, failures + more
    slow = None
    if second == "Abar":
        try:
            slow = critical_curve(params, s0, s1, model=settings.model)
        except (RuntimeError, ValueError) as err:
            say(f"no slow-flow critical curve: {err}")
    return Chart(
        params,
        (s0, s1),
        (a0, a1),
        family,
        curves,
        slow,
        time.perf_counter() - started,
        status,
        second,
        failures,
        tasks=tuple(tasks),
        seeds=tuple(seeds),
        bottom=bottom,
    )


def _scan_seeds(at: Params, state0, box: dict, shooting, branching, say) -> list:
    """The curve starts on every family of orbits that the scan finds at ``at.sigma`` over the
    box's Abar (switched at pitchforks as a seed is: :func:`seed_branching`); none where it finds
    no orbit."""
    a0, a1 = box["Abar"]
    at = at.replace(Abar=min(max(at.Abar, a0), a1))
    try:
        found = scan_families(
            at,
            state0,
            shooting=shooting,
            branching=seed_branching(branching),
            interval=ParameterRange(name="Abar", lo=a0, hi=a1),
        )
    except (ConvergenceError, ValueError) as err:
        say(f"no orbits found at sigma = {at.sigma:.4g}, outside the primary branch: {err}")
        return []
    say(f"sigma = {at.sigma:.4g}, outside the primary branch: {len(found.branches)} branch(es) in Abar")
    return family_starts(found, at, box, shooting)
