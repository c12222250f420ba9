"""Two-parameter curves of orbit bifurcations of (9), traced from the special points of
one-parameter branches, and the result object that holds them (saved and loaded like a Branch).
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

from slosh_bif.continuation import Branch, ContinuationOptions, continuation
from slosh_bif.model.params import Params, real_pair
from slosh_bif.orbits.codim2.coefficients import boundary, curve_coefficients
from slosh_bif.orbits.codim2.minaug import MinAugCurveProblem
from slosh_bif.orbits.codim2.multiplier_curves import (
    FlipCurveProblem,
    FoldCurveProblem,
    PitchforkCurveProblem,
)
from slosh_bif.orbits.codim2.torus import TorusCurveProblem
from slosh_bif.orbits.floquet import floquet_multipliers
from slosh_bif.orbits.orbit_tools import orbit_measures
from slosh_bif.orbits.settings import LOCATE_TOL, SHOOTING, ShootingSettings
from slosh_bif.orbits.shooting import PARAMETERS, ShootingProblem

__all__ = [
    "BifurcationCurve",
    "CurveSeed",
    "trace_curve",
    "curve_problem",
    "CURVE_PROBLEMS",
    "CURVE_OPTIONS",
    "CODIM2_KINDS",
    "curve_boundary",
]

CURVE_PROBLEMS = {
    "LP": FoldCurveProblem,
    "PD": FlipCurveProblem,
    "BP": PitchforkCurveProblem,
    "NS": TorusCurveProblem,
}


def curve_problem(
    params: Params, kind: str, p1: str = "sigma", p2: str = "Abar", **options
) -> MinAugCurveProblem:
    """The curve problem of ``kind`` (LP, PD, BP or NS) in (p1, p2); ``options`` as for
    :class:`~slosh_bif.orbits.codim2.minaug.MinAugCurveProblem`."""
    if kind not in CURVE_PROBLEMS:
        raise ValueError(f"kind must be one of {', '.join(CURVE_PROBLEMS)}; got {kind!r}")
    return CURVE_PROBLEMS[kind](params, p1, p2, **options)


# Like the one-parameter orbit branches (the corrector's tolerance above the integration's
# rounding, codimension-2 points located to the same arclength); a turn of a curve in p1 is no
# bifurcation, so folds and branch points of the augmented system are not detected. Steps are
# capped at 0.25: longer ones leave more curves stalled at singular points of their systems, and
# the chart no faster.
CURVE_OPTIONS = ContinuationOptions(
    step=0.05,
    step_max=0.25,
    tol=1e-9,
    max_steps=2000,
    detect_folds=False,
    detect_branch_points=False,
    locate_tol=LOCATE_TOL,
)

CODIM2_KINDS = ("CP", "LPPD", "LPNS", "PDNS", "R1", "R2", "R3", "R4", "BPLP", "GPD", "DBP", "CH")


@dataclasses.dataclass(frozen=True)
class BifurcationCurve:
    """A curve of LP, PD, NS or BP points of periodic orbits in (p1, p2).

    ``curve["sigma"]``, ``curve["Abar"]`` (the two parameters), ``curve["A1"]`` and
    ``curve["max_abs_w"]`` (the orbit at each point) are arrays in curve order; ``branch`` is the
    continuation result (its special points are the codimension-2 points: CP, LPPD, LPNS, PDNS,
    R1-R4, BPLP; an NS curve ends at R1 and R2; ``curve["kappa"]``, ``curve["theta"]``: its pair's
    cos(theta) and theta; its ``stable`` column says whether the point bounds stable orbits: every multiplier
    but the critical one inside the unit circle); ``origin`` where it was started;
    ``period_multiple`` the orbits' period in units of 2pi (2 on a period-2 branch's curves).
    """

    kind: str
    p1: str
    p2: str
    branch: Branch
    measures: dict
    origin: str = ""
    period_multiple: int = 1

    def __len__(self):
        return len(self.branch)

    def __getitem__(self, name: str) -> np.ndarray:
        if name == self.p1:
            return self.branch.p
        if name == self.p2:
            return self._p2_of(self.branch.x.T)
        if name in ("theta", "kappa") and self.kind == "NS":
            last = self.branch.x[:, -1]  # kappa = cos(theta); curves saved before kappa hold theta itself
            if self.branch.names[-1] == name:
                return last
            return np.cos(last) if name == "kappa" else np.arccos(np.clip(last, -1.0, 1.0))
        if name in self.measures:
            return self.measures[name]
        raise KeyError(
            f"{name!r} is not a column of this curve; its columns are {self.p1}, {self.p2}, "
            f"{', '.join(self.measures)}"
        )

    @property
    def status(self) -> str:
        return self.branch.status

    def codim2_points(self) -> list:
        """(label, p1, p2) of each codimension-2 point, in curve order."""
        return [
            (sp.kind, float(sp.p), float(self._p2_of(sp.x)))
            for sp in self.branch.special
            if sp.kind in CODIM2_KINDS
        ]

    def _p2_of(self, x):
        return x[-2 if self.kind == "NS" else -1]  # kappa follows p2 on an NS curve

    def save(self, path) -> Path:
        """The branch's .npz with the curve's kind, parameters, origin and measures added."""
        meta = dict(
            kind=self.kind,
            p1=self.p1,
            p2=self.p2,
            origin=self.origin,
            measures=sorted(self.measures),
            period_multiple=self.period_multiple,
        )
        return self.branch.save(
            path,
            curve_meta=np.array(json.dumps(meta)),
            **{f"measure_{k}": v for k, v in self.measures.items()},
        )

    @classmethod
    def load(cls, path) -> "BifurcationCurve":
        branch = Branch.load(path)
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["curve_meta"]))
            measures = {k: data[f"measure_{k}"].copy() for k in meta["measures"]}
        return cls(
            meta["kind"],
            meta["p1"],
            meta["p2"],
            branch,
            measures,
            meta["origin"],
            int(meta.get("period_multiple", 1)),
        )


def curve_boundary(curve) -> tuple:
    """(coefficient, boundary) per point of ``curve`` (:func:`.coefficients.boundary`): a fold is
    a jump in either model (its coefficient NaN: its zero is the cusp CP, located by its own
    test); NaN and '' where no coefficient was computed (a curve saved without it)."""
    n = len(curve)
    if curve.kind == "LP":
        return np.full(n, np.nan), np.full(n, "jump", dtype="<U12")
    if "coefficient" not in curve.measures:
        return np.full(n, np.nan), np.full(n, "", dtype="<U12")
    coefficient = curve.measures["coefficient"]
    return coefficient, boundary(curve.kind, coefficient, curve.measures["judged"])


@dataclasses.dataclass(frozen=True)
class CurveSeed:
    """Where a curve starts: the special point of ``kind`` (LP, PD, NS or BP) at ``p`` on a
    branch of orbits continued in ``branch_param``, whose period is ``period_multiple`` forcing
    periods. ``x`` holds the orbit's states at the starts of its arcs (the settings' ``segments``
    per forcing period), or, from a symmetric branch (traced on the half-period map), the half
    period's. ``origin`` says where the point was found (it is kept with the curve)."""

    kind: str
    x: np.ndarray
    p: float
    branch_param: str = "sigma"
    period_multiple: int = 1
    origin: str = ""

    @classmethod
    def on(cls, orbit_branch, point, origin: str = "") -> "CurveSeed":
        """The seed at the special point ``point`` of the :class:`~slosh_bif.orbits.orbit_branch.OrbitBranch`
        ``orbit_branch``."""
        problem = orbit_branch.problem
        return cls(
            point.kind,
            problem.full_states(point.x),
            float(point.p),
            orbit_branch.branch.param,
            problem.period_multiple,
            origin,
        )


def trace_curve(
    params: Params,
    seed: CurveSeed,
    *,
    box: dict,
    shooting: ShootingSettings = SHOOTING,
    options: ContinuationOptions | None = None,
    callback=None,
) -> BifurcationCurve:
    """Trace the curve of ``seed.kind`` (LP, PD, NS or BP) through the seed's special point over
    ``box``, ``{p1: (low, high), p2: (low, high)}``, in both directions until it leaves the box,
    closes, or cannot be continued (its status says which). p1 and p2 are any two real fields of
    :class:`Params`; when the seed's branch parameter is neither, the curve lies in the plane
    where it is held at the seed's p (a sigma branch's fold continued in (Abar, eps)).
    ``shooting``: the arcs (``segments`` per forcing period), their integrator and tolerance
    (``atol`` is ``rtol`` / 100 on curves), and the samples of each point's measures;
    ``options``: the continuation's (:data:`CURVE_OPTIONS` by default; its parameter bounds are
    the box's). ``callback(p, x)`` is called at each accepted point.
    """
    kind, period_multiple = seed.kind, seed.period_multiple
    if kind not in CURVE_PROBLEMS:
        raise ValueError(f"kind must be one of {', '.join(CURVE_PROBLEMS)}; got {kind!r}")
    (p1, (lo1, hi1)), (p2, (lo2, hi2)) = read_box(box)
    segments = shooting.segments * period_multiple  # arcs of the orbit's whole period
    x = np.asarray(seed.x, dtype=float)
    if (
        period_multiple == 1 and segments % 2 == 0 and x.shape == (2 * segments,)
    ):  # a symmetric branch's half-period states
        x = np.concatenate([x, -x])
    if kind == "BP":  # the half-period map: the first half of the arcs of a symmetric orbit
        if segments % 2:
            raise ValueError(
                f"a BP curve starts from a symmetric orbit in an even number of arcs; got {segments}"
            )
        segments //= 2
        x = x[: 4 * segments]
    at = start_params(params, seed, box)
    span1 = hi1 - lo1
    if x.shape != (4 * segments,) or not np.all(np.isfinite(x)):
        raise ValueError(
            f"the start must be {4 * segments} finite numbers (the states at the starts of "
            f"{segments} arcs); got shape {x.shape}"
        )
    check = ShootingProblem(
        at,
        p1,
        segments=segments,
        period_multiple=period_multiple,
        symmetric=kind == "BP",
        backend=shooting.backend,
    )
    mu = start_multipliers(check, x, at, kind)
    setup = dict(
        segments=segments,
        period_multiple=period_multiple,
        rtol=shooting.rtol,
        atol=shooting.rtol * 1e-2,
        box=(lo1 - 0.5 * span1, hi1 + 0.5 * span1),
        p2_box=(lo2, hi2),
        backend=shooting.backend,
    )
    problem = curve_problem(at, kind, p1, p2, **setup)
    branch = continue_curve(problem, x, mu, at, box, options, callback)
    branch, coefficients = curve_coefficients(problem, branch)
    measures = {**_measures(problem, branch, shooting.points_per_2pi), **coefficients}
    return BifurcationCurve(kind, p1, p2, branch, measures, seed.origin, period_multiple)


def read_box(box) -> tuple:
    """((p1, (low, high)), (p2, (low, high))) of a curve's box, or a one-line error."""
    if not (isinstance(box, dict) and len(box) == 2 and all(len(r) == 2 for r in box.values())):
        raise ValueError(f"box must be {{p1: (low, high), p2: (low, high)}} for two parameters; got {box!r}")
    (p1, (lo1, hi1)), (p2, (lo2, hi2)) = box.items()
    real_pair((p1, p2))
    if not (lo1 < hi1 and lo2 < hi2):
        raise ValueError(f"empty box: {p1} in [{lo1}, {hi1}], {p2} in [{lo2}, {hi2}]")
    return (p1, (lo1, hi1)), (p2, (lo2, hi2))


def start_params(params: Params, seed, box) -> Params:
    """The parameter set at the seed (its branch parameter at the seed's value), checked inside the box."""
    if seed.branch_param not in PARAMETERS:
        raise ValueError(
            f"the start branch's parameter must be one of {', '.join(PARAMETERS)}; got {seed.branch_param!r}"
        )
    at = params.replace(**{seed.branch_param: float(seed.p)})
    (p1, (lo1, hi1)), (p2, (lo2, hi2)) = read_box(box)
    p1_0, p2_0 = float(getattr(at, p1)), float(getattr(at, p2))
    if not (lo1 <= p1_0 <= hi1 and lo2 <= p2_0 <= hi2):
        raise ValueError(f"the start point ({p1} = {p1_0:g}, {p2} = {p2_0:g}) lies outside the box")
    return at


def start_multipliers(orbits, x, at: Params, kind: str):
    """The multipliers of the orbit x at ``at`` (``orbits``: its orbit equations), or a one-line
    error, before any continuation, when it is not an orbit with the multiplier of ``kind`` (to
    1e-3: a located special point has it to the corrector's tolerance)."""
    arcs = orbits.arcs(x, at)
    mu = floquet_multipliers(arcs.mats) if np.all(np.isfinite(arcs.mats)) else np.full(4, np.nan + 0j)
    residual = np.linalg.norm(orbits.residual_of(x, arcs))
    critical = {
        "LP": np.min(np.abs(mu - 1)),
        "PD": np.min(np.abs(mu + 1)),
        "BP": np.min(np.abs(mu - 1)),
        "NS": np.min(np.abs(np.abs(mu[np.abs(mu.imag) > 1e-9]) - 1), initial=np.inf),
    }[kind]
    if not (residual < 1e-6 and critical < 1e-3):
        raise ValueError(
            f"the start is not a {kind} point of a periodic orbit (residual {residual:.2g}, "
            f"multipliers {np.round(mu, 4)})"
        )
    return mu


def continue_curve(
    problem: MinAugCurveProblem, x, mu, at: Params, box, options, callback, *, orient=None, tail=None
) -> Branch:
    """The curve of ``problem`` through the orbit x at ``at`` (multipliers ``mu``), over ``box``:
    both ways, or with ``orient`` (a vector in the curve's unknowns and p1) the way it points
    alone. ``tail``: the unknowns after the orbit's (p2, and an NS curve's cos theta) where they
    are known (a curve resumed from a point of its own)."""
    (p1, (lo1, hi1)), (p2, _) = read_box(box)
    if tail is not None:
        u0 = np.append(x, tail)
    else:
        u0 = np.append(x, float(getattr(at, p2)))
        if problem.kind == "NS":
            pair = mu[np.argmin(np.abs(np.abs(mu) - 1) + (np.abs(mu.imag) < 1e-9))]  # the pair on the circle
            u0 = np.append(u0, np.cos(np.angle(pair)))
    p1_0 = float(getattr(at, p1))
    problem.init_borders(u0, p1_0)
    opts = dataclasses.replace(options or CURVE_OPTIONS, p_min=lo1, p_max=hi1)
    if orient is not None:
        opts = dataclasses.replace(opts, direction="forward")
    return _once(continuation(problem, u0, p1_0, param=p1, options=opts, orient=orient, callback=callback))


def _once(branch: Branch) -> Branch:
    """The branch with each codimension-2 point once: where a curve creeps along a singular
    point its test functions flip sign at every step, and the same point is found again and
    again (seen: a cusp 20 times at one (sigma, Abar)): one per kind within 1e-4 in the parameters."""
    kept = []
    for sp in branch.special:
        if sp.kind in CODIM2_KINDS and any(
            q.kind == sp.kind and abs(q.p - sp.p) + np.max(np.abs(q.x[-2:] - sp.x[-2:])) < 1e-4 for q in kept
        ):
            continue
        kept.append(sp)
    return dataclasses.replace(branch, special=tuple(kept))


def _measures(problem: MinAugCurveProblem, branch: Branch, points_per_2pi: int) -> dict:
    rows = []
    n = len(problem.orbits.names)  # the orbit's states come first in each point
    critical = 2 if problem.kind == "NS" else 1  # multipliers on the unit circle come first
    for x, p in zip(branch.x, branch.p):
        single = _orbit_problem(problem, x, p)
        rows.append(orbit_measures(single, x[:n], p, points_per_2pi=points_per_2pi))
    out = {key: np.array([r[key] for r in rows]) for key in ("A1", "max_abs_X", "max_abs_w")} if rows else {}
    out["max_abs_multiplier"] = (
        np.max(np.abs(branch.eigenvalues[:, critical:]), axis=1) if len(branch) else np.array([])
    )
    return out


def _orbit_problem(problem: MinAugCurveProblem, x, p):
    """The one-parameter shooting problem over the whole period at the curve point's second
    parameter (for a BP curve, whose problem is the half-period map, twice its arcs)."""
    s = problem.orbits
    segments = 2 * s.segments if s.symmetric else s.segments
    return ShootingProblem(
        problem.params_at(x, p),
        problem.p1,
        segments=segments,
        period_multiple=s.period_multiple,
        rtol=s.rtol,
        atol=s.atol,
        backend=s.backend,
    )
