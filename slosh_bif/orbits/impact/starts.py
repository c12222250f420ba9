"""Start orbits for the families of the vibro-impact model (8): the orbit a simulation of (8)
settles on at the set's own sigma, or, where it settles on none there (a strongly modulated
response, a run stopped), the one a simulation from the slow flow's motion (25), (29), (35) on a
stable steady state of (46) elsewhere in the range settles on, as the starts of (9) do
(:func:`slosh_bif.orbits.starts.start_orbit`)."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from slosh_bif.continuation import ConvergenceError
from slosh_bif.model.params import Params
from slosh_bif.orbits.impact.branches import settled_orbit
from slosh_bif.orbits.impact.problem import VARIANT_NAMES

__all__ = ["ImpactStart", "impact_start", "GUESSES"]

GUESSES = 6  # stable steady states of (46) tried, from the range's ends inward


@dataclasses.dataclass(frozen=True)
class ImpactStart:
    """An orbit of (8) to start a family from: its parameter set (sigma where it was found), its
    state at tau = 0 and how it was found."""

    params: Params
    x: np.ndarray
    found_from: str


def impact_start(
    params: Params,
    state0,
    *,
    periods: int,
    p_range: tuple | None = None,
    param: str = "sigma",
    variant: str = "paper",
) -> ImpactStart:
    """The orbit of (8) (``variant``) that a ``periods``-period simulation from ``state0`` at
    ``params`` settles on (:func:`settled_orbit`). Where it settles on none and ``p_range`` (lo,
    hi) of ``param`` (sigma, or Abar at the set's sigma) is given: the orbit a ``periods``-period
    simulation from the slow flow's motion on a stable steady state of (46) in that range settles on, up to
    :data:`GUESSES` states tried from the ends inward (far from the peak the slow flow is
    closest to the full models); only those where the set's ``param`` lies outside ``p_range``.
    Raises :class:`ConvergenceError` saying what was tried."""
    p0 = getattr(params, param)
    if p_range is not None and not p_range[0] <= p0 <= p_range[1]:
        why = f"the set's {param} = {p0:g} lies outside [{p_range[0]:g}, {p_range[1]:g}]"
    else:
        try:
            x = settled_orbit(params, state0, periods=periods, variant=variant)
            return ImpactStart(
                params, x, f"Newton from the strobe of a simulation settled at sigma = {params.sigma:g}"
            )
        except ConvergenceError as err:
            if p_range is None:
                raise
            why = str(err)
    from slosh_bif.orbits.starts import slow_flow_motion, stable_steady_states

    with warnings.catch_warnings():  # a guess: the simulation and Newton decide, not (46)'s accuracy
        warnings.filterwarnings("ignore", message="slow flow outside its checked range")
        try:
            guesses = stable_steady_states(params, *p_range, tries=GUESSES, param=param)
            states = [slow_flow_motion(at, A, psi, 0.0) for at, A, psi in guesses]
        except (ValueError, ConvergenceError):  # no steady state of (46) to start from
            guesses = states = []
    for (at, A, _), y0 in zip(guesses, states):
        y0[2] = np.clip(y0[2], -1 + 1e-9, 1 - 1e-9)  # the particle inside the walls
        try:
            x = settled_orbit(at, y0, periods=periods, tries=1, variant=variant)
        except ConvergenceError:
            continue
        return ImpactStart(
            at,
            x,
            f"a {periods}-period simulation from the slow flow's motion on the stable steady state "
            f"A = {A:.6g} of (46) at {param} = {getattr(at, param):.6g} (at {param} = "
            f"{getattr(params, param):g}: {why})",
        )
    where = f"in {param} in [{p_range[0]:g}, {p_range[1]:g}]"
    raise ConvergenceError(
        f"{why}; nor from {len(guesses)} stable steady states of (46) {where}"
        if guesses
        else f"{why}; and (46) has no stable steady state {where} to start {VARIANT_NAMES[variant]} from"
    )
