"""The start orbits of ``shoot`` and ``compare`` from their options: a ``--guess`` at the set's
own sigma (or Abar) inside the continued range, and the orbit of the vibro-impact model (8) a
simulation settles on, else one from the slow flow's steady states of (46) over the range
(:func:`~slosh_bif.orbits.impact.starts.impact_start`)."""

from __future__ import annotations

from slosh_bif.cli.common import progress, state0_of

__all__ = ["check_start_inside", "impact_start_of"]


def check_start_inside(params, param, lo, hi) -> None:
    """The one-line error, before any work, for a --guess at the set's ``param`` outside [lo, hi]
    (without one a start outside the range comes from the slow flow's states inside it)."""
    p0 = getattr(params, param)
    if not lo <= p0 <= hi:
        option = "--sigma-min/--sigma-max" if param == "sigma" else "--abar-min/--abar-max"
        raise ValueError(
            f"--guess is an orbit at the set's {param} = {p0:g} (the preset's, the parameter file's or "
            f"--set), which must lie in the range [{lo:g}, {hi:g}] ({option})"
        )


def impact_start_of(args, params, variant, lo, hi):
    """(its parameter set, its state) of the orbit of (8) a simulation settles on (else from the
    slow flow's steady states over [lo, hi] of the continued parameter), or the one-line error
    with the options to change."""
    from slosh_bif.continuation import ConvergenceError
    from slosh_bif.orbits.impact.starts import impact_start

    try:
        start = impact_start(
            params,
            state0_of(args, params),
            periods=args.settle,
            p_range=(lo, hi),
            param=args.parameter,
            variant=variant,
        )
    except ConvergenceError as err:
        raise ConvergenceError(f"{err}; pass --guess X,Xd,w,wd or change --settle") from None
    value = getattr(start.params, args.parameter)
    progress(f"start orbit at {args.parameter} = {value:.5g}: {start.found_from}")
    return start.params, start.x
