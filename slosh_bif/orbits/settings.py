"""Settings of the orbit computations of (9), each a frozen object passed whole.

* :class:`ShootingSettings`: how one orbit is computed (multiple shooting in ``segments`` arcs
  per forcing period, the arcs' integrator and tolerances) and how finely its measures (A1,
  max |X|, max |w|) are sampled;
* :class:`BranchingSettings`: which branches a family follows off its first one (switching at
  the symmetry-breaking pitchforks and at period doublings, up to ``max_branches``);
* :class:`StartSettings`: where :func:`~slosh_bif.orbits.scan.scan_families` looks for starts;
* :class:`~slosh_bif.report.files.Resume` (in the report layer, shared with the sweeps): what an
  earlier, interrupted run finished, and where a run records its pieces.

Continuation's own step control is :class:`~slosh_bif.continuation.ContinuationOptions`. Each
object checks its fields on construction; an error names the field and what it may be.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from slosh_bif.orbits.shooting import BACKENDS

__all__ = [
    "ParameterRange",
    "ShootingSettings",
    "BranchingSettings",
    "StartSettings",
    "SHOOTING",
    "BRANCHING",
    "NO_SWITCHING",
    "STARTS",
    "LOCATE_TOL",
]

LOCATE_TOL = 1e-10
"""Arclength to which special points of the shooting problems of (9) are located (Brent on the
arclength, :mod:`slosh_bif.continuation.detection`). Their test functions carry the integration's
and the corrector's error, about 1e-11 in arclength on the Fig. 10 branches and more on period-2
and period-4 orbits: located closer, Brent only bisects in that noise (10.2 corrector solves a
located point over the Fig. 10 scan at 1e-13, 6.0 at this tolerance; the special points of
the Fig. 10 branch move by at most 2e-11 in sigma)."""


def _need(settings, ok: bool, name: str, allowed: str) -> None:
    if not ok:
        raise ValueError(
            f"{type(settings).__name__}.{name} must be {allowed}; got {getattr(settings, name)!r}"
        )


def _integer(value, low: int, high: float = float("inf")) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and low <= value <= high


@dataclasses.dataclass(frozen=True)
class ParameterRange:
    """The interval [lo, hi] of the real parameter ``name`` (sigma by default) a family is traced
    over: a one-line ValueError unless both ends are finite and lo < hi."""

    lo: float
    hi: float
    name: str = "sigma"

    def __post_init__(self):
        from slosh_bif.model.params import REAL_FIELDS

        if self.name not in REAL_FIELDS:
            raise ValueError(f"the parameter must be one of {', '.join(REAL_FIELDS)}; got {self.name!r}")
        for end in ("lo", "hi"):
            value = getattr(self, end)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
                raise ValueError(f"{self.name} range: {end} must be a number; got {value!r}")
            object.__setattr__(self, end, float(value))
        if not (math.isfinite(self.lo) and math.isfinite(self.hi) and self.lo < self.hi):
            raise ValueError(f"{self.name} range: need finite lo < hi; got [{self.lo}, {self.hi}]")


@dataclasses.dataclass(frozen=True)
class ShootingSettings:
    """How an orbit of (9) is computed and measured.

    Attributes
    ----------
    segments : int
        Shooting arcs per forcing period (a period-k orbit has k times as many; a symmetric
        orbit's half-period map half as many), 1 to 64.
    rtol, atol : float
        The arcs' integration tolerances.
    backend : str
        The arcs' integrator: "auto" (numba's compiled integrator when numba imports, else scipy's), "numba"
        or "scipy".
    points_per_2pi : int
        Samples per forcing period of each orbit's measures.
    """

    segments: int = 4
    rtol: float = 1e-10
    atol: float = 1e-12
    backend: str = "auto"
    points_per_2pi: int = 256

    def __post_init__(self):
        _need(self, _integer(self.segments, 1, 64), "segments", "an integer in [1, 64]")
        _need(
            self,
            isinstance(self.rtol, float | int) and 1e-14 <= self.rtol <= 1e-4,
            "rtol",
            "in [1e-14, 1e-4]",
        )
        _need(self, isinstance(self.atol, float | int) and 0 < self.atol <= 1e-4, "atol", "in (0, 1e-4]")
        _need(self, self.backend in BACKENDS, "backend", f"one of {', '.join(BACKENDS)}")
        _need(self, _integer(self.points_per_2pi, 8, 1 << 16), "points_per_2pi", "an integer in [8, 65536]")

    def replace(self, **changes) -> ShootingSettings:
        return dataclasses.replace(self, **changes)


@dataclasses.dataclass(frozen=True)
class BranchingSettings:
    """Which branches a family of orbits follows beyond its first.

    Attributes
    ----------
    switch : bool
        Switch onto the branches born at the first branch's pitchforks (and period doublings).
    doublings : bool
        Switch at period doublings too (followed up to period 8), not only at pitchforks.
    max_branches : int
        Branches per family at most, the first one included.
    """

    switch: bool = True
    doublings: bool = True
    max_branches: int = 6

    def __post_init__(self):
        _need(self, isinstance(self.switch, bool), "switch", "True or False")
        _need(self, isinstance(self.doublings, bool), "doublings", "True or False")
        _need(self, _integer(self.max_branches, 1), "max_branches", "an integer >= 1")


@dataclasses.dataclass(frozen=True)
class StartSettings:
    """Where a scan for every family looks for start orbits (see
    :func:`~slosh_bif.orbits.scan_starts.scan_starts`).

    Attributes
    ----------
    points : int
        Values of the parameter, evenly spread over the range, at which starts are simulated.
    settle : int
        Forcing periods each start simulation runs before Newton.
    random_starts : int
        Random initial states per value (drawn from numpy's generator seeded with ``seed``).
    seed : int
        The seed of those draws.
    """

    points: int = 5
    settle: int = 100
    random_starts: int = 4
    seed: int = 0

    def __post_init__(self):
        _need(self, _integer(self.points, 1), "points", "an integer >= 1 (scan values of the parameter)")
        _need(self, _integer(self.settle, 1), "settle", "an integer >= 1 (forcing periods)")
        _need(self, _integer(self.random_starts, 0), "random_starts", "an integer >= 0")
        _need(self, _integer(self.seed, 0), "seed", "an integer >= 0")


SHOOTING = ShootingSettings()
BRANCHING = BranchingSettings()
NO_SWITCHING = BranchingSettings(switch=False)
STARTS = StartSettings()
