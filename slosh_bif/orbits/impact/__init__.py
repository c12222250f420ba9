"""Periodic orbits of the vibro-impact model (8) and of the corrected impact model: the
stroboscopic map with its saltation matrices (:mod:`~slosh_bif.orbits.impact.problem`),
their start orbits (:mod:`~slosh_bif.orbits.impact.starts`), branches continued in pieces
through grazing (:mod:`~slosh_bif.orbits.impact.branches`,
:mod:`~slosh_bif.orbits.impact.grazing_crossing`), switching at the pitchforks of symmetric
orbits and at period doublings (:mod:`~slosh_bif.orbits.impact.switching`), the map as the
orbit equations of the shared curve problems (:mod:`~slosh_bif.orbits.impact.strobe`), curves
of LP, PD, NS, BP (:mod:`~slosh_bif.orbits.impact.curves`) and of grazing
(:mod:`~slosh_bif.orbits.impact.grazing`), and their output. The Floquet tests, the curve
problems' base and the continuation engine are shared with the smooth model (9)."""

from slosh_bif.lazy import lazy_names

# public name -> the module that defines it, loaded on first use
_WHERE = {
    "ImpactOrbitProblem": "problem",
    "trace_impact_orbits": "branches",
    "settled_orbit": "branches",
    "impact_start": "starts",
    "ImpactStart": "starts",
    "ImpactBranch": "branches",
    "ImpactCurveSeed": "curves",
    "trace_impact_curve": "curves",
    "trace_grazing_curve": "curves",
    "ImpactStrobe": "strobe",
    "GrazingCurveProblem": "grazing",
}

__all__ = sorted(_WHERE)


__getattr__, __dir__ = lazy_names(__name__, _WHERE)
