"""A settled forced record in time, the vessel's displacement X(tau) on a steady 2pi-orbit, and
the orbit of the full model it is compared with: of the smooth model (9) or of the vibro-impact
model (8) (or of the corrected impact model), sampled at the record's own times.

Data: a CSV with ``tau`` and ``X`` (optionally ``std``), tau the forcing's phase of eq. (7) (the
excitation Abar cos tau at tau = 0, as the models have it), strictly increasing, the record
settled (a transient is fitted by the slow flow, :mod:`.time_series`). With a ``sigma`` column the
file holds a record at each of several forcing frequencies (the rows of one sigma, tau increasing
within them), fitted together (:class:`RecordOrbits`): one frequency's record hardly separates the
vessel's damping from the wall's, several do. The orbit a record follows
is found as a frequency response's point's would be (:func:`~.response_objective.orbit_response`
with the one point (sigma, A1), A1 the record's first harmonic); by (9) the record then takes, among
the stable orbits found there and the one a simulation from rest settles on, the one whose samples
explain the whole record best (two orbits can share A1 to 1e-8), by (8) the stable orbit whose A1
explains it best. At any later parameter set the orbit is Newton's from the last one, through intermediate
sets where Newton from the last misses, and a lost orbit is reported, never replaced.

The samples' derivatives in the parameters come from the models' own sensitivities, not from
differences of orbits. (9): the variational equations along the orbit, the start moving as
(M - I) dy0/dq = -s(2pi) (M the monodromy, s the sensitivity at a fixed start). (8): the saltation
sensitivities at every sample and impact (:meth:`~slosh_bif.flows.impact.flow.ImpactFlow.sensitivities`),
the section's state moving as (I - M) dx/dq = dP/dq, and from the last sample before a record's
time the flight's closed form expm(K s) (8 being linear between impacts) with its Frechet
derivative in the flight's parameters.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np

from slosh_bif.flows.impact.flow import ImpactFlow
from slosh_bif.flows.smooth import integrator
from slosh_bif.identify.csv_table import read_columns
from slosh_bif.identify.impact_samples import Flights
from slosh_bif.identify.response_data import ResponseData
from slosh_bif.identify.response_impact import STEP
from slosh_bif.identify.response_objective import orbit_response
from slosh_bif.identify.response_orbits import LostOrbit
from slosh_bif.model.params import REAL_FIELDS, Params

__all__ = ["SteadyRecord", "read_steady_record", "RecordOrbit", "RecordOrbits", "MIN_PHASES", "STEP_SIZE"]

MIN_PHASES = 8  # distinct phases (mod 2pi) a record needs: the orbit's shape, not a few points
STEP_SIZE = 0.05  # the largest relative move of a parameter between two sets an orbit is followed over
MAX_STEPS = 40  # sets in between at most (a move from near 0 is relative to where it goes)
TOL = 1e-10  # the integration's tolerance for (9)'s samples


@dataclasses.dataclass(frozen=True)
class SteadyRecord:
    """A settled record: times ``tau`` (the forcing's phase), displacements ``X``, optional ``std``
    of each, the file they came from, and where the file holds records at several forcing
    frequencies, each sample's ``sigmas``."""

    tau: np.ndarray
    X: np.ndarray
    std: np.ndarray | None = None
    source: str = ""
    sigmas: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.tau)

    @property
    def A(self) -> np.ndarray:
        """The measured values (the name the fits' shared code reads)."""
        return self.X

    def first_harmonic(self) -> float:
        """A1 of the record: the amplitude of the least-squares fit of c0 + a cos tau + b sin tau."""
        basis = np.column_stack([np.ones(len(self)), np.cos(self.tau), np.sin(self.tau)])
        (_, a, b), *_ = np.linalg.lstsq(basis, self.X, rcond=None)
        return float(math.hypot(a, b))

    def parts(self, sigma: float) -> list:
        """(sigma, rows) of each record: the one at ``sigma`` where the samples carry no sigma, else
        one per sigma in the order the file has them."""
        if self.sigmas is None:
            return [(float(sigma), np.arange(len(self)))]
        return [(s, np.flatnonzero(self.sigmas == s)) for s in dict.fromkeys(self.sigmas.tolist())]

    def subset(self, rows) -> SteadyRecord:
        """The record of the samples ``rows`` (one frequency's)."""
        std = None if self.std is None else self.std[rows]
        return SteadyRecord(self.tau[rows], self.X[rows], std, self.source)


def read_steady_record(path) -> SteadyRecord:
    """``tau, X[, std, sigma]``; one-line errors naming the file, line and column: tau strictly
    increasing (within each sigma's rows), at least :data:`MIN_PHASES` distinct phases modulo 2pi
    in each record, std positive."""
    path = Path(path)
    values = read_columns(path, ("tau", "X"), "a settled forced record", optional=("std", "sigma"))
    record = SteadyRecord(values["tau"], values["X"], values.get("std"), str(path), values.get("sigma"))
    sigmas = record.sigmas
    for sigma, part in record.parts(0.0):
        where = f" at sigma = {sigma:g}" if sigmas is not None else ""
        tau = record.tau[part]
        if len(tau) < 2 or np.any(np.diff(tau) <= 0):
            raise ValueError(f"{path}: tau must increase strictly over the rows{where}")
        phases = np.unique(np.mod(np.round(np.mod(tau, 2 * np.pi), 9), round(2 * np.pi, 9)))  # 0 is 2pi
        if len(phases) < MIN_PHASES:
            raise ValueError(
                f"{path}: {len(phases)} distinct phases of tau modulo 2pi{where}; a settled record needs "
                f"at least {MIN_PHASES} over the forcing period to show the orbit's shape"
            )
    return record


class RecordOrbit:
    """The 2pi-orbit of ``model`` ("smooth": (9); "impact": (8); "impact-corrected") a settled
    ``record`` follows, found at ``params`` and followed to any set near it (:meth:`samples`)."""

    def __init__(self, record: SteadyRecord, params: Params, model: str = "smooth", progress=None):
        if model not in ("smooth", "impact", "impact-corrected"):
            raise ValueError(
                f"a settled record is compared with an orbit model (smooth, impact); got {model!r}"
            )
        self.record, self.model = record, model
        point = ResponseData(
            np.array([params.sigma]), np.array([record.first_harmonic()]), source=record.source
        )
        self.orbits = orbit_response(point, params, model, progress)
        self.phases = np.mod(record.tau, 2 * np.pi)
        self._choose_by_shape()

    @property
    def params(self) -> Params:
        """The parameter set the orbit is at."""
        return self.orbits.params

    @property
    def stable(self) -> bool:
        return bool(self.orbits.stable[0])

    @property
    def candidates(self) -> list:
        """(A1, stable) of every orbit found where the record's orbit was chosen."""
        return list(self.orbits.candidates[0])

    def differentiates(self, names) -> bool:
        """Whether :meth:`gradient` has every name (the corrected impact model has no derivatives
        in the wall's lam and chi)."""
        if self.model == "smooth":
            return all(name in REAL_FIELDS for name in names)
        return self.orbits.differentiates(names)

    def state(self):
        return self.orbits.state(), self.orbits.params

    def restore(self, state) -> None:
        self.orbits.restore(state[0])
        self.orbits.params = state[1]

    def samples(self, params: Params) -> np.ndarray:
        """X of the orbit at ``params`` at the record's times; :class:`LostOrbit` where it is lost."""
        self._move(params)
        return self.at_phases(self.phases)[0]

    def gradient(self, names) -> np.ndarray:
        """dX/d(``names``) at the record's times, shape (samples, len(names)), at the set of the
        last :meth:`samples` call, the orbit moving with the parameters."""
        return self.at_phases(self.phases, names)[1]

    def at_phases(self, phases, names=(), orbit=None) -> tuple:
        """(X, dX/d names) of the orbit (``orbit``: another found at the same set, as the orbit
        response lists it) at ``phases`` (any reals: taken modulo 2pi)."""
        phases = np.mod(np.asarray(phases, dtype=float), 2 * np.pi)
        if self.model == "smooth":
            x = self.orbits.x[0] if orbit is None else orbit[0]
            return _smooth_samples(self.orbits.params, x[:4], phases, names)
        variant = "corrected" if self.model == "impact-corrected" else "paper"
        section, x = (self.orbits.phase[0], self.orbits.x[0]) if orbit is None else orbit[:2]
        return _impact_samples(self.orbits.params, section, x, phases, names, variant)

    def _choose_by_shape(self) -> None:
        """The orbit the record follows, among every stable one found at its sigma and the one a
        simulation from rest settles on: the one whose samples explain the whole record best, not
        its first harmonic alone (at sigma = 0.5 of a set with n = 20 two stable orbits of (9)
        have the same A1 to 1e-8, the particle moving differently, the vessel's motion differing
        by 4e-3: mirror twins, of which the search at a set may find either)."""
        found = [f for f in self.orbits.found[0] + self.orbits.settled_from_rest(0) if f[-1]]
        if not found:
            return
        if self.model == "smooth":  # each one's mirror twin: which of a pair a search finds is rounding
            found += [m for m in (self.orbits.mirrored(0, f) for f in found) if m is not None and m[-1]]
        scale = self.record.std if self.record.std is not None else 1.0

        def misfit(f):
            return float(np.sum(((self.record.X - self.at_phases(self.phases, (), f)[0]) / scale) ** 2))

        best = min(found, key=misfit)
        if self.model == "smooth":
            self.orbits.x[0] = best[0]
        else:
            self.orbits.phase[0], self.orbits.x[0] = best[0], best[1]
        self.orbits.stable[0] = True

    def _move(self, params: Params) -> None:
        """Follow the orbit to ``params``: Newton from the last set, else through sets in between
        that move no parameter by more than STEP_SIZE of its larger end (at most MAX_STEPS of them); on
        a loss the orbit stays."""
        home = self.state()
        last = self.orbits.params
        try:
            self.orbits.amplitudes(params)
            return
        except LostOrbit:
            self.restore(home)
        a, b = last.as_dict(), params.as_dict()
        moved = {k: (a[k], b[k]) for k in REAL_FIELDS if a[k] != b[k]}
        size = max((abs(v1 - v0) / max(abs(v0), abs(v1)) for v0, v1 in moved.values()), default=0.0)
        steps = min(MAX_STEPS, max(2, math.ceil(size / STEP_SIZE)))
        try:
            for w in np.linspace(0.0, 1.0, steps + 1)[1:]:
                self.orbits.amplitudes(
                    last.replace(**{k: v0 + w * (v1 - v0) for k, (v0, v1) in moved.items()})
                )
        except LostOrbit:
            self.restore(home)
            raise


def _grid(phases) -> tuple:
    """(times from 0 to 2pi through every phase, each phase's index in them)."""
    grid = np.unique(np.concatenate([[0.0, 2 * np.pi], phases]))
    return grid, np.searchsorted(grid, phases)


def _smooth_samples(params: Params, y0, phases, names) -> tuple:
    """(X, dX) of (9)'s 2pi-orbit through y0 at ``phases``: one integration of (9) for X, one of
    its variational equations per two names for dX."""
    grid, index = _grid(phases)
    X = integrator.integrate_grid(params, y0, grid, rtol=TOL, atol=TOL * 1e-2)[index, 0]
    rows = [[1.0 if field == name else 0.0 for field in REAL_FIELDS] for name in names]
    if len(rows) % 2:
        rows.append([0.0] * len(REAL_FIELDS))  # the pair kernel takes two directions at a time
    columns = []
    for k in range(0, len(rows), 2):
        z = integrator.integrate_grid(params, y0, grid, rtol=TOL, atol=TOL * 1e-2, directions=rows[k : k + 2])
        Phi = z[:, 4:20].reshape(-1, 4, 4)
        S = z[:, 20:28].reshape(-1, 2, 4).transpose(0, 2, 1)  # (time, component, direction)
        lhs = Phi[-1] - np.eye(4)
        if np.linalg.cond(lhs) > 1e12:
            raise LostOrbit("the orbit's monodromy has a multiplier 1 (a fold): X has no derivative there")
        dy0 = np.linalg.solve(lhs, -S[-1])
        columns.append(Phi[index, 0, :] @ dy0 + S[index, 0, :])
    dX = np.concatenate(columns, axis=1)[:, : len(names)] if columns else np.zeros((len(phases), 0))
    return X, dX


def _impact_samples(params: Params, section: float, x, phases, names, variant: str) -> tuple:
    """(X, dX) of the impact model's 2pi-orbit through x on the section at phase ``section``, at
    ``phases``: from the last sample (or impact) before each, the flight's closed form."""
    times = section + np.mod(phases - section, 2 * np.pi)  # in [section, section + 2pi)
    X, columns = None, []
    for name in [None, *names]:
        flow = ImpactFlow(params, STEP, param=name, variant=variant)
        t, y, phis, dps, _, code = flow.sensitivities(np.asarray(x, dtype=float), section, 2 * np.pi)
        if code != 0:
            raise LostOrbit(f"the orbit at sigma = {params.sigma:.4g} ends early (code {code})")
        at = Flights(flow, t, y, times)
        if name is None:
            X = at.X()
            continue
        dx = np.linalg.solve(np.eye(4) - phis[-1], dps[-1])
        columns.append(at.derivative(np.einsum("nij,j->ni", phis[at.last], dx) + dps[at.last]))
    dX = np.column_stack(columns) if columns else np.zeros((len(times), 0))
    return X, dX


class RecordOrbits:
    """The orbits of every record in ``record`` (one per sigma where the samples carry one, else the
    one at ``params``'s sigma), each the :class:`RecordOrbit` its record follows, moved together:
    :meth:`samples` and :meth:`gradient` over all samples in the file's order."""

    def __init__(self, record: SteadyRecord, params: Params, model: str = "smooth", progress=None):
        self.parts = record.parts(params.sigma)
        self.size = len(record)
        self.members = [
            RecordOrbit(record.subset(rows), params.replace(sigma=sigma), model, progress)
            for sigma, rows in self.parts
        ]

    @property
    def sigmas(self) -> list:
        return [sigma for sigma, _ in self.parts]

    @property
    def stable(self) -> bool:
        return all(member.stable for member in self.members)

    @property
    def unstable(self) -> list:
        """The sigmas whose record's orbit is unstable."""
        return [sigma for sigma, member in zip(self.sigmas, self.members) if not member.stable]

    @property
    def candidates(self) -> list:
        """(sigma, A1, stable) of every orbit found where each record's orbit was chosen."""
        return [
            (sigma, *candidate)
            for sigma, member in zip(self.sigmas, self.members)
            for candidate in member.candidates
        ]

    def differentiates(self, names) -> bool:
        return all(member.differentiates(names) for member in self.members)

    def state(self) -> list:
        return [member.state() for member in self.members]

    def restore(self, state) -> None:
        for member, saved in zip(self.members, state):
            member.restore(saved)

    def samples(self, params: Params) -> np.ndarray:
        """X of every record's orbit at ``params`` (each at its own sigma); :class:`LostOrbit` where
        one is lost, every orbit left where it was."""
        home, X = self.state(), np.empty(self.size)
        try:
            for (sigma, rows), member in zip(self.parts, self.members):
                X[rows] = member.samples(params.replace(sigma=sigma))
        except (ValueError, RuntimeError):  # lost, or outside the admissible set: none moved
            self.restore(home)
            raise
        return X

    def gradient(self, names) -> np.ndarray:
        """dX/d(``names``) at every sample, at the set of the last :meth:`samples` call."""
        G = np.empty((self.size, len(names)))
        for (_, rows), member in zip(self.parts, self.members):
            G[rows] = member.gradient(names)
        return G

    def curves(self, phases) -> list:
        """Each record's orbit over ``phases``: {sigma, phase, X, stable}."""
        return [
            {
                "sigma": sigma,
                "phase": list(map(float, phases)),
                "X": member.at_phases(phases)[0].tolist(),
                "stable": member.stable,
            }
            for sigma, member in zip(self.sigmas, self.members)
        ]
