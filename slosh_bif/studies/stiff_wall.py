"""The limit of a stiff wall, orbit by orbit: (9)'s periodic orbits against the corrected impact model's
and (8)'s as the wall exponent n grows (eqs. 8, 9, 10, 21).

At each (sigma, n) the attracting orbit of (9) that a simulation from ``state0`` settles on is
found by shooting; the orbits of the two impact models are then found by Newton on their
stroboscopic maps from (9)'s state at tau = 0 (the same orbit, checked by the impact count), and
the first-harmonic amplitudes A1 compared:

* the corrected impact model is (9) with its wall replaced by the wall's own measured law
  (:mod:`slosh_bif.flows.impact.band`): what separates it from (9) is only the contact's finite
  duration, which must vanish as n grows;
* (8) as the paper states it differs from the corrected model by its first-order coefficients
  (the expansion of (9)'s in eps, off by O(eps^2 sigma)), the restitution of (21) and the rigid
  wall at |w| = 1: its difference to (9) does not vanish with n.

The rate is the least-squares slope of log(error) against log(n) over the n with an error above
rounding (1e-9).

What makes up (8)'s difference (:func:`simplifications`): the four impact models with either
flights ((8)'s first-order coefficients or (9)'s exact linear part) and either wall ((21) at
|w| = 1, or the measured law), each simulated from (9)'s orbit until it repeats.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation.corrector import newton_solve
from slosh_bif.flows.impact.flow import ImpactFlow
from slosh_bif.model.params import Params
from slosh_bif.orbits.impact.output import first_harmonic, orbit_measures
from slosh_bif.orbits.impact.problem import ImpactOrbitProblem
from slosh_bif.orbits.starts import settle_and_shoot

__all__ = [
    "StiffWallPoint",
    "stiff_wall_points",
    "convergence_rate",
    "markdown_table",
    "Simplifications",
    "simplifications",
    "simplifications_table",
]

ROUNDING = 1e-9  # errors below this are rounding, not the contact's


@dataclasses.dataclass(frozen=True)
class StiffWallPoint:
    """One (sigma, n): A1 of (9)'s orbit and of the two impact models' (NaN where not found),
    their impact counts and the relative differences to (9); ``status`` says what was not found."""

    sigma: float
    n: int
    smooth: float
    corrected: float
    paper: float
    impacts: int
    status: str

    @property
    def corrected_error(self) -> float:
        return abs(self.corrected - self.smooth) / self.smooth

    @property
    def paper_error(self) -> float:
        return abs(self.paper - self.smooth) / self.smooth


def _impact_orbit(params: Params, variant: str, y0, sigma):
    """(A1, impact count) of the orbit of the impact model ``variant`` by Newton from y0, or None."""
    problem = ImpactOrbitProblem(params, variant=variant)
    x = np.array(y0, dtype=float)
    if problem.wall_distance(x, sigma) < 0:  # (9)'s particle inside its wall at tau = 0
        x[2] = np.sign(x[2]) * (abs(x[2]) + problem.wall_distance(x, sigma) - 1e-3)
    run = newton_solve(problem, x, sigma, tol=1e-12)
    if not (run.converged and problem.in_domain(run.x, sigma)):
        return None
    return orbit_measures(problem, run.x, sigma)["A1"], len(problem.evaluate(run.x, sigma).impacts)


def stiff_wall_points(params: Params, sigmas, ns, state0=(0.0, 0.0, 0.0, 0.5), progress=None) -> list:
    """A :class:`StiffWallPoint` per (sigma, n); ``progress(point)`` hears of each."""
    sigmas, ns = [float(s) for s in sigmas], [int(n) for n in ns]
    if not sigmas or not ns:
        raise ValueError("need at least one sigma and one n")
    for n in ns:
        params.replace(n=n)  # a one-line error for an inadmissible n (with the set's pbar) before any work
    points = []
    for sigma in sigmas:
        for n in ns:
            at = params.replace(sigma=sigma, n=n)
            orbit, smooth = settle_and_shoot(at, state0, first=150, every=50, most=400)
            found = {"corrected": None, "paper": None}
            if np.isfinite(smooth):
                for variant in found:
                    found[variant] = _impact_orbit(at, variant, orbit.y0, sigma)
            counts = {v[1] for v in found.values() if v is not None}
            missing = [
                name
                for name, v in (("(9)", smooth if np.isfinite(smooth) else None), *found.items())
                if v is None
            ]
            if missing:
                status = f"not found: {', '.join(missing)}"
            else:
                status = "ok" if len(counts) == 1 else "the impact models' orbits differ in impacts"
            point = StiffWallPoint(
                sigma,
                n,
                float(smooth),
                found["corrected"][0] if found["corrected"] else np.nan,
                found["paper"][0] if found["paper"] else np.nan,
                found["corrected"][1] if found["corrected"] else 0,
                status,
            )
            points.append(point)
            if progress is not None:
                progress(point)
    return points


def convergence_rate(points, sigma) -> float:
    """The slope of log(corrected error) against log(n) at ``sigma`` (NaN with fewer than two
    points above rounding)."""
    rows = [p for p in points if p.sigma == sigma and p.status == "ok" and p.corrected_error > ROUNDING]
    if len(rows) < 2:
        return float("nan")
    return float(np.polyfit(np.log([p.n for p in rows]), np.log([p.corrected_error for p in rows]), 1)[0])


def markdown_table(points) -> str:
    """The points as a Markdown table, with the rate per sigma."""
    lines = [
        "| sigma | n | A1 of (9) | corrected impact model: error | (8): error | impacts | status |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for p in points:
        lines.append(
            f"| {p.sigma:g} | {p.n} | {p.smooth:.6f} | {p.corrected_error:.2e} | {p.paper_error:.2e} | "
            f"{p.impacts} | {p.status} |"
        )
    rates = ", ".join(
        f"sigma = {s:g}: n^{convergence_rate(points, s):.2f}" for s in dict.fromkeys(p.sigma for p in points)
    )
    return "\n".join(lines) + f"\n\nThe corrected impact model's error falls as {rates}.\n"


@dataclasses.dataclass(frozen=True)
class Simplifications:
    """A1 at one sigma of (9) and of the impact models with (flights, wall) each of the paper's or
    (9)'s own: ``paper`` (first-order, (21)), ``exact_flights`` (exact, (21)), ``measured_wall``
    (first-order, measured), ``corrected`` (exact, measured); NaN where the run did not repeat."""

    sigma: float
    smooth: float
    paper: float
    exact_flights: float
    measured_wall: float
    corrected: float


SETTLE_PERIODS = 400


def _settled_a1(flow: ImpactFlow, y0) -> float:
    """A1 of the orbit a run from y0 settles on (NaN when it does not repeat to 1e-8 after
    :data:`SETTLE_PERIODS` periods), by the trapezoid rule on samples every 0.01."""
    run = flow.run(
        np.asarray(y0, dtype=float), 0.0, 2 * np.pi * SETTLE_PERIODS, stick_speed=1e-9, max_impacts=10**7
    )
    if run[3] != 0:
        return float("nan")
    fine = ImpactFlow(flow.params, 0.01, variant=flow.variant, exact_flights=flow.exact_flights)
    t, y, _, code = fine.run(run[1][:, -1], 0.0, 2 * np.pi, stick_speed=1e-9, max_impacts=10**5)
    if code != 0 or np.abs(y[:, -1] - y[:, 0]).max() > 1e-8 * (1 + np.abs(y[:, 0]).max()):
        return float("nan")
    return first_harmonic(t, y[0])


def simplifications(params: Params, sigmas, state0=(0.0, 0.0, 0.0, 0.5)) -> list:
    """A :class:`Simplifications` per sigma: the runs start at (9)'s attracting orbit (the one a
    simulation from ``state0`` settles on), the particle moved inside the walls."""
    rows = []
    for sigma in (float(s) for s in sigmas):
        at = params.replace(sigma=sigma)
        orbit, smooth = settle_and_shoot(at, state0, first=150, every=50, most=400)
        y0 = np.array(orbit.y0, dtype=float)
        y0[2] = np.clip(y0[2], -0.95, 0.95)
        values = [
            _settled_a1(ImpactFlow(at, variant=variant, exact_flights=exact), y0)
            if np.isfinite(smooth)
            else np.nan
            for variant, exact in (
                ("paper", False),
                ("paper", True),
                ("corrected", False),
                ("corrected", True),
            )
        ]
        rows.append(Simplifications(sigma, float(smooth), *values))
    return rows


def simplifications_table(rows) -> str:
    """The rows as a Markdown table of the differences to (9), in percent."""

    def pct(value, ref):
        return f"{100 * (value - ref) / ref:+.2f} %" if np.isfinite(value) else "not settled"

    lines = [
        "| sigma | A1 of (9) | (8) | (8), exact flights | (8), measured wall | corrected impact model |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        cells = " | ".join(pct(v, r.smooth) for v in (r.paper, r.exact_flights, r.measured_wall, r.corrected))
        lines.append(f"| {r.sigma:g} | {r.smooth:.6f} | {cells} |")
    return "\n".join(lines) + "\n"
